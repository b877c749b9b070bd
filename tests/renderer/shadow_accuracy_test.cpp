// The shadow map against the truth (docs/SHADOWS.md, "Accuracy vs time"): the ray-traced reference
// (GiReference::lightVisibility) and its error measure on the CPU, then `DebugView::Shadow` on every
// configuration: the map's visibility agrees with the reference, more closely with a larger map,
// and every configuration sees the same visibility.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "janus/renderer/gi_reference.h"
#include "janus/renderer/light_grid.h"
#include "janus/renderer/renderer.h"
#include "renderer/renderer_test_support.h"
#include "scene/scene_internal.h"

namespace janus::renderer {
namespace {

using test_support::Config;

const glm::vec3 kLightDirection = glm::normalize(glm::vec3(0.35f, -1.0f, 0.2f));
constexpr float kBoxHalf = 0.5f, kBoxHeight = 1.0f;   // the box's centre above the ground

// A 6 m ground (single-sided, facing up), a 1 m box floating above it and a sun, seen from above at
// an angle: the box's shadow lies on the ground away from its contact, so its whole outline is an
// edge a map can get wrong.
Scene boxOverGround() {
    Scene scene;
    scene.materials.push_back(Material{});
    const uint32_t quad = detail::addMesh(scene, detail::makeQuad(0));
    scene.instances.push_back(Instance{quad, test_support::quadFacing(glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f), 6.0f), 1u, "ground"});
    const uint32_t box = detail::addMesh(scene, detail::makeBox(0));
    scene.instances.push_back(Instance{box,
                                       glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, kBoxHeight, 0.0f)), glm::vec3(kBoxHalf)),
                                       1u, "box"});
    Light sun;
    sun.direction = kLightDirection;
    sun.intensity = 3.0f;
    scene.lights.push_back(sun);
    scene.camera.position = glm::vec3(0.6f, 4.5f, 3.5f);
    scene.camera.target = glm::vec3(0.3f, 0.0f, 0.0f);
    return scene;
}

// Where the shadow of the box's centre falls on the ground (y = 0).
glm::vec3 umbraCentre() { return glm::vec3(0.0f, kBoxHeight, 0.0f) + kLightDirection * (kBoxHeight / -kLightDirection.y); }

// The pixel (row 0 on top) `world` lands on in a width x height view of `camera`.
glm::ivec2 pixelOf(const Camera& camera, const glm::vec3& world, uint32_t width, uint32_t height) {
    const glm::vec4 clip = makeProjection(camera, width, height) * makeView(camera) * glm::vec4(world, 1.0f);
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;   // NDC y = -1 is row 0 (docs/ARCHITECTURE.md)
    return glm::ivec2(int((ndc.x * 0.5f + 0.5f) * width), int((ndc.y * 0.5f + 0.5f) * height));
}

float channel(const ImageRGBAF& image, glm::ivec2 pixel, int c) {
    return image.pixels[(size_t(pixel.y) * image.width + size_t(pixel.x)) * 4 + size_t(c)];
}

// ---- The reference (CPU) ---------------------------------------------------------------------

TEST(ShadowReference, TheBoxShadowsTheGroundWhereTheLightSaysAndOnlyThere) {
    const Scene scene = boxOverGround();
    const GiReference tracer(scene);
    const uint32_t size = 96;
    const ImageRGBAF visibility = tracer.lightVisibility(scene.camera, size, size, kLightDirection);
    struct Probe {
        glm::vec3 point;
        float lit, compared;
        const char* what;
    };
    const std::vector<Probe> probes = {
        {umbraCentre(), 0.0f, 1.0f, "ground in the box's shadow"},
        {umbraCentre() + glm::vec3(0.2f, 0.0f, -0.15f), 0.0f, 1.0f, "ground in the box's shadow, off centre"},
        {glm::vec3(-1.5f, 0.0f, 1.0f), 1.0f, 1.0f, "open ground"},
        {glm::vec3(2.0f, 0.0f, -1.5f), 1.0f, 1.0f, "open ground"},
        {glm::vec3(0.0f, kBoxHeight + kBoxHalf, 0.0f), 1.0f, 1.0f, "box top"},
    };
    for (const Probe& probe : probes) {
        const glm::ivec2 pixel = pixelOf(scene.camera, probe.point, size, size);
        ASSERT_TRUE(pixel.x >= 0 && pixel.y >= 0 && pixel.x < int(size) && pixel.y < int(size)) << probe.what << " is out of view";
        EXPECT_EQ(channel(visibility, pixel, 3), probe.compared) << probe.what;
        EXPECT_EQ(channel(visibility, pixel, 0), probe.lit) << probe.what << " at pixel " << pixel.x << ", " << pixel.y;
    }
    // The sky and the box's faces turned from the light are not compared: the light adds nothing
    // there whatever a map says.
    uint64_t compared = 0, shadowed = 0;
    for (size_t i = 0; i < size_t(size) * size; ++i) {
        const float a = visibility.pixels[i * 4 + 3], v = visibility.pixels[i * 4];
        ASSERT_TRUE(a == 0.0f || a == 1.0f);
        ASSERT_TRUE(v == 0.0f || v == 1.0f);
        if (a == 0.0f) {
            EXPECT_EQ(v, 0.0f);
        }
        compared += a == 1.0f;
        shadowed += a == 1.0f && v == 0.0f;
    }
    EXPECT_LT(compared, uint64_t(size) * size) << "the box's sides facing away and the sky must not be compared";
    EXPECT_GT(shadowed, 100u) << "the box's shadow should cover a good part of the view";
}

TEST(ShadowReference, ErrorsSplitIntoLeaksAndFalseShadows) {
    // Six compared pixels (reference: 3 lit, 3 shadowed) and one that is not.
    const ImageRGBAF reference{7, 1, {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1, 0}};
    const float nan = std::numeric_limits<float>::quiet_NaN();
    // lit 1 (right), 0.25 (a false shadow, 0.75 off), 0.6 (0.4 off, not wrong); shadowed 0 (right),
    // 0.9 (a leak), NaN (counted as wrong: a leak, 1 off); the uncompared pixel 0.3 is ignored.
    const ImageRGBAF rendered{7, 1, {1, 0, 0, 1, 0.25f, 0, 0, 1, 0.6f, 0, 0, 1, 0, 0, 0, 1, 0.9f, 0, 0, 1, nan, 0, 0, 1, 0.3f, 0, 0, 1}};
    const VisibilityError error = compareVisibility(rendered, reference);
    EXPECT_EQ(error.compared, 6u);
    EXPECT_NEAR(error.meanAbsolute, (0.0 + 0.75 + 0.4 + 0.0 + 0.9 + 1.0) / 6.0, 1e-6);
    EXPECT_NEAR(error.rmse, std::sqrt((0.75 * 0.75 + 0.4 * 0.4 + 0.9 * 0.9 + 1.0) / 6.0), 1e-6);
    EXPECT_NEAR(error.leakFraction, 2.0 / 6.0, 1e-12);
    EXPECT_NEAR(error.falseShadowFraction, 1.0 / 6.0, 1e-12);
    EXPECT_NEAR(error.wrongFraction, 3.0 / 6.0, 1e-12);
    EXPECT_THROW(compareVisibility(ImageRGBAF{6, 1, std::vector<float>(24, 1.0f)}, reference), RendererError);
}

TEST(ShadowReference, RefusesANonDirectionAndAnEmptyImage) {
    const Scene scene = boxOverGround();
    const GiReference tracer(scene);
    EXPECT_THROW(tracer.lightVisibility(scene.camera, 8, 8, glm::vec3(0.0f)), RendererError);
    EXPECT_THROW(tracer.lightVisibility(scene.camera, 8, 8, glm::vec3(std::numeric_limits<float>::quiet_NaN(), -1.0f, 0.0f)), RendererError);
    EXPECT_THROW(tracer.lightVisibility(scene.camera, 0, 8, kLightDirection), RendererError);
}

// ---- DebugView::Shadow on every configuration ------------------------------------------------

class ShadowAccuracyTest : public testing::TestWithParam<Config> {};

ImageRGBAF shadowView(const Config& config, const Scene& scene, uint32_t mapSize) {
    RenderSettings settings;
    settings.width = settings.height = test_support::kSize;
    settings.lighting.shadowMapSize = mapSize;
    settings.debugView = DebugView::Shadow;
    return test_support::renderOneFrame(config, scene, settings).hdr;
}

TEST_P(ShadowAccuracyTest, TheMapsVisibilityApproachesTheRayTracedOneAsItGrows) {
    const Scene scene = boxOverGround();
    const ImageRGBAF reference =
        GiReference(scene).lightVisibility(scene.camera, test_support::kSize, test_support::kSize, kLightDirection);
    const ImageRGBAF coarse = shadowView(GetParam(), scene, 64), fine = shadowView(GetParam(), scene, 2048);
    for (const ImageRGBAF* image : {&coarse, &fine})
        for (size_t i = 0; i < image->pixels.size(); i += 4)
            ASSERT_TRUE(image->pixels[i] >= 0.0f && image->pixels[i] <= 1.0f) << "visibility " << image->pixels[i] << " at pixel " << i / 4;
    const VisibilityError coarseError = compareVisibility(coarse, reference), fineError = compareVisibility(fine, reference);
    ASSERT_GT(fineError.compared, 5000u);
    // A 2048 map's texel is ~3 mm here, its PCF blur ~1 cm: only pixels on the shadow's outline
    // may differ, and by less than half at most of them (lavapipe / llvmpipe: mean 0.06 %, 0.02 %
    // wrong; the bounds leave room for other drivers' filtering). Acne or a shadow shifted by a
    // texel of a wrong fit would cover whole areas of the ground.
    EXPECT_LT(fineError.meanAbsolute, 0.003) << "2048 map";
    EXPECT_LT(fineError.wrongFraction, 0.002) << "2048 map";
    EXPECT_LT(fineError.meanAbsolute * 2.0, coarseError.meanAbsolute) << "a 64 map should be much further from the reference";
    // Where the map is certain (well inside the shadow or the light), it is exact.
    EXPECT_EQ(channel(fine, pixelOf(scene.camera, umbraCentre(), test_support::kSize, test_support::kSize), 0), 0.0f);
    EXPECT_EQ(channel(fine, pixelOf(scene.camera, glm::vec3(-1.5f, 0.0f, 1.0f), test_support::kSize, test_support::kSize), 0), 1.0f);
}

TEST_P(ShadowAccuracyTest, EveryConfigurationSeesTheSameVisibility) {
    const Config reference = test_support::allConfigs().front();
    if (GetParam().name() == reference.name()) GTEST_SKIP() << "the reference configuration";
    const Scene scene = boxOverGround();
    const ImageRGBAF expected = shadowView(reference, scene, 256), actual = shadowView(GetParam(), scene, 256);
    ASSERT_EQ(actual.pixels.size(), expected.pixels.size());
    // The same map and the same taps; the filtered compare's bilinear weights are the driver's, so
    // a pixel may differ by a rounding step of them, never by more than 1/64.
    for (size_t i = 0; i < expected.pixels.size(); i += 4)
        ASSERT_NEAR(actual.pixels[i], expected.pixels[i], 1.0f / 64.0f) << "pixel " << i / 4 << " against " << reference.name();
}

INSTANTIATE_TEST_SUITE_P(Configurations, ShadowAccuracyTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
