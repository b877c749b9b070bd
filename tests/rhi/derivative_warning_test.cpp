// With validation on, createShader says when a fragment shader takes implicit derivatives where
// the quad may be incomplete (rhi/backend-api/janus/rhi/derivative_lint.h): one Warning per
// finding, the same text on every backend, through takeDebugMessages() and the callback. Mesa
// renders such shaders as intended, so without this a user learns of it on another driver.
#include "backend_test.h"
#include "glslang_compile.h"

namespace janus::rhi::test {
namespace {

const std::string kHeader = "#version 450\n"
                            "layout(location = 0) in vec2 uv;\n"
                            "layout(location = 0) out vec4 color;\n"
                            "layout(set = 0, binding = 0) uniform sampler2D labels;\n"
                            "layout(set = 0, binding = 1) uniform sampler2D emission;\n";
// The shape forward.frag had before issue 10's fix: the emissive lookup after the alpha test.
const std::string kSampledAfterDiscard = kHeader + R"(
void main() {
    vec4 base = texture(labels, uv);
    if (base.a < 0.5) discard;
    color = base + texture(emission, uv);
})";
const std::string kSampledFirst = kHeader + R"(
void main() {
    vec4 base = texture(labels, uv);
    vec4 glow = texture(emission, uv);
    if (base.a < 0.5) discard;
    color = base + glow;
})";

ShaderDesc fragment(const std::string& source, const std::string& name) {
    return ShaderDesc().setStage(ShaderStage::Fragment).setSpirv(compileGlsl(source, ShaderStage::Fragment)).setDebugName(name);
}

class DerivativeWarningTest : public BackendTest {
protected:
    void customizeDeviceDesc(DeviceDesc& desc) override {
        desc.messageCallback = [this](const DebugMessage& m) { received.push_back(m); };
    }
    std::vector<DebugMessage> received;
};
JANUS_INSTANTIATE_BACKEND_TESTS(DerivativeWarningTest);

TEST_P(DerivativeWarningTest, ALookupAfterADiscardIsAWarningNamingTheShader) {
    ShaderHandle shader = device().createShader(fragment(kSampledAfterDiscard, "labels"));
    EXPECT_NE(shader, nullptr) << "a warning, not a refusal";
    const std::vector<DebugMessage> messages = device().takeDebugMessages();
    ASSERT_EQ(messages.size(), 1u);
    EXPECT_EQ(messages[0].severity, MessageSeverity::Warning);
    EXPECT_EQ(messages[0].text.rfind("createShader: fragment shader 'labels': an implicit-LOD texture lookup of 'emission' in 'main' "
                                     "may run after a discard in 'main'",
                                     0),
              0u)
        << messages[0].text;
    ASSERT_EQ(received.size(), 1u) << "the callback sees it as it is collected";
    EXPECT_EQ(received[0].text, messages[0].text);
}

TEST_P(DerivativeWarningTest, LookupsBeforeTheDiscardSayNothing) {
    ShaderHandle shader = device().createShader(fragment(kSampledFirst, "labels"));
    EXPECT_TRUE(device().takeDebugMessages().empty());
    EXPECT_TRUE(received.empty());
}

class DerivativeWarningWithoutValidationTest : public BackendTest {
protected:
    void customizeDeviceDesc(DeviceDesc& desc) override {
        desc.enableValidation = false;
        desc.enableSynchronizationValidation = false;
    }
};
JANUS_INSTANTIATE_BACKEND_TESTS(DerivativeWarningWithoutValidationTest);

TEST_P(DerivativeWarningWithoutValidationTest, IsNotChecked) {
    ShaderHandle shader = device().createShader(fragment(kSampledAfterDiscard, "labels"));
    EXPECT_NE(shader, nullptr);
    EXPECT_TRUE(device().takeDebugMessages().empty());
}

}  // namespace
}  // namespace janus::rhi::test
