// Implicit derivatives after a discard or in divergent control flow
// (rhi/backend-api/janus/rhi/derivative_lint.h): none in any shader we ship, and the checks
// find each way one can hide, and keep quiet where the quad is whole, or that first test proves
// nothing.
// Mesa keeps discarded lanes as helpers, so no image rendered here shows the bug; NVIDIA's GL
// driver does not (issue 10: alpha-masked labels sampled mip 0 at their edges).
#include <gtest/gtest.h>

#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "glslang_compile.h"
#include "janus/rhi/derivative_lint.h"
#include "janus/shaders/shaders.h"

namespace janus::rhi {
namespace {

using shaders::all;
using shaders::Entry;

std::string joined(const std::vector<std::string>& lines) {
    std::string text;
    for (const std::string& line : lines) text += line + "\n";
    return text;
}

TEST(DerivativeLint, NoShaderTakesImplicitDerivativesWhereTheQuadMayBeIncomplete) {
    size_t checked = 0;
    for (const Entry& entry : all()) {
        EXPECT_EQ(joined(derivativeHazards(entry.spirv)), "") << entry.name;
        ++checked;
    }
    EXPECT_GT(checked, 0u);
}

// A fragment shader with the inputs and resources the cases below use, compiled by glslang.
std::vector<uint32_t> compileFragment(const std::string& body) {
    return test::compileGlsl("#version 450\n"
                             "layout(location = 0) in vec2 uv;\n"
                             "layout(location = 1) in float cut;\n"
                             "layout(location = 2) flat in int layer;\n"
                             "layout(set = 0, binding = 2) uniform Settings { float threshold; int count; } settings;\n"
                             "layout(location = 0) out vec4 color;\n"
                             "layout(set = 0, binding = 0) uniform sampler2D labels;\n"
                             "layout(set = 0, binding = 1) uniform sampler2D emission;\n" +
                                 body,
                             ShaderStage::Fragment);
}

std::vector<std::string> findings(const std::string& body) { return derivativesAfterDiscard(compileFragment(body)); }
std::vector<std::string> divergent(const std::string& body) { return derivativesInDivergentFlow(compileFragment(body)); }

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

TEST(DerivativeLint, NamesTheSourceLineWhenTheModuleHasDebugInfo) {
    const std::string source = "#version 450\n"                                            // line 1
                               "layout(location = 0) in vec2 uv;\n"                         // 2
                               "layout(location = 0) out vec4 color;\n"                     // 3
                               "layout(set = 0, binding = 0) uniform sampler2D labels;\n"   // 4
                               "layout(set = 0, binding = 1) uniform sampler2D emission;\n" // 5
                               "void main() {\n"                                            // 6
                               "    vec4 base = texture(labels, uv);\n"                     // 7
                               "    if (base.a < 0.5) discard;\n"                           // 8
                               "    color = base + texture(emission, uv);\n"                // 9
                               "}\n";
    const std::vector<std::string> found =
        derivativesAfterDiscard(test::compileGlsl(source, ShaderStage::Fragment, "labels.frag"));
    ASSERT_EQ(found.size(), 1u) << joined(found);
    EXPECT_NE(found[0].find("implicit-LOD texture lookup of 'emission' at labels.frag:9 in 'main'"), std::string::npos) << found[0];
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

TEST(DerivativeLint, FindsALookupInABranchOnAPerFragmentValue) {
    // The shape forward.frag's normal map had: sampled only where the tangent frame exists.
    const std::vector<std::string> found = divergent(R"(
void main() {
    color = vec4(0.0);
    if (uv.x > 0.5) color = texture(labels, uv);
})");
    ASSERT_EQ(found.size(), 1u) << joined(found);
    EXPECT_NE(found[0].find("implicit-LOD texture lookup of 'labels' in 'main' runs where a branch on a per-fragment value"),
              std::string::npos)
        << found[0];
    EXPECT_EQ(joined(findings(R"(
void main() {
    color = vec4(0.0);
    if (uv.x > 0.5) color = texture(labels, uv);
})")),
              "")
        << "no discard: the other check has nothing to say";
}

TEST(DerivativeLint, BranchesEveryFragmentOfAQuadTakesAlikeAreFine) {
    // Uniform-buffer values, flat inputs and gl_FrontFacing are the same in all four fragments.
    EXPECT_EQ(joined(divergent(R"(
void main() {
    color = vec4(0.0);
    if (settings.threshold > 0.5) color += texture(labels, uv);
    if (layer == 2) color += texture(emission, uv);
    if (gl_FrontFacing) color += vec4(dFdx(uv), 0.0, 0.0);
    for (int i = 0; i < settings.count; ++i) color += texture(labels, uv + vec2(float(i)));
})")),
              "");
}

TEST(DerivativeLint, FindsDerivativesInLoopsAndAfterTheLanesThatLeft) {
    // A trip count from a varying value.
    EXPECT_EQ(divergent(R"(
void main() {
    color = vec4(0.0);
    for (int i = 0; i < int(uv.x * 8.0); ++i) color += texture(labels, uv + vec2(float(i)));
})").size(),
              1u);
    // After a loop whose lanes all meet again at its end: fine.
    EXPECT_EQ(joined(divergent(R"(
void main() {
    float sum = 0.0;
    for (int i = 0; i < int(uv.x * 8.0); ++i) sum += 1.0;
    color = texture(labels, uv) * sum;
})")),
              "");
    // After a varying break, the rest of the loop runs without the lanes that left.
    EXPECT_EQ(divergent(R"(
void main() {
    color = vec4(0.0);
    for (int i = 0; i < 4; ++i) {
        if (uv.x > float(i) * 0.25) break;
        color += texture(labels, uv);
    }
})").size(),
              1u);
    // After a varying early return, the rest of the function runs without them.
    EXPECT_EQ(divergent(R"(
void main() {
    color = vec4(0.0);
    if (uv.y > 0.5) return;
    color = texture(emission, uv);
})").size(),
              1u);
}

TEST(DerivativeLint, FollowsVaryingValuesThroughVariablesAndCalls) {
    // A flag set in a varying branch varies, and so does the branch on it.
    EXPECT_EQ(divergent(R"(
void main() {
    bool near = false;
    if (uv.x > 0.5) near = true;
    color = vec4(0.0);
    if (near) color = texture(labels, uv);
})").size(),
              1u);
    // A lookup inside a function called from a varying branch.
    const std::vector<std::string> found = divergent(R"(
vec4 glow(vec2 at) { return texture(emission, at); }
void main() {
    color = vec4(0.0);
    if (uv.x > 0.5) color = glow(uv);
})");
    ASSERT_EQ(found.size(), 1u) << joined(found);
    EXPECT_NE(found[0].find("of 'emission' (in 'glow') in 'main'"), std::string::npos) << found[0];
    // Explicit LODs and gradients taken outside are fine anywhere.
    EXPECT_EQ(joined(divergent(R"(
void main() {
    vec2 dx = dFdx(uv), dy = dFdy(uv);
    color = vec4(0.0);
    if (uv.x > 0.5) color = textureLod(labels, uv, 1.0) + textureGrad(emission, uv, dx, dy);
})")),
              "");
}

TEST(DerivativeLint, FollowsCallsByWhatTheyAreGiven) {
    // A helper of a uniform value returns a uniform value.
    EXPECT_EQ(joined(divergent(R"(
float doubled(float x) { return x * 2.0; }
void main() {
    color = vec4(0.0);
    if (doubled(settings.threshold) > 0.5) color = texture(labels, uv);
})")),
              "");
    // Given a varying value, or reading an input itself, it returns a varying one.
    EXPECT_EQ(divergent(R"(
float doubled(float x) { return x * 2.0; }
void main() {
    color = vec4(0.0);
    if (doubled(uv.x) > 0.5) color = texture(labels, uv);
})").size(),
              1u);
    EXPECT_EQ(divergent(R"(
float edge() { return uv.x; }
void main() {
    color = vec4(0.0);
    if (edge() > 0.5) color = texture(labels, uv);
})").size(),
              1u);
    // An out parameter holds what the function stored: varying or not.
    auto branchOnOutParameterStoredFrom = [](const std::string& value) {
        return divergent("void pick(out float v) { v = " + value + "; }\n" + R"(
void main() {
    float v;
    pick(v);
    color = vec4(0.0);
    if (v > 0.5) color = texture(labels, uv);
})");
    };
    EXPECT_EQ(branchOnOutParameterStoredFrom("uv.x").size(), 1u);
    EXPECT_EQ(joined(branchOnOutParameterStoredFrom("settings.threshold")), "");
}

TEST(DerivativeLint, RefusesWhatIsNotSpirv) {
    const std::vector<uint32_t> text = {0x6c736c67, 0, 0, 0, 0};
    EXPECT_THROW(derivativesAfterDiscard(text), std::invalid_argument);
    EXPECT_THROW(derivativesInDivergentFlow(text), std::invalid_argument);
    std::vector<uint32_t> truncated = compileFragment("void main() { color = texture(labels, uv); }");
    truncated.back() = 0xFFFF0000u | truncated.back();   // a word count past the end
    EXPECT_THROW(derivativesAfterDiscard(truncated), std::invalid_argument);
}

// Corrupt modules (one word replaced, or cut short) end in a result or an exception, never a
// crash or a hang: with validation on, the lint sees whatever SPIR-V a user passes createShader.
TEST(DerivativeLint, SurvivesCorruptedModules) {
    const std::span<const uint32_t> original = shaders::get("forward_frag");
    std::mt19937 random(17);
    for (int trial = 0; trial < 400; ++trial) {
        std::vector<uint32_t> module(original.begin(), original.end());
        if (trial % 4 == 3) {
            module.resize(5 + random() % (module.size() - 5));
        } else {
            const size_t at = 5 + random() % (module.size() - 5);
            module[at] = trial % 2 ? uint32_t(random()) : (module[at] & 0xFFFF0000u) | uint32_t(random() % 400);
        }
        try {
            (void)derivativeHazards(module);
        } catch (const std::exception&) {
        }
    }
}

}  // namespace
}  // namespace janus::rhi
