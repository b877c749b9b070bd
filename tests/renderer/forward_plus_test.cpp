// GPU tests of Forward+ (issue 3) on all five configurations with validation on: the tiled
// image equals the naive all-lights image, tile lists are well formed and conservative, the
// frame plan holds only what the scene needs, and parity across configurations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "janus/renderer/image.h"
#include "janus/renderer/renderer.h"
#include "janus/renderer/scene.h"
#include "renderer/renderer_test_support.h"

namespace janus::renderer {
namespace {

using namespace test_support;


// ---------------------------------------------------------------------------------------------
// Scenes

// The default room (x in [-2, 2], y in [0, 3], z in [-2, 2], two directional lights) seen from
// its usual camera; tests add local lights to it.
Scene room() { return defaultScene(); }

glm::vec3 cameraForward(const Camera& camera) { return glm::normalize(camera.target - camera.position); }
glm::vec3 cameraRight(const Camera& camera) { return glm::normalize(glm::cross(cameraForward(camera), camera.up)); }

// Deterministic on every platform (std distributions are not): a 32-bit hash of the index.
float hashUnit(uint32_t i) {
    i ^= i >> 16;
    i *= 0x7feb352dU;
    i ^= i >> 15;
    i *= 0x846ca68bU;
    i ^= i >> 16;
    return float(i >> 8) / float(1u << 24);
}

// The room with `count` coloured point and spot lights of small range scattered inside it; every
// third light has no range (culled by the intensity cut-off instead).
Scene roomWithManyLights(uint32_t count) {
    Scene scene = room();
    for (uint32_t i = 0; i < count; ++i) {
        auto r = [&](uint32_t k) { return hashUnit(i * 8 + k); };
        const glm::vec3 position(-1.9f + 3.8f * r(0), 0.1f + 2.8f * r(1), -1.9f + 3.8f * r(2));
        const glm::vec3 color(0.2f + 0.8f * r(3), 0.2f + 0.8f * r(4), 0.2f + 0.8f * r(5));
        const std::optional<float> range = i % 3 == 2 ? std::nullopt : std::optional<float>(0.4f + 0.8f * r(6));
        // Without a range the default cut-off (0.01 lux) gives radius sqrt(I / 0.01): keep I small.
        const float intensity = range ? 0.5f + 2.0f * r(7) : 0.004f;
        if (i % 2 == 0) {
            scene.lights.push_back(pointLight(position, color, intensity, range));
        } else {
            const glm::vec3 direction(r(6) - 0.5f, -1.0f, r(7) - 0.5f);
            scene.lights.push_back(spotLight(position, direction, color, intensity * 2.0f, range, 0.3f, 0.6f));
        }
    }
    return scene;
}

Scene cameraInsideLights() {
    Scene scene = room();
    const Camera& camera = scene.camera;
    scene.lights.push_back(pointLight(camera.position, glm::vec3(1.0f, 0.8f, 0.6f), 1.5f, 3.0f));
    // A head lamp: a spot at the eye looking where the camera looks.
    scene.lights.push_back(spotLight(camera.position, cameraForward(camera), glm::vec3(0.6f, 0.8f, 1.0f), 6.0f, 5.0f, 0.2f, 0.4f));
    // The eye inside a light centred elsewhere.
    scene.lights.push_back(pointLight(camera.position + glm::vec3(0.4f, -0.6f, -0.5f), glm::vec3(0.3f, 1.0f, 0.3f), 1.0f, 1.5f));
    return scene;
}

Scene lightsStraddlingTheNearPlane() {
    Scene scene = room();
    const Camera& camera = scene.camera;
    const glm::vec3 forward = cameraForward(camera), right = cameraRight(camera);
    const float near = camera.nearPlane;
    // Centres on, just in front of and just behind the near plane, on and off the axis; ranges
    // reach far into the room.
    scene.lights.push_back(pointLight(camera.position + forward * near, glm::vec3(1.0f, 0.4f, 0.4f), 1.0f, 1.2f));
    scene.lights.push_back(pointLight(camera.position + forward * (0.5f * near) + right * 0.3f, glm::vec3(0.4f, 1.0f, 0.4f), 1.0f, 1.5f));
    scene.lights.push_back(pointLight(camera.position + forward * (2.0f * near) - right * 0.3f, glm::vec3(0.4f, 0.4f, 1.0f), 1.0f, 1.5f));
    scene.lights.push_back(spotLight(camera.position + forward * near - camera.up * 0.2f, forward, glm::vec3(1.0f), 4.0f, 4.0f, 0.1f, 0.5f));
    return scene;
}

Scene lightsBehindTheCamera() {
    Scene scene = room();
    const Camera& camera = scene.camera;
    const glm::vec3 forward = cameraForward(camera), right = cameraRight(camera);
    // Centres behind the eye (some outside the room: local lights cast no shadows, they reach
    // the visible floor through the front wall) whose spheres reach into the view.
    scene.lights.push_back(pointLight(camera.position - forward * 0.5f, glm::vec3(1.0f, 0.7f, 0.3f), 1.5f, 1.8f));
    scene.lights.push_back(pointLight(camera.position - forward * 1.0f + right * 0.8f, glm::vec3(0.3f, 0.7f, 1.0f), 2.0f, 3.0f));
    scene.lights.push_back(pointLight(camera.position - forward * 2.0f - right * 0.5f, glm::vec3(0.8f, 0.3f, 0.8f), 3.0f, 4.5f));
    scene.lights.push_back(spotLight(camera.position - forward * 0.8f, forward, glm::vec3(1.0f), 8.0f, 5.0f, 0.2f, 0.45f));
    return scene;
}

// ---------------------------------------------------------------------------------------------
// Checks

// ---------------------------------------------------------------------------------------------
// Forward+ image == naive image

struct SceneCase {
    const char* name;
    Scene (*make)();
    uint32_t tileSize;
};

void PrintTo(const SceneCase& sceneCase, std::ostream* os) { *os << sceneCase.name; }

const SceneCase kEqualityScenes[] = {
    {"ManyLights", [] { return roomWithManyLights(64); }, 16},
    {"CameraInsideLights", cameraInsideLights, 16},
    // Larger tiles too: the near-plane lights cover many pixels of few tiles.
    {"LightsStraddlingTheNearPlane", lightsStraddlingTheNearPlane, 32},
    {"LightsBehindTheCamera", lightsBehindTheCamera, 16},
};

using EqualityParam = std::tuple<SceneCase, Config>;

class ForwardPlusEqualsNaive : public testing::TestWithParam<EqualityParam> {
protected:
    const SceneCase& sceneCase() const { return std::get<0>(GetParam()); }
    const Config& config() const { return std::get<1>(GetParam()); }
};

TEST_P(ForwardPlusEqualsNaive, TiledImagesEqualTheNaiveImage) {
    const Scene scene = sceneCase().make();
    const FrameOutput naive = renderOneFrame(config(), scene, settingsFor(LightCulling::Naive));
    ASSERT_TRUE(naive.report.lightCulling.has_value()) << "the scene has local lights";
    EXPECT_EQ(naive.report.lightCulling->mode, LightCulling::Naive);
    EXPECT_EQ(naive.report.lightCulling->builder, "");
    expectFiniteHdr(naive.hdr, "naive");
    for (LightCulling mode : {LightCulling::Tiles2D, LightCulling::TilesDepth}) {
        RenderSettings settings = settingsFor(mode);
        settings.lighting.tileSize = sceneCase().tileSize;
        const FrameOutput tiled = renderOneFrame(config(), scene, settings, ReadBack{.tiles = true});
        const std::string label = fmt::format("{}-{}-{}", sceneCase().name, config().name(), cullingName(mode));
        ASSERT_TRUE(tiled.report.lightCulling.has_value()) << label;
        const LightCullingReport& culling = *tiled.report.lightCulling;
        EXPECT_EQ(culling.mode, mode) << label;
        EXPECT_EQ(culling.builder, config().path == FeaturePath::Compute ? "compute" : "cpu") << label;
        EXPECT_EQ(culling.tileSize, sceneCase().tileSize) << label;
        EXPECT_EQ(culling.overflowTiles, 0u) << label << ": the default cap must hold these scenes";
        EXPECT_EQ(culling.droppedLights, 0u) << label;
        EXPECT_GT(culling.listedLights, 0u) << label << ": visible lights must be listed somewhere";
        ASSERT_TRUE(tiled.tiles.has_value()) << label;
        expectWellFormedTileLists(*tiled.tiles, culling, kSize, kSize, label);
        expectSameImage(naive, tiled, label);
    }
}

INSTANTIATE_TEST_SUITE_P(Configs, ForwardPlusEqualsNaive, testing::Combine(testing::ValuesIn(kEqualityScenes), testing::ValuesIn(allConfigs())),
                         [](const testing::TestParamInfo<EqualityParam>& info) {
                             return fmt::format("{}_{}", std::get<0>(info.param).name, std::get<1>(info.param).name());
                         });

// ---------------------------------------------------------------------------------------------
// Parity of the many-lights scene across the five configurations

class ForwardPlusParity : public testing::TestWithParam<Config> {};

TEST_P(ForwardPlusParity, ManyLightsMatchesVulkanCompute) {
    const Scene scene = roomWithManyLights(64);
    static const FrameOutput reference = renderOneFrame(allConfigs()[0], scene, settingsFor(LightCulling::TilesDepth));
    const FrameOutput result = renderOneFrame(GetParam(), scene, settingsFor(LightCulling::TilesDepth));
    // As in render_test.cpp: at most one 8-bit step (the last bit of the shading math may round
    // differently in lavapipe's SPIR-V and llvmpipe's GLSL builds), except a handful of
    // silhouette pixels whose centre lies within rounding error of a triangle edge (GL and Vulkan
    // break ties with opposite y). A light missing from a tile changes a whole tile's pixels.
    constexpr uint64_t kMaxSilhouettePixels = 4;
    const ImageDifference diff = compareImages(reference.display, result.display, 1);
    if (diff.differingPixels > kMaxSilhouettePixels) {
        const std::filesystem::path dir = outputDir();
        writePNG(dir / fmt::format("ManyLights-{}.png", GetParam().name()), result.display);
        writePNG(dir / "ManyLights-vulkan_compute.png", reference.display);
        writePNG(dir / fmt::format("ManyLights-{}-diff.png", GetParam().name()), differenceHeatmap(reference.display, result.display));
        ADD_FAILURE() << GetParam().name() << " differs from vulkan/compute by more than 1 step in " << diff.differingPixels
                      << " pixels (up to " << diff.maxChannelDifference << " steps); images in " << dir;
    }
    ASSERT_TRUE(result.report.lightCulling.has_value());
    EXPECT_EQ(result.report.lightCulling->localLights, reference.report.lightCulling->localLights);
}

INSTANTIATE_TEST_SUITE_P(Configs, ForwardPlusParity, testing::ValuesIn(allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

// ---------------------------------------------------------------------------------------------
// Only what the scene needs

class ForwardPlusFramePlan : public testing::TestWithParam<Config> {
protected:
    const Config& config() const { return GetParam(); }
    bool compute() const { return config().path == FeaturePath::Compute; }
};

TEST_P(ForwardPlusFramePlan, NoLocalLightsMeansNoTileWork) {
    // The default room has two directional lights and no point or spot light; even a tiled mode
    // asked for explicitly has nothing to cull.
    for (LightCulling mode : {LightCulling::Auto, LightCulling::Tiles2D, LightCulling::TilesDepth}) {
        const FrameOutput output = renderOneFrame(config(), room(), settingsFor(mode, 64));
        const std::string label = fmt::format("{} {}", config().name(), cullingName(mode));
        EXPECT_FALSE(output.report.lightCulling.has_value()) << label << ": " << output.report.toJson().dump();
        EXPECT_FALSE(hasPassStartingWith(output.report, "light-cull")) << label << ": " << passNames(output.report);
        EXPECT_FALSE(hasPassStartingWith(output.report, "depth-prepass")) << label << ": " << passNames(output.report);
        expectFiniteHdr(output.hdr, label);
    }
    Renderer renderer(test_support::deviceFor(config().backend), room(), [&] {
        RenderSettings settings = settingsFor(LightCulling::TilesDepth, 32);
        settings.path = config().path;
        return settings;
    }());
    renderer.renderFrame();
    EXPECT_THROW(renderer.readTileLists(), RendererError) << "no tiles were built";
}

TEST_P(ForwardPlusFramePlan, AutoLoopsFewLightsNaivelyAndTilesMany) {
    Scene scene = roomWithManyLights(6);
    RenderSettings settings = settingsFor(LightCulling::Auto, 64);
    settings.lighting.autoTiledThreshold = 7;   // 6 lights: below
    const FrameOutput few = renderOneFrame(config(), scene, settings);
    ASSERT_TRUE(few.report.lightCulling.has_value());
    EXPECT_EQ(few.report.lightCulling->mode, LightCulling::Naive);
    EXPECT_EQ(few.report.lightCulling->localLights, 6u);
    EXPECT_FALSE(hasPassStartingWith(few.report, "light-cull")) << passNames(few.report);
    EXPECT_FALSE(hasPassStartingWith(few.report, "depth-prepass")) << passNames(few.report);

    settings.lighting.autoTiledThreshold = 6;   // 6 lights: at the threshold, tiled
    const FrameOutput many = renderOneFrame(config(), scene, settings);
    ASSERT_TRUE(many.report.lightCulling.has_value());
    EXPECT_EQ(many.report.lightCulling->mode, LightCulling::TilesDepth);
    EXPECT_EQ(many.report.lightCulling->builder, compute() ? "compute" : "cpu");
    EXPECT_TRUE(hasPassStartingWith(many.report, "depth-prepass")) << "TilesDepth needs depth bounds: " << passNames(many.report);
    if (compute()) {
        EXPECT_TRUE(hasPassStartingWith(many.report, "light-cull")) << passNames(many.report);
    }
    // Both frame plans light the scene the same way.
    expectSameImage(few, many, fmt::format("AutoThreshold-{}", config().name()));
}

TEST_P(ForwardPlusFramePlan, ShadowMapOnlyForADirectionalLight) {
    Scene withSun = roomWithManyLights(4);
    const FrameOutput sun = renderOneFrame(config(), withSun, settingsFor(LightCulling::Naive, 64));
    EXPECT_TRUE(hasPassStartingWith(sun.report, "shadow-map")) << passNames(sun.report);
    ASSERT_TRUE(sun.report.lightCulling.has_value());
    EXPECT_EQ(sun.report.lightCulling->directionalLights, 2u);

    RenderSettings noShadows = settingsFor(LightCulling::Naive, 64);
    noShadows.lighting.shadows = false;
    EXPECT_FALSE(hasPassStartingWith(renderOneFrame(config(), withSun, noShadows).report, "shadow-map"));

    Scene noSun = withSun;
    std::erase_if(noSun.lights, [](const Light& light) { return light.type == LightType::Directional; });
    const FrameOutput local = renderOneFrame(config(), noSun, settingsFor(LightCulling::Naive, 64));
    EXPECT_FALSE(hasPassStartingWith(local.report, "shadow-map")) << passNames(local.report);
    ASSERT_TRUE(local.report.lightCulling.has_value());
    EXPECT_EQ(local.report.lightCulling->directionalLights, 0u);
    EXPECT_EQ(local.report.lightCulling->localLights, 4u);
}

TEST_P(ForwardPlusFramePlan, SceneQualityKeysAndSettingsOverrideThem) {
    Scene scene = roomWithManyLights(8);
    scene.quality = {{"lightCulling", "tiles-2d"}, {"tileSize", 32}, {"maxLightsPerTile", 64}};
    RenderSettings settings;
    settings.width = settings.height = 64;
    const FrameOutput fromScene = renderOneFrame(config(), scene, settings);
    ASSERT_TRUE(fromScene.report.lightCulling.has_value());
    EXPECT_EQ(fromScene.report.lightCulling->mode, LightCulling::Tiles2D);
    EXPECT_EQ(fromScene.report.lightCulling->tileSize, 32u);
    EXPECT_EQ(fromScene.report.lightCulling->tilesX, 2u);
    EXPECT_EQ(fromScene.report.lightCulling->maxLightsPerTile, 64u);

    settings.lighting.culling = LightCulling::TilesDepth;
    settings.lighting.tileSize = 16;
    const FrameOutput overridden = renderOneFrame(config(), scene, settings);
    ASSERT_TRUE(overridden.report.lightCulling.has_value());
    EXPECT_EQ(overridden.report.lightCulling->mode, LightCulling::TilesDepth);
    EXPECT_EQ(overridden.report.lightCulling->tileSize, 16u);
    EXPECT_EQ(overridden.report.lightCulling->tilesX, 4u);
    EXPECT_EQ(overridden.report.lightCulling->maxLightsPerTile, 64u) << "unset settings keep the scene's value";
}

INSTANTIATE_TEST_SUITE_P(Configs, ForwardPlusFramePlan, testing::ValuesIn(allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

TEST(ForwardPlusLimits, MoreThan16384LocalLightsIsRefusedWithTheCountAndTheLimit) {
    Scene scene = room();
    for (uint32_t i = 0; i < 16385; ++i)
        scene.lights.push_back(pointLight(glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(1.0f), 0.001f, 0.1f));
    rhi::IDevice& device = test_support::deviceFor(rhi::Backend::Vulkan);
    try {
        Renderer renderer(device, scene, settingsFor(LightCulling::TilesDepth, 32));
        renderer.renderFrame();
        FAIL() << "16385 local lights were accepted";
    } catch (const RendererError& e) {
        EXPECT_NE(std::string(e.what()).find("16385"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("16384"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(device.takeDebugMessages().empty());
}

}  // namespace
}  // namespace janus::renderer
