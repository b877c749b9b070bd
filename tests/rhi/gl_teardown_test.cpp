// Teardown never throws (issue 10, item 3): on NVIDIA the renderer tests aborted at exit with
// "terminate called after throwing 'janus::rhi::Error' DeviceLost: eglMakeCurrent failed (EGL
// error 0x3000)", because devices held by static objects were destroyed after the driver had shut
// its EGL down, and every GL resource destructor made its context current with a throwing call.
//
// Here a platform double wraps a real EGL context and refuses makeCurrent once told to, as that
// driver did. Before the fix the first destructor to run threw out of a noexcept destructor and
// the test executable died in std::terminate.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstddef>
#include <memory>
#include <string>

#include "backend_test.h"
#include "gl_device.h"
#include "gl_platform.h"
#include "janus/shaders/shaders.h"

namespace janus::rhi::gl {
namespace {

struct PlatformSwitch {
    bool refuse = false;
    int refusedCalls = 0;
};

class RefusingPlatform final : public Platform {
public:
    RefusingPlatform(std::unique_ptr<Platform> real, std::shared_ptr<PlatformSwitch> state)
        : m_real(std::move(real)), m_state(std::move(state)) {}
    void makeCurrent() override {
        if (m_state->refuse) {
            ++m_state->refusedCalls;
            throw Error(ErrorCode::DeviceLost, "eglMakeCurrent failed (EGL error 0x3000)");
        }
        m_real->makeCurrent();
    }
    void releaseCurrent() noexcept override { m_real->releaseCurrent(); }
    void* getProcAddress(const char* name) const override { return m_real->getProcAddress(name); }
    std::string describe() const override { return m_real->describe(); }

private:
    std::unique_ptr<Platform> m_real;
    std::shared_ptr<PlatformSwitch> m_state;
};

size_t occurrences(const std::string& text, const std::string& what) {
    size_t count = 0;
    for (size_t pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + what.size())) ++count;
    return count;
}

TEST(GLTeardown, AContextThatCannotBeMadeCurrentIsReleasedWithoutThrowingAndSaysSoOnce) {
    if (!test::backendSelected({Backend::GL, GLPlatform::EGL, "gl_egl"}))
        GTEST_SKIP() << "gl_egl is not in JANUS_TEST_BACKENDS";
    auto state = std::make_shared<PlatformSwitch>();
    const DeviceDesc desc = DeviceDesc().setBackend(Backend::GL).setEnableValidation(true);
    auto device = std::make_unique<Device>(
        desc, std::make_unique<RefusingPlatform>(createEglPlatform(GLApi::DesktopCore43, true, {}), state));

    // One resource of every kind the backend deletes, used once so the context holds a framebuffer
    // object and a vertex array too.
    TextureHandle target = device->createTexture(
        TextureDesc().setFormat(Format::RGBA8_UNORM).setSize(4, 4).setUsage(TextureUsage::RenderTarget));
    BufferHandle buffer = device->createBuffer(BufferDesc().setSize(256).setUsage(BufferUsage::Vertex));
    SamplerHandle sampler = device->createSampler(SamplerDesc());
    ShaderHandle vertexShader = device->createShader(
        ShaderDesc().setStage(ShaderStage::Vertex).setSpirv(shaders::get("rt_vertex_color_vert")));
    ShaderHandle fragmentShader = device->createShader(
        ShaderDesc().setStage(ShaderStage::Fragment).setSpirv(shaders::get("rt_vertex_color_frag")));
    PipelineHandle pipeline = device->createGraphicsPipeline(
        GraphicsPipelineDesc()
            .setShaders(vertexShader, fragmentShader)
            .addVertexBuffer({0, sizeof(test::ColorVertex), false})
            .addVertexAttribute({0, VertexFormat::Float4, 0, offsetof(test::ColorVertex, x)})
            .addVertexAttribute({1, VertexFormat::Float4, 0, offsetof(test::ColorVertex, r)})
            .addColorFormat(Format::RGBA8_UNORM));
    TimerQueryHandle timer = device->createTimerQuery();
    CommandListHandle commands = device->createCommandList();
    commands->begin();
    commands->beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target, {0, 1, 0, 1})));
    commands->setPipeline(pipeline);
    commands->setVertexBuffer(0, buffer);
    commands->draw(3);
    commands->endRenderPass();
    commands->end();
    device->execute(commands);
    device->waitIdle();
    for (const DebugMessage& message : device->takeDebugMessages()) ADD_FAILURE() << message.text;
    const std::string platformName = device->info().platform;   // "egl (surfaceless)" on Mesa

    // Another device's context is current, as at exit with several devices alive, so tearing
    // this one down has to ask its platform.
    std::unique_ptr<IDevice> other = createDevice(DeviceDesc().setBackend(Backend::GL));
    state->refuse = true;

    testing::internal::CaptureStderr();
    // The device first: its resources outlive it and keep the context (and its objects) alive.
    EXPECT_NO_THROW(device.reset());
    EXPECT_NO_THROW({
        commands.reset();
        timer.reset();
        pipeline.reset();
        vertexShader.reset();
        fragmentShader.reset();
        sampler.reset();
        buffer.reset();
        target.reset();   // the last handle: the context goes with it
    });
    const std::string stderrText = testing::internal::GetCapturedStderr();

    EXPECT_EQ(occurrences(stderrText, "could not be made current at teardown"), 1u) << stderrText;
    EXPECT_NE(stderrText.find(fmt::format("janus: gl: the {} context could not be made current at teardown "
                                          "(DeviceLost: eglMakeCurrent failed (EGL error 0x3000)); GL objects are left to the "
                                          "driver\n",
                                          platformName)),
              std::string::npos)
        << stderrText;
    // Once refused, the rest of the teardown does not ask again (nor print again).
    EXPECT_EQ(state->refusedCalls, 1);

    // The other device was not disturbed: its context is still current and renders.
    TextureHandle otherTarget = other->createTexture(
        TextureDesc().setFormat(Format::RGBA8_UNORM).setSize(2, 2).setUsage(TextureUsage::RenderTarget));
    CommandListHandle otherCommands = other->createCommandList();
    otherCommands->begin();
    otherCommands->beginRenderPass(RenderPassDesc().addColor(Attachment::clear(otherTarget, {0, 0, 1, 1})));
    otherCommands->endRenderPass();
    otherCommands->end();
    other->execute(otherCommands);
    const std::vector<std::byte> pixels = other->readTexture(otherTarget, {});
    ASSERT_EQ(pixels.size(), 16u);
    EXPECT_EQ(uint8_t(pixels[0]), 0u);
    EXPECT_EQ(uint8_t(pixels[2]), 255u);
}

// A device whose platform works releases everything and prints nothing.
TEST(GLTeardown, AWorkingContextIsReleasedSilently) {
    if (!test::backendSelected({Backend::GL, GLPlatform::EGL, "gl_egl"}))
        GTEST_SKIP() << "gl_egl is not in JANUS_TEST_BACKENDS";
    auto state = std::make_shared<PlatformSwitch>();
    auto device = std::make_unique<Device>(
        DeviceDesc().setBackend(Backend::GL),
        std::make_unique<RefusingPlatform>(createEglPlatform(GLApi::DesktopCore43, false, {}), state));
    BufferHandle buffer = device->createBuffer(BufferDesc().setSize(64).setUsage(BufferUsage::Uniform));
    std::unique_ptr<IDevice> other = createDevice(DeviceDesc().setBackend(Backend::GL));
    testing::internal::CaptureStderr();
    device.reset();
    buffer.reset();
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    EXPECT_EQ(state->refusedCalls, 0);
}

}  // namespace
}  // namespace janus::rhi::gl
