// What the GL backend's SPIR-V -> GLSL translation (rhi-gl/src/gl_shader_translation.h) adds for
// every vertex shader, checked on the translated text.
#include <gtest/gtest.h>

#include <string>

#include "gl_shader_translation.h"
#include "janus/shaders/shaders.h"

namespace janus::rhi::gl {
namespace {

// The renderer's depth prepass and forward pass link forward.vert into two GL programs and compare
// depths with LessOrEqual: only `invariant` makes a GL driver compute gl_Position identically in both.
TEST(GlShaderTranslation, VertexShadersDeclareAnInvariantPosition) {
    ShaderDesc desc;
    desc.setStage(ShaderStage::Vertex).setSpirv(shaders::get("forward_vert"));
    for (const bool es : {false, true})
        for (const bool zeroToOne : {false, true}) {
            const std::string source = translateToGlsl(desc, GlslTarget{es, zeroToOne}).source;
            EXPECT_NE(source.find("invariant gl_Position;"), std::string::npos) << (es ? "ESSL" : "GLSL") << ":\n" << source;
        }
    ShaderDesc fragment;
    fragment.setStage(ShaderStage::Fragment).setSpirv(shaders::get("depth_prepass_frag"));
    EXPECT_EQ(translateToGlsl(fragment, GlslTarget{}).source.find("invariant"), std::string::npos);
}

}  // namespace
}  // namespace janus::rhi::gl
