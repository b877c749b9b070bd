// Alpha-masked casters cast shadows only where their alpha test keeps them, as the forward pass
// draws them: a checkered masked quad casts a checkered shadow, and a masked quad whose alpha is
// below its cutoff everywhere casts none. Before, the shadow map drew every masked caster solid
// (its pass read no material), so both cast full shadows. On every configuration, through the
// shadow debug view (the map's visibility on the surface each pixel sees), and against the
// ray-traced reference, whose rays pass where the alpha test discards too.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "janus/renderer/renderer.h"
#include "janus/renderer/gi_reference.h"
#include "janus/renderer/light_grid.h"
#include "renderer/renderer_test_support.h"
#include "scene/scene_internal.h"

namespace janus::renderer {
namespace {

using test_support::Config;

// A grey floor at y = 0 under a sun that travels along +x and down (shadows fall 0.5 m towards +x
// of casters 0.5 m up), and two masked 1 m quads 0.5 m up, facing the sun: A (x in [-1.5, -0.5])
// with a 2x2 checker of alpha 1 and 0 (nearest, clamped: each cell a quadrant), B (x in [0.5,
// 1.5]) with alpha 0.2 everywhere, below its cutoff. An orthographic camera looks straight down
// at x, z in [-2, 2].
Scene maskedCasters() {
    Scene scene;
    scene.name = "masked casters";
    const int32_t grey = detail::addMaterial(scene, "floor", glm::vec3(0.6f), 0.0f, 1.0f);
    TextureImage checker;
    checker.width = checker.height = 2;
    checker.rgba = {255, 255, 255, 255, 255, 255, 255, 0, 255, 255, 255, 0, 255, 255, 255, 255};
    checker.sampling.wrapU = checker.sampling.wrapV = TextureWrap::ClampToEdge;
    checker.sampling.nearestMagnification = checker.sampling.nearestMinification = true;
    checker.sampling.mipmapped = false;
    checker.name = "checker alpha";
    scene.textures.push_back(checker);
    const int32_t checkered = detail::addMaterial(scene, "checkered mask", glm::vec3(0.8f, 0.2f, 0.2f), 0.0f, 1.0f);
    scene.materials[size_t(checkered)].alphaMode = AlphaMode::Mask;
    scene.materials[size_t(checkered)].baseColorTexture = 0;
    const int32_t clear = detail::addMaterial(scene, "clear mask", glm::vec3(0.2f, 0.2f, 0.8f), 0.0f, 1.0f);
    scene.materials[size_t(clear)].alphaMode = AlphaMode::Mask;
    scene.materials[size_t(clear)].baseColorFactor.a = 0.2f;
    const glm::vec3 up(0.0f, 1.0f, 0.0f);
    scene.instances.push_back(
        Instance{detail::addMesh(scene, detail::makeQuad(grey)), test_support::quadFacing(glm::vec3(0.0f), up, 6.0f), 1u, "floor"});
    scene.instances.push_back(Instance{detail::addMesh(scene, detail::makeQuad(checkered)),
                                       test_support::quadFacing(glm::vec3(-1.0f, 0.5f, 0.0f), up, 1.0f), 1u, "A"});
    scene.instances.push_back(Instance{detail::addMesh(scene, detail::makeQuad(clear)),
                                       test_support::quadFacing(glm::vec3(1.0f, 0.5f, 0.0f), up, 1.0f), 1u, "B"});
    Light sun;
    sun.direction = glm::normalize(glm::vec3(1.0f, -1.0f, 0.0f));
    sun.intensity = 3.0f;
    scene.lights.push_back(sun);
    scene.camera.projection = CameraProjection::Orthographic;
    scene.camera.position = glm::vec3(0.0f, 5.0f, 0.0f);
    scene.camera.target = glm::vec3(0.0f);
    scene.camera.up = glm::vec3(0.0f, 0.0f, -1.0f);
    scene.camera.orthographicHalfHeight = 2.0f;
    scene.camera.nearPlane = 0.1f;
    scene.camera.farPlane = 10.0f;
    return scene;
}

// The visibility (debug view's red) of the floor pixels whose centre's ray meets the floor at
// x in [x0, x1], z in [z0, z1]: their mean, lowest and highest.
struct RegionVisibility {
    double mean = 0.0, lowest = 1e9, highest = -1e9;
    uint32_t pixels = 0;
};
RegionVisibility visibility(const ImageRGBAF& hdr, const Camera& camera, float x0, float x1, float z0, float z1) {
    const glm::dmat4 inverse = glm::inverse(glm::dmat4(makeProjection(camera, hdr.width, hdr.height)) * glm::dmat4(makeView(camera)));
    RegionVisibility region;
    for (uint32_t y = 0; y < hdr.height; ++y)
        for (uint32_t x = 0; x < hdr.width; ++x) {
            // NDC y = -1 is row 0; the ray is straight down, so its near point's x, z are the floor's.
            const glm::dvec4 p = inverse * glm::dvec4((x + 0.5) / hdr.width * 2.0 - 1.0, (y + 0.5) / hdr.height * 2.0 - 1.0, 0.0, 1.0);
            const double wx = p.x / p.w, wz = p.z / p.w;
            if (wx < x0 || wx > x1 || wz < z0 || wz > z1) continue;
            const double v = hdr.pixels[(size_t(y) * hdr.width + x) * 4];
            region.mean += v;
            region.lowest = std::min(region.lowest, v);
            region.highest = std::max(region.highest, v);
            ++region.pixels;
        }
    if (region.pixels > 0) region.mean /= region.pixels;
    return region;
}

std::string describe(const RegionVisibility& r) {
    return fmt::format("mean {:.3f}, lowest {:.3f}, highest {:.3f} over {} pixels", r.mean, r.lowest, r.highest, r.pixels);
}

class MaskedShadowTest : public testing::TestWithParam<Config> {
protected:
    // The scene's shadow debug view: the map's visibility in the HDR image's red channel.
    test_support::FrameOutput renderShadowView(const Scene& scene) {
        RenderSettings settings;
        settings.width = settings.height = test_support::kSize;
        settings.debugView = DebugView::Shadow;
        return test_support::renderOneFrame(GetParam(), scene, settings);
    }
};

TEST_P(MaskedShadowTest, AMaskedCasterCastsOnlyWhereItsAlphaTestKeepsIt) {
    const Scene scene = maskedCasters();
    const test_support::FrameOutput frame = renderShadowView(scene);
    ASSERT_EQ(frame.report.passes.front().name, "shadow-map") << test_support::passNames(frame.report);
    // Open floor, away from every shadow: lit.
    const RegionVisibility open = visibility(frame.hdr, scene.camera, -1.95f, -1.6f, -1.5f, 1.5f);
    EXPECT_GT(open.lowest, 0.99) << GetParam().name() << ": " << describe(open);
    // A's right half casts here (beside A, seen directly): one of its two cells is opaque, the
    // other clear, so half of the region is shadowed and half lit (the PCF kernel blurs the
    // cells' edges by about two texels either way).
    const RegionVisibility checkered = visibility(frame.hdr, scene.camera, -0.45f, -0.05f, -0.45f, 0.45f);
    EXPECT_NEAR(checkered.mean, 0.5, 0.12) << GetParam().name() << ": " << describe(checkered);
    EXPECT_LT(checkered.lowest, 0.01) << GetParam().name() << ": the opaque cells cast no shadow; " << describe(checkered);
    EXPECT_GT(checkered.highest, 0.99) << GetParam().name() << ": the clear cells cast a shadow; " << describe(checkered);
    // B is cut out everywhere: its shadow's place, and the floor seen through B, are lit.
    const RegionVisibility clear = visibility(frame.hdr, scene.camera, 0.55f, 1.95f, -0.45f, 0.45f);
    EXPECT_GT(clear.pixels, 100u);
    EXPECT_GT(clear.lowest, 0.99) << GetParam().name() << ": a fully cut-out caster casts a shadow; " << describe(clear);
}

// The map against the ray-traced truth (GiReference::lightVisibility, whose shadow rays pass
// where the alpha test discards): only the shadows' outlines may differ (the PCF kernel's blur).
TEST_P(MaskedShadowTest, TheShadowMapMatchesTheRayTracedVisibility) {
    const Scene scene = maskedCasters();
    const test_support::FrameOutput frame = renderShadowView(scene);
    const GiReference reference(scene);
    const ImageRGBAF truth = reference.lightVisibility(scene.camera, test_support::kSize, test_support::kSize, scene.lights[0].direction);
    const VisibilityError error = compareVisibility(frame.hdr, truth);
    EXPECT_GT(error.compared, 10000u);
    // 128 px over 4 m: a pixel is 3 cm, the PCF kernel about 1.6 cm; the outlines are about 1.5 %
    // of the pixels, and any of them may fall either way.
    EXPECT_LT(error.wrongFraction, 0.02) << GetParam().name() << ": leaks " << error.leakFraction << ", false shadows "
                                         << error.falseShadowFraction;
    EXPECT_LT(error.meanAbsolute, 0.015) << GetParam().name();
}

INSTANTIATE_TEST_SUITE_P(Configs, MaskedShadowTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

// The reference alone (CPU): its shadow rays and its other rays pass where the alpha test
// discards. They stopped at every masked surface before, whatever its alpha.
TEST(MaskedReference, RaysPassWhereTheAlphaTestDiscards) {
    const Scene scene = maskedCasters();
    const GiReference reference(scene);
    const ImageRGBAF truth = reference.lightVisibility(scene.camera, test_support::kSize, test_support::kSize, scene.lights[0].direction);
    const RegionVisibility checkered = visibility(truth, scene.camera, -0.45f, -0.05f, -0.45f, 0.45f);
    EXPECT_NEAR(checkered.mean, 0.5, 0.1) << describe(checkered);
    const RegionVisibility clear = visibility(truth, scene.camera, 0.55f, 1.95f, -0.45f, 0.45f);
    EXPECT_EQ(clear.lowest, 1.0) << describe(clear);
    // Looking straight down through B at the open floor: the floor's light (albedo 0.6 / pi x the
    // sun's 3 lux at 45 degrees), not B's blue.
    const glm::dvec3 seen = reference.incidentRadiance(glm::vec3(0.7f, 2.0f, 0.1f), glm::vec3(0.0f, -1.0f, 0.0f), 1, 1);
    const double floor = 0.6 / 3.14159265358979 * 3.0 * std::sqrt(0.5);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(seen[c], floor, 1e-3 * floor) << "channel " << c;
}

}  // namespace
}  // namespace janus::renderer
