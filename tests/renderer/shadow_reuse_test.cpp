// A static scene draws its shadow map once: nothing in a scene moves once it is loaded, so the map
// stays right until setLights turns the main light (DirectionalShadowMap::upToDate). Later frames
// have no shadow-map pass and the same image, shadows and all; a light of another colour or
// intensity keeps the map, a turned one draws it again. Before, every frame drew the map. On every
// configuration.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "janus/renderer/renderer.h"
#include "renderer/renderer_test_support.h"

namespace janus::renderer {
namespace {

using test_support::Config;

class ShadowReuseTest : public testing::TestWithParam<Config> {};

int shadowPasses(const FrameReport& report) {
    return int(std::count_if(report.passes.begin(), report.passes.end(), [](const PassReport& p) { return p.name == "shadow-map"; }));
}

TEST_P(ShadowReuseTest, AStaticSceneDrawsItsShadowMapOnceAndATurnedLightDrawsItAgain) {
    rhi::IDevice& device = test_support::deviceFor(GetParam().backend);
    device.takeDebugMessages();
    const Scene scene = defaultScene();
    RenderSettings settings;
    settings.width = settings.height = test_support::kSize;
    settings.path = GetParam().path;
    Renderer renderer(device, scene, settings);
    EXPECT_EQ(shadowPasses(renderer.renderFrame()), 1) << GetParam().name();
    const ImageRGBA8 first = renderer.readDisplayImage();
    for (int frame = 2; frame <= 3; ++frame) {
        EXPECT_EQ(shadowPasses(renderer.renderFrame()), 0) << GetParam().name() << ": frame " << frame;
        EXPECT_EQ(renderer.readDisplayImage().pixels, first.pixels) << GetParam().name() << ": frame " << frame << " lost its shadows";
    }
    // Brighter, same direction: the map stays.
    std::vector<Light> lights = scene.lights;
    const auto main = mainDirectionalLight(scene);
    ASSERT_TRUE(main.has_value());
    lights[*main].intensity *= 1.5f;
    renderer.setLights(lights);
    EXPECT_EQ(shadowPasses(renderer.renderFrame()), 0) << GetParam().name() << ": a brighter light drew the map again";
    // Turned: the map is drawn again, and the shadows move.
    lights[*main].direction = glm::normalize(lights[*main].direction + glm::vec3(0.4f, 0.0f, 0.3f));
    renderer.setLights(lights);
    EXPECT_EQ(shadowPasses(renderer.renderFrame()), 1) << GetParam().name() << ": a turned light kept the old map";
    const ImageRGBA8 turned = renderer.readDisplayImage();
    EXPECT_EQ(shadowPasses(renderer.renderFrame()), 0) << GetParam().name();
    // The same as a new renderer made with the turned light (its map drawn in its first frame).
    Scene turnedScene = scene;
    turnedScene.lights = lights;
    Renderer fresh(device, turnedScene, settings);
    fresh.renderFrame();
    EXPECT_EQ(fresh.readDisplayImage().pixels, turned.pixels) << GetParam().name();
    EXPECT_TRUE(device.takeDebugMessages().empty()) << GetParam().name();
}

INSTANTIATE_TEST_SUITE_P(Configs, ShadowReuseTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
