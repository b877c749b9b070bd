// A Renderer keeps a reference to its rhi::IDevice, which must outlive it. When the device goes
// first anyway (say, members declared in the wrong order), the renderer's calls that use the
// device throw RendererError saying so, and its destructor warns instead of waiting on freed
// memory (before: use after free, a crash or worse). RHI handles may outlive their device.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "janus/renderer/renderer.h"
#include "renderer/renderer_test_support.h"

namespace janus::renderer {
namespace {

using test_support::Config;

class RendererLifetimeTest : public testing::TestWithParam<Config> {};

TEST_P(RendererLifetimeTest, ARendererWhoseDeviceWentFirstRefusesWorkAndOnlyWarns) {
    std::unique_ptr<rhi::IDevice> device =
        rhi::createDevice(rhi::DeviceDesc{}.setBackend(GetParam().backend).setEnableValidation(true));
    RenderSettings settings;
    settings.width = settings.height = 32;
    settings.path = GetParam().path;
    auto renderer = std::make_unique<Renderer>(*device, defaultScene(), settings);
    renderer->renderFrame();
    renderer->readDisplayImage();
    EXPECT_TRUE(device->takeDebugMessages().empty());
    device.reset();

    auto expectRefused = [](const std::function<void()>& call, const char* name) {
        try {
            call();
            ADD_FAILURE() << name << ": no error";
        } catch (const RendererError& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find(name), std::string::npos) << message;
            EXPECT_NE(message.find("was destroyed"), std::string::npos) << message;
        }
    };
    expectRefused([&] { renderer->renderFrame(); }, "renderFrame()");
    expectRefused([&] { renderer->readDisplayImage(); }, "readDisplayImage()");
    expectRefused([&] { renderer->readHdrImage(); }, "readHdrImage()");
    expectRefused([&] { renderer->readDepth(); }, "readDepth()");
    expectRefused([&] { renderer->setLights(defaultScene().lights); }, "setLights()");
    testing::internal::CaptureStderr();
    renderer.reset();
    const std::string warning = testing::internal::GetCapturedStderr();
    EXPECT_NE(warning.find("destroyed before the renderer"), std::string::npos) << warning;
}

INSTANTIATE_TEST_SUITE_P(Configs, RendererLifetimeTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
