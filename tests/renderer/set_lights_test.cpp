// Renderer::setLights (docs/LIGHTING.md, "Moving lights"; docs/GI.md, "Relight"): on every
// configuration, a moved point light (tiled culling, GI) and a moved directional light (the shadow
// map refitted, no GI) give exactly the image of a new Renderer made with the moved lights; the
// frame after a change relights the irradiance volume and the frame after an unchanged set does
// not; a light dimmed to zero keeps the plan; bad lights and lights the plan has no room for are
// refused and change nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "janus/renderer/renderer.h"
#include "renderer/renderer_test_support.h"

namespace janus::renderer {
namespace {

namespace fs = std::filesystem;
using test_support::Config;

const fs::path kCornellBox = fs::path(JANUS_SHARED_SCENES_DIR) / "cornell-box" / "cornellBox.gltf";

class SetLightsTest : public test_support::ConfigTest {};

using test_support::countPasses;

// The cornell box (its glTF brings no light: the default key light, directional) with a small
// volume relit in one frame, two bounces, and no reflection probe (their update mode decides when
// they see new lights; they are not what is tested here).
Scene cornellBox(bool gi) {
    Scene scene = loadScene(kCornellBox);
    scene.reflectionProbes.clear();
    if (gi) {
        scene.irradianceVolume->probeCounts = glm::uvec3(2);
        scene.irradianceVolume->bounces = 2;
    } else {
        scene.irradianceVolume.reset();
    }
    return scene;
}

glm::vec3 boxCentre(const Scene& scene) {
    const Scene withVolume = loadScene(kCornellBox);   // its volume covers the box
    return (withVolume.irradianceVolume->bounds.min + withVolume.irradianceVolume->bounds.max) * 0.5f;
}

struct Rendered {
    FrameReport report;
    ImageRGBAF hdr;
};

Rendered renderWith(rhi::IDevice& device, const Scene& scene, const RenderSettings& settings) {
    Renderer renderer(device, scene, settings);
    Rendered out;
    out.report = renderer.renderFrame();
    out.hdr = renderer.readHdrImage();
    return out;
}

// Exact: setLights must leave the renderer in the state a new one starts in (same light array,
// frame uniforms, shadow fit, relight from scratch), and every configuration is deterministic for
// the same inputs, so not one bit may differ.
void expectSameHdr(const ImageRGBAF& expected, const ImageRGBAF& actual, const std::string& label) {
    ASSERT_EQ(expected.pixels.size(), actual.pixels.size()) << label;
    size_t differing = 0, first = 0;
    for (size_t i = 0; i < expected.pixels.size(); ++i)
        if (expected.pixels[i] != actual.pixels[i] && differing++ == 0) first = i;
    EXPECT_EQ(differing, 0u) << label << ": first at value " << first << " (pixel " << first / 4 << "): expected "
                             << expected.pixels[first] << ", got " << actual.pixels[first];
}

double maxDifference(const ImageRGBAF& a, const ImageRGBAF& b) {
    double most = 0.0;
    for (size_t i = 0; i < a.pixels.size() && i < b.pixels.size(); ++i) most = std::max(most, double(std::abs(a.pixels[i] - b.pixels[i])));
    return most;
}

TEST_P(SetLightsTest, AMovedPointLightGivesTheImageOfANewRendererAndRelightsTheVolumeOnce) {
    device().takeDebugMessages();
    Scene scene = cornellBox(true);
    const glm::vec3 centre = boxCentre(scene);
    scene.lights.push_back(test_support::pointLight(centre + glm::vec3(-0.5f, 0.3f, 0.0f), glm::vec3(1.0f, 0.8f, 0.6f), 4.0f, {}));
    RenderSettings settings = settingsOfSize(48, 48);
    settings.lighting.culling = LightCulling::TilesDepth;   // the moved light must reach the tile lists too

    Renderer renderer(device(), scene, settings);
    const FrameReport first = renderer.renderFrame();
    EXPECT_EQ(countPasses(first, "gi-probe-sh"), 2u) << test_support::passNames(first);
    EXPECT_EQ(countPasses(renderer.renderFrame(), "gi-"), 0u) << "a static scene relights once";
    const ImageRGBAF before = renderer.readHdrImage();

    std::vector<Light> moved = scene.lights;
    moved.back().position = centre + glm::vec3(0.5f, -0.2f, 0.3f);
    renderer.setLights(moved);
    const FrameReport after = renderer.renderFrame();
    // The same cycles as a new renderer's first frame: two bounces, both passes each.
    EXPECT_EQ(countPasses(after, "gi-brick-radiance"), 2u) << test_support::passNames(after);
    EXPECT_EQ(countPasses(after, "gi-probe-sh"), 2u) << test_support::passNames(after);
    EXPECT_EQ(countPasses(after, "light-cull-"), 1u) << test_support::passNames(after);
    const ImageRGBAF movedImage = renderer.readHdrImage();

    renderer.setLights(moved);   // nothing changed: nothing to relight
    const FrameReport unchanged = renderer.renderFrame();
    EXPECT_EQ(countPasses(unchanged, "gi-"), 0u) << test_support::passNames(unchanged);
    const ImageRGBAF unchangedImage = renderer.readHdrImage();

    Scene movedScene = scene;
    movedScene.lights = moved;
    const Rendered fresh = renderWith(device(), movedScene, settings);
    expectNoMessages();
    // The move must show (else the comparison below proves nothing)...
    EXPECT_GT(maxDifference(before, movedImage), 0.05) << GetParam().name();
    // ...and give, bit for bit, what a renderer made with the moved light renders.
    expectSameHdr(fresh.hdr, movedImage, GetParam().name() + " moved point light");
    expectSameHdr(fresh.hdr, unchangedImage, GetParam().name() + " frame after an unchanged set");
}

TEST_P(SetLightsTest, AMovedDirectionalLightRefitsTheShadowMapAndASceneWithoutGiHasNoRelight) {
    device().takeDebugMessages();
    const Scene scene = cornellBox(false);
    ASSERT_EQ(scene.lights.size(), 1u);
    ASSERT_EQ(scene.lights[0].type, LightType::Directional);
    const RenderSettings settings = settingsOfSize(48, 48);

    Renderer renderer(device(), scene, settings);
    renderer.renderFrame();
    const ImageRGBAF before = renderer.readHdrImage();
    std::vector<Light> moved = scene.lights;
    moved[0].direction = glm::normalize(glm::vec3(0.6f, -1.0f, 0.2f));
    moved[0].intensity *= 1.5f;
    renderer.setLights(moved);
    const FrameReport after = renderer.renderFrame();
    EXPECT_EQ(countPasses(after, "gi-"), 0u) << test_support::passNames(after);
    EXPECT_EQ(countPasses(after, "shadow-map"), 1u) << test_support::passNames(after);
    const ImageRGBAF movedImage = renderer.readHdrImage();

    Scene movedScene = scene;
    movedScene.lights = moved;
    const Rendered fresh = renderWith(device(), movedScene, settings);
    expectNoMessages();
    EXPECT_GT(maxDifference(before, movedImage), 0.05) << GetParam().name();
    expectSameHdr(fresh.hdr, movedImage, GetParam().name() + " moved directional light");
}

// A point light dimmed to 0 is packed as a dark placeholder (the plan keeps its light array): the
// image is that of a renderer made without it, and turning it on again works.
TEST_P(SetLightsTest, ALightDimmedToZeroKeepsThePlanAndAddsNothing) {
    device().takeDebugMessages();
    Scene scene = cornellBox(false);
    const glm::vec3 centre = boxCentre(scene);
    scene.lights.push_back(test_support::pointLight(centre + glm::vec3(0.3f, 0.2f, 0.0f), glm::vec3(1.0f), 5.0f, {}));
    const RenderSettings settings = settingsOfSize(48, 48);
    Renderer renderer(device(), scene, settings);
    renderer.renderFrame();
    const ImageRGBAF lit = renderer.readHdrImage();

    std::vector<Light> dimmed = scene.lights;
    dimmed.back().intensity = 0.0f;
    renderer.setLights(dimmed);
    renderer.renderFrame();
    const ImageRGBAF dark = renderer.readHdrImage();
    Scene without = scene;
    without.lights.pop_back();
    const Rendered fresh = renderWith(device(), without, settings);

    renderer.setLights(scene.lights);
    renderer.renderFrame();
    const ImageRGBAF litAgain = renderer.readHdrImage();
    expectNoMessages();
    expectSameHdr(fresh.hdr, dark, GetParam().name() + " dimmed to zero");
    expectSameHdr(lit, litAgain, GetParam().name() + " lit again");
}

TEST_P(SetLightsTest, BadLightsAndLightsThePlanHasNoRoomForAreRefusedAndChangeNothing) {
    device().takeDebugMessages();
    Scene scene = cornellBox(false);
    scene.lights[0].intensity = 0.0f;   // no directional light that gives light: no shadow-map pass
    scene.lights.push_back(test_support::pointLight(boxCentre(scene), glm::vec3(1.0f), 3.0f, {}));
    Renderer renderer(device(), scene, settingsOfSize(32, 32));
    renderer.renderFrame();
    const ImageRGBAF before = renderer.readHdrImage();

    auto expectRefused = [&](std::vector<Light> lights, const std::string& expected, const char* what) {
        try {
            renderer.setLights(lights);
            ADD_FAILURE() << what << ": no error";
        } catch (const RendererError& e) {
            EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << what << ": " << e.what();
        }
    };
    std::vector<Light> bad = scene.lights;
    bad[1].position.x = std::numeric_limits<float>::quiet_NaN();
    expectRefused(bad, "light 1 has a NaN or infinite", "NaN position");
    bad = scene.lights;
    bad[1].intensity = -1.0f;
    expectRefused(bad, "light 1 has a negative colour or intensity", "negative intensity");
    bad = scene.lights;
    bad[0].direction = glm::vec3(0.0f);
    expectRefused(bad, "light 0 has a zero direction", "zero direction");
    bad = scene.lights;
    bad.push_back(test_support::pointLight(glm::vec3(0.0f), glm::vec3(1.0f), 1.0f, {}));
    expectRefused(bad, "create a new Renderer", "a second point light");
    bad = scene.lights;
    bad[0].intensity = 2.0f;
    expectRefused(bad, "create a new Renderer", "a directional light where the frame has no shadow map");

    const FrameReport after = renderer.renderFrame();
    EXPECT_EQ(countPasses(after, "shadow-map"), 0u) << test_support::passNames(after);
    expectNoMessages();
    expectSameHdr(before, renderer.readHdrImage(), GetParam().name() + " after refused lights");
}

INSTANTIATE_TEST_SUITE_P(Configs, SetLightsTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
