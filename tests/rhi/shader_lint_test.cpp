// Implicit derivatives after a discard (shaders/include/janus/shaders/derivative_lint.h): none in
// any shader we ship, and the check finds each way one can hide, or that first test proves nothing.
// Mesa keeps discarded lanes as helpers, so no image rendered here shows the bug; NVIDIA's GL
// driver does not (issue 10: alpha-masked labels sampled mip 0 at their edges).
#include <gtest/gtest.h>

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "janus/shaders/derivative_lint.h"
#include "janus/shaders/shaders.h"

namespace janus::shaders {
namespace {

std::string joined(const std::vector<std::string>& lines) {
    std::string text;
    for (const std::string& line : lines) text += line + "\n";
    return text;
}

TEST(DerivativeLint, NoShaderTakesImplicitDerivativesAfterADiscard) {
    size_t checked = 0;
    for (const Entry& entry : all()) {
        EXPECT_EQ(joined(derivativesAfterDiscard(entry.spirv)), "") << entry.name;
        ++checked;
    }
    EXPECT_GT(checked, 0u);
}

// GLSL 450 fragment shader -> SPIR-V for Vulkan 1.2, as the build's glslangValidator -V makes it
// (no inlining, so calls stay calls).
std::vector<uint32_t> compileFragment(const std::string& body) {
    static const bool initialised = glslang::InitializeProcess();
    (void)initialised;
    const std::string source = "#version 450\n"
                               "layout(location = 0) in vec2 uv;\n"
                               "layout(location = 1) in float cut;\n"
                               "layout(location = 0) out vec4 color;\n"
                               "layout(set = 0, binding = 0) uniform sampler2D labels;\n"
                               "layout(set = 0, binding = 1) uniform sampler2D emission;\n" +
                               body;
    glslang::TShader shader(EShLangFragment);
    const char* text = source.c_str();
    shader.setStrings(&text, 1);
    shader.setEnvInput(glslang::EShSourceGlsl, EShLangFragment, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_5);
    if (!shader.parse(GetDefaultResources(), 450, false, EShMsgDefault))
        throw std::runtime_error(std::string("glslang: ") + shader.getInfoLog() + "\n" + source);
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(EShMsgDefault)) throw std::runtime_error(std::string("glslang link: ") + program.getInfoLog());
    std::vector<uint32_t> spirv;
    glslang::GlslangToSpv(*program.getIntermediate(EShLangFragment), spirv);
    return spirv;
}

std::vector<std::string> findings(const std::string& body) { return derivativesAfterDiscard(compileFragment(body)); }

TEST(DerivativeLint, FindsALookupAfterADiscardAndNamesIt) {
    // The shape forward.frag had: the base colour's alpha test, then the emissive lookup.
    const std::vector<std::string> found = findings(R"(
void main() {
    vec4 base = texture(labels, uv);
    if (base.a < cut) discard;
    color = base + texture(emission, uv);
})");
    ASSERT_EQ(found.size(), 1u) << joined(found);
    EXPECT_NE(found[0].find("implicit-LOD texture lookup of 'emission'"), std::string::npos) << found[0];
    EXPECT_NE(found[0].find("after a discard in 'main'"), std::string::npos) << found[0];
    EXPECT_NE(found[0].find("textureLod"), std::string::npos) << found[0];
}

TEST(DerivativeLint, AcceptsLookupsBeforeTheDiscardAndExplicitLodsAfterIt) {
    EXPECT_EQ(joined(findings(R"(
void main() {
    vec4 base = texture(labels, uv);
    vec4 glow = texture(emission, uv);
    vec2 slope = dFdx(uv);
    if (base.a < cut) discard;
    color = base + glow + textureLod(emission, uv, 2.0) + textureGrad(labels, uv, slope, slope);
})")),
              "");
}

TEST(DerivativeLint, FindsDerivativesAndLodQueriesAfterADiscard) {
    const std::vector<std::string> found = findings(R"(
void main() {
    if (cut > 0.5) discard;
    color = vec4(dFdx(uv), fwidth(uv).x, textureQueryLod(labels, uv).x);
})");
    ASSERT_EQ(found.size(), 3u) << joined(found);
    EXPECT_NE(found[0].find("a derivative (dFdx/dFdy/fwidth)"), std::string::npos) << found[0];
    EXPECT_NE(joined(found).find("level-of-detail query of 'labels'"), std::string::npos) << joined(found);
}

TEST(DerivativeLint, FindsALookupInAFunctionCalledAfterADiscard) {
    const std::vector<std::string> found = findings(R"(
vec4 glow(vec2 at) { return texture(emission, at); }
void main() {
    if (cut > 0.5) discard;
    color = glow(uv);
})");
    ASSERT_EQ(found.size(), 1u) << joined(found);
    EXPECT_NE(found[0].find("of 'emission' (in 'glow')"), std::string::npos) << found[0];
}

TEST(DerivativeLint, FindsALookupAfterAFunctionThatDiscards) {
    const std::vector<std::string> found = findings(R"(
void alphaTest(float alpha) { if (alpha < cut) discard; }
void main() {
    vec4 base = texture(labels, uv);
    alphaTest(base.a);
    color = base * texture(emission, uv);
})");
    ASSERT_EQ(found.size(), 1u) << joined(found);
    EXPECT_NE(found[0].find("after a call to 'alphaTest', which may discard"), std::string::npos) << found[0];
}

TEST(DerivativeLint, FindsALookupBeforeADiscardInTheSameLoop) {
    // The second iteration's lookup comes after the first iteration's discard.
    const std::vector<std::string> found = findings(R"(
void main() {
    vec4 sum = vec4(0.0);
    for (int i = 0; i < 4; ++i) {
        vec4 layer = texture(labels, uv + vec2(float(i)));
        if (layer.a < cut) discard;
        sum += layer;
    }
    color = sum;
})");
    ASSERT_EQ(found.size(), 1u) << joined(found);
    EXPECT_NE(found[0].find("of 'labels'"), std::string::npos) << found[0];
}

TEST(DerivativeLint, DemoteKeepsDerivativesDefined) {
    // demote (SPV_EXT_demote_to_helper_invocation) leaves the lane running as a helper.
    EXPECT_EQ(joined(findings(R"(
#extension GL_EXT_demote_to_helper_invocation : require
void main() {
    vec4 base = texture(labels, uv);
    if (base.a < cut) demote;
    color = base * texture(emission, uv);
})")),
              "");
}

TEST(DerivativeLint, RefusesWhatIsNotSpirv) {
    const std::vector<uint32_t> text = {0x6c736c67, 0, 0, 0, 0};
    EXPECT_THROW(derivativesAfterDiscard(text), std::invalid_argument);
    std::vector<uint32_t> truncated = compileFragment("void main() { color = texture(labels, uv); }");
    truncated.back() = 0xFFFF0000u | truncated.back();   // a word count past the end
    EXPECT_THROW(derivativesAfterDiscard(truncated), std::invalid_argument);
}

}  // namespace
}  // namespace janus::shaders
