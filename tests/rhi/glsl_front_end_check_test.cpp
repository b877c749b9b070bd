// The build-time GL shader check's front end (rhi-gl/tools/glsl_front_end_check.h): glslang must
// accept what a GL driver accepts and reject what it must reject, or the check proves nothing.
// The check itself runs over every shader during the build (target janus_gl_shader_check).
#include <gtest/gtest.h>

#include <string>

#include "glsl_front_end_check.h"

namespace janus::rhi::gl {
namespace {

TEST(GlslFrontEndCheck, AcceptsValidGlsl430AndEssl300) {
    const std::string compute = R"(#version 430
layout(local_size_x = 8) in;
layout(binding = 0, std430) buffer Values { float values[]; } data;
void main() { data.values[gl_GlobalInvocationID.x] *= 2.0; }
)";
    EXPECT_EQ(glslangRejection(compute, ShaderStage::Compute), "");
    const std::string fragment = R"(#version 300 es
precision highp float;
layout(location = 0) out vec4 color;
uniform sampler2D image;
void main() { color = texture(image, vec2(0.5)); }
)";
    EXPECT_EQ(glslangRejection(fragment, ShaderStage::Fragment), "");
}

TEST(GlslFrontEndCheck, RejectsWhatEssl300Forbids) {
    // ESSL has no implicit int -> uint conversion (GLSL 430 has).
    const std::string conversion = R"(#version 300 es
precision highp float;
layout(location = 0) out vec4 color;
void main() { uint count = 1; color = vec4(float(count)); }
)";
    const std::string log = glslangRejection(conversion, ShaderStage::Fragment);
    EXPECT_NE(log.find("ERROR"), std::string::npos) << log;
    EXPECT_NE(log.find("cannot convert"), std::string::npos) << log;
    // Compute shaders do not exist in ESSL 300.
    EXPECT_NE(glslangRejection("#version 300 es\nlayout(local_size_x = 1) in;\nvoid main() {}\n", ShaderStage::Compute), "");
}

TEST(GlslFrontEndCheck, RejectsAShaderThatDoesNotLink) {
    const std::string log = glslangRejection("#version 430\nvoid notMain() {}\n", ShaderStage::Vertex);
    EXPECT_NE(log.find("Missing entry point"), std::string::npos) << log;
}

// A shader at the limits links; one texture or one uniform block more is refused, naming the limit
// (the renderer's forward shader samples 15 textures: its next feature's texture must fit).
TEST(GlslFrontEndCheck, RejectsMoreTexturesOrUniformBlocksPerStageThanTheMinimums) {
    auto fragment = [](int textures, int blocks) {
        std::string source = "#version 300 es\nprecision highp float;\nlayout(location = 0) out vec4 color;\n";
        for (int i = 0; i < textures; ++i) source += "uniform highp sampler2D t" + std::to_string(i) + ";\n";
        for (int i = 0; i < blocks; ++i) source += "layout(std140) uniform B" + std::to_string(i) + " { vec4 v; } b" + std::to_string(i) + ";\n";
        source += "void main() {\n    color = vec4(0.0);\n";
        for (int i = 0; i < textures; ++i) source += "    color += texture(t" + std::to_string(i) + ", vec2(0.5));\n";
        for (int i = 0; i < blocks; ++i) source += "    color += b" + std::to_string(i) + ".v;\n";
        return source + "}\n";
    };
    EXPECT_EQ(glslangRejection(fragment(kMinTextureUnitsPerStage, kMinUniformBlocksPerStage), ShaderStage::Fragment), "");
    const std::string textures = glslangRejection(fragment(kMinTextureUnitsPerStage + 1, 1), ShaderStage::Fragment);
    EXPECT_NE(textures.find("samples 17 textures"), std::string::npos) << textures;
    EXPECT_NE(textures.find("GL_MAX_TEXTURE_IMAGE_UNITS"), std::string::npos) << textures;
    const std::string blocks = glslangRejection(fragment(1, kMinUniformBlocksPerStage + 1), ShaderStage::Fragment);
    EXPECT_NE(blocks.find("reads 13 uniform blocks"), std::string::npos) << blocks;
}

}  // namespace
}  // namespace janus::rhi::gl
