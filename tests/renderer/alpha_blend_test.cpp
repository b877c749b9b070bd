// alphaMode BLEND: the transparent pass (docs/LIGHTING.md, "Transparent surfaces"). Blended
// instances are left out of the prepass, the forward pass and the shadow map, then drawn after
// the sky, back to front per instance, depth tested without depth writes, premultiplied alpha,
// lit like everything else. On every configuration.
//
// Most scenes here are emissive quads with no light and no ambient: their radiance is exactly
// the emissive colour, so blended pixels have analytic values (0.5 and 0.25 are exact in fp16).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/packing.hpp>

#include "janus/renderer/light_grid.h"
#include "janus/renderer/renderer.h"
#include "janus/renderer/scene_view.h"
#include "renderer/renderer_test_support.h"
#include "scene/scene_internal.h"

namespace janus::renderer {
namespace {

namespace fs = std::filesystem;
using test_support::Config;
using test_support::FrameOutput;
using test_support::kSize;

const glm::vec3 kRed(1.0f, 0.0f, 0.0f), kGreen(0.0f, 1.0f, 0.0f), kBlue(0.0f, 0.0f, 1.0f);

// A camera at z = 4 looking at the origin; no light, no ambient: surfaces show their emission.
Scene stage(const char* name) {
    Scene scene;
    scene.name = name;
    scene.camera.position = {0.0f, 0.0f, 4.0f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    scene.camera.fovYRadians = glm::radians(50.0f);
    scene.camera.nearPlane = 0.1f;
    scene.camera.farPlane = 50.0f;
    scene.environment.ambientColor = glm::vec3(0.0f);
    return scene;
}

int32_t addEmissive(Scene& scene, const std::string& name, glm::vec3 emissive, float alpha, AlphaMode mode, bool doubleSided = false) {
    Material material;
    material.name = name;
    material.baseColorFactor = glm::vec4(0.0f, 0.0f, 0.0f, alpha);
    material.metallicFactor = 0.0f;
    material.roughnessFactor = 1.0f;
    material.emissiveFactor = emissive;
    material.alphaMode = mode;
    material.doubleSided = doubleSided;
    scene.materials.push_back(material);
    return int32_t(scene.materials.size() - 1);
}

// A quad in the xy plane facing +z (towards the camera), centred at `center`.
void addQuad(Scene& scene, int32_t material, glm::vec3 center, glm::vec2 halfSize, float turnY = 0.0f) {
    scene.meshes.push_back(detail::makeQuad(material));
    const glm::mat4 world = glm::translate(glm::mat4(1.0f), center) * glm::rotate(glm::mat4(1.0f), turnY, glm::vec3(0, 1, 0)) *
                            glm::scale(glm::mat4(1.0f), glm::vec3(halfSize, 1.0f));
    scene.instances.push_back(Instance{uint32_t(scene.meshes.size() - 1), world});
}

// The pixel the scene camera shows `world` in (row 0 on top).
glm::uvec2 pixelOf(const Scene& scene, glm::vec3 world, uint32_t size = kSize) {
    const SceneView view = makeCameraView(scene.camera, size, size);
    const glm::vec4 clip = view.viewProjection() * glm::vec4(world, 1.0f);
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    return glm::uvec2(glm::floor((ndc * 0.5f + 0.5f) * float(size)));
}

glm::vec4 hdrAt(const ImageRGBAF& image, glm::uvec2 p) {
    const size_t i = (size_t(p.y) * image.width + p.x) * 4;
    return {image.pixels[i], image.pixels[i + 1], image.pixels[i + 2], image.pixels[i + 3]};
}

// The HDR radiance where the camera sees `world` is `expected` (and alpha stays 1).
void expectRadianceAt(const FrameOutput& output, const Scene& scene, glm::vec3 world, glm::vec3 expected, const std::string& label) {
    const glm::uvec2 p = pixelOf(scene, world, output.hdr.width);
    const glm::vec4 actual = hdrAt(output.hdr, p);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(actual[c], expected[c], 1e-3f) << label << ": pixel (" << p.x << ", " << p.y << ") channel " << c;
    EXPECT_NEAR(actual.a, 1.0f, 1e-3f) << label << ": alpha of pixel (" << p.x << ", " << p.y << ")";
}

std::vector<std::string> passNames(const FrameReport& report) {
    std::vector<std::string> names;
    for (const PassReport& pass : report.passes) names.push_back(pass.name);
    return names;
}

// The draws of the report's pass `name`; a failure (and -1) when there is no such pass.
int64_t drawsOf(const FrameReport& report, const std::string& name) {
    auto it = std::find_if(report.passes.begin(), report.passes.end(), [&](const PassReport& p) { return p.name == name; });
    if (it != report.passes.end()) return int64_t(it->draws);
    ADD_FAILURE() << "no pass '" << name << "' in " << test_support::passNames(report);
    return -1;
}

RenderSettings plainSettings(uint32_t size = kSize) {
    RenderSettings settings;
    settings.width = settings.height = size;
    return settings;
}

class AlphaBlendTest : public testing::TestWithParam<Config> {
protected:
    const Config& config() const { return GetParam(); }
    std::string tonemap() const { return config().path == FeaturePath::Compute ? "tonemap-compute" : "tonemap-fallback"; }
};

// A half-transparent blue quad in front of an opaque red one: where both are, 0.5 blue + 0.5 red;
// where the blue one is over the black background, half blue. Drawn opaque (before the pass
// existed) it was plain blue there.
TEST_P(AlphaBlendTest, ABlendedQuadCompositesOverOpaqueSurfacesAndTheBackground) {
    Scene scene = stage("blue over red");
    addQuad(scene, addEmissive(scene, "red", kRed, 1.0f, AlphaMode::Opaque), {-0.5f, 0.0f, -1.0f}, {0.8f, 0.8f});
    addQuad(scene, addEmissive(scene, "blue glass", kBlue, 0.5f, AlphaMode::Blend), {0.5f, 0.0f, 0.0f}, {0.8f, 0.8f});
    const FrameOutput output = test_support::renderOneFrame(config(), scene, plainSettings());
    const std::string label = config().name();
    expectRadianceAt(output, scene, {0.0f, 0.0f, 0.0f}, 0.5f * kBlue + 0.5f * kRed, label + " blue over red");
    expectRadianceAt(output, scene, {1.0f, 0.0f, 0.0f}, 0.5f * kBlue, label + " blue over the background");
    expectRadianceAt(output, scene, {-1.0f, 0.0f, -1.0f}, kRed, label + " red alone");
    expectRadianceAt(output, scene, {0.0f, 1.5f, 0.0f}, glm::vec3(0.0f), label + " background");
    EXPECT_EQ(passNames(output.report), (std::vector<std::string>{"forward", "transparent", tonemap()}))
        << test_support::passNames(output.report);
    EXPECT_EQ(drawsOf(output.report, "forward"), 1);
    EXPECT_EQ(drawsOf(output.report, "transparent"), 1);
}

// Blended instances composite back to front whatever their order in the scene: a near green
// quad listed before a far blue one still ends up on top. Instances at the same depth keep
// scene order (the later one on top).
TEST_P(AlphaBlendTest, BlendedInstancesCompositeBackToFrontAndTiesKeepSceneOrder) {
    Scene scene = stage("order");
    addQuad(scene, addEmissive(scene, "red", kRed, 1.0f, AlphaMode::Opaque), {0.0f, 0.0f, -1.0f}, {2.0f, 2.0f});
    addQuad(scene, addEmissive(scene, "near green", kGreen, 0.5f, AlphaMode::Blend), {0.0f, -0.6f, 0.5f}, {0.5f, 0.5f});
    addQuad(scene, addEmissive(scene, "far blue", kBlue, 0.5f, AlphaMode::Blend), {0.0f, -0.6f, 0.0f}, {0.5f, 0.5f});
    const glm::vec3 yellow(1.0f, 1.0f, 0.0f), cyan(0.0f, 1.0f, 1.0f);
    addQuad(scene, addEmissive(scene, "yellow", yellow, 0.5f, AlphaMode::Blend), {0.0f, 0.9f, -0.5f}, {0.5f, 0.5f});
    addQuad(scene, addEmissive(scene, "cyan", cyan, 0.5f, AlphaMode::Blend), {0.0f, 0.9f, -0.5f}, {0.5f, 0.5f});
    const FrameOutput output = test_support::renderOneFrame(config(), scene, plainSettings());
    const std::string label = config().name();
    // green over (blue over red) = (0.25, 0.5, 0.25); the scene's order would give (0.25, 0.25, 0.5).
    expectRadianceAt(output, scene, {0.0f, -0.6f, 0.0f}, 0.5f * kGreen + 0.25f * kBlue + 0.25f * kRed, label + " back to front");
    // cyan over (yellow over red) = (0.5, 0.75, 0.5); the other way round (0.75, 0.75, 0.25).
    expectRadianceAt(output, scene, {0.0f, 0.9f, -0.5f}, 0.5f * cyan + 0.25f * yellow + 0.25f * kRed, label + " tie");
    EXPECT_EQ(drawsOf(output.report, "transparent"), 4);
}

// Depth test on, depth writes off: a blended quad behind an opaque one is hidden by it, and the
// depth buffer holds only the opaque surfaces.
TEST_P(AlphaBlendTest, ABlendedQuadBehindAnOpaqueOneIsHiddenAndWritesNoDepth) {
    Scene scene = stage("blue behind red");
    addQuad(scene, addEmissive(scene, "red", kRed, 1.0f, AlphaMode::Opaque), {0.0f, 0.0f, 0.0f}, {0.8f, 0.8f});
    addQuad(scene, addEmissive(scene, "blue glass", kBlue, 0.5f, AlphaMode::Blend), {0.0f, 0.0f, -1.0f}, {2.0f, 2.0f});
    const FrameOutput output = test_support::renderOneFrame(config(), scene, plainSettings(), {.depth = true});
    const std::string label = config().name();
    expectRadianceAt(output, scene, {0.0f, 0.0f, 0.0f}, kRed, label + " red in front");
    expectRadianceAt(output, scene, {0.0f, 1.3f, -1.0f}, 0.5f * kBlue, label + " blue beside red");
    // Where only the blended quad is, the depth is still the cleared far plane.
    const glm::uvec2 beside = pixelOf(scene, {0.0f, 1.3f, -1.0f});
    EXPECT_EQ(output.depth.at(size_t(beside.y) * kSize + beside.x), 1.0f) << label;
    const glm::uvec2 centre = pixelOf(scene, {0.0f, 0.0f, 0.0f});
    EXPECT_LT(output.depth.at(size_t(centre.y) * kSize + centre.x), 1.0f) << label;
}

// Double-sided blended instances draw their back faces, then their front faces (two draws);
// single-sided ones are back-face culled like opaque ones.
TEST_P(AlphaBlendTest, DoubleSidedBlendedMeshesShowTheirBackFaces) {
    Scene scene = stage("double-sided");
    // Both quads turned away from the camera.
    addQuad(scene, addEmissive(scene, "double-sided", kBlue, 0.5f, AlphaMode::Blend, true), {-1.0f, 0.8f, 0.0f}, {0.4f, 0.4f},
            glm::pi<float>());
    addQuad(scene, addEmissive(scene, "single-sided", kBlue, 0.5f, AlphaMode::Blend, false), {1.0f, 0.8f, 0.0f}, {0.4f, 0.4f},
            glm::pi<float>());
    // Closed boxes: the double-sided one shows its far side through its near side.
    const int32_t glassBox = addEmissive(scene, "double-sided box", kGreen, 0.5f, AlphaMode::Blend, true);
    const int32_t plainBox = addEmissive(scene, "single-sided box", kGreen, 0.5f, AlphaMode::Blend, false);
    scene.meshes.push_back(detail::makeBox(glassBox));
    scene.instances.push_back(Instance{uint32_t(scene.meshes.size() - 1),
                                       glm::translate(glm::mat4(1.0f), {-1.0f, -0.8f, 0.0f}) * glm::scale(glm::mat4(1.0f), glm::vec3(0.3f))});
    scene.meshes.push_back(detail::makeBox(plainBox));
    scene.instances.push_back(Instance{uint32_t(scene.meshes.size() - 1),
                                       glm::translate(glm::mat4(1.0f), {1.0f, -0.8f, 0.0f}) * glm::scale(glm::mat4(1.0f), glm::vec3(0.3f))});
    const FrameOutput output = test_support::renderOneFrame(config(), scene, plainSettings());
    const std::string label = config().name();
    expectRadianceAt(output, scene, {-1.0f, 0.8f, 0.0f}, 0.5f * kBlue, label + " double-sided quad from behind");
    expectRadianceAt(output, scene, {1.0f, 0.8f, 0.0f}, glm::vec3(0.0f), label + " single-sided quad from behind");
    // Front face over back face over black: 0.5 g + 0.5 * 0.5 g.
    expectRadianceAt(output, scene, {-1.0f, -0.8f, 0.3f}, 0.75f * kGreen, label + " double-sided box");
    expectRadianceAt(output, scene, {1.0f, -0.8f, 0.3f}, 0.5f * kGreen, label + " single-sided box");
    // Two quads and two boxes; each double-sided one draws twice.
    EXPECT_EQ(drawsOf(output.report, "transparent"), 6);
}

// The pass exists only for scenes with blended instances; blended instances are in neither the
// shadow map nor the forward pass nor the depth prepass.
TEST_P(AlphaBlendTest, TheTransparentPassExistsOnlyWithBlendedMaterials) {
    Scene scene = stage("pass list");
    addQuad(scene, addEmissive(scene, "red", kRed, 1.0f, AlphaMode::Opaque), {0.0f, 0.0f, -1.0f}, {2.0f, 2.0f});
    const int32_t glass = addEmissive(scene, "blue glass", kBlue, 0.5f, AlphaMode::Blend);
    addQuad(scene, glass, {0.0f, 0.0f, 0.0f}, {0.5f, 0.5f});
    Light sun;
    sun.direction = glm::normalize(glm::vec3(0.2f, -0.3f, -1.0f));
    scene.lights.push_back(sun);
    const std::string tonemapPass = tonemap();

    const FrameOutput blended = test_support::renderOneFrame(config(), scene, plainSettings());
    EXPECT_EQ(passNames(blended.report), (std::vector<std::string>{"shadow-map", "forward", "transparent", tonemapPass}))
        << test_support::passNames(blended.report);
    EXPECT_EQ(drawsOf(blended.report, "shadow-map"), 1);   // the blended quad casts no shadow
    EXPECT_EQ(drawsOf(blended.report, "forward"), 1);
    EXPECT_EQ(drawsOf(blended.report, "transparent"), 1);

    Scene opaque = scene;
    opaque.materials[size_t(glass)].alphaMode = AlphaMode::Opaque;
    const FrameOutput plain = test_support::renderOneFrame(config(), opaque, plainSettings());
    EXPECT_EQ(passNames(plain.report), (std::vector<std::string>{"shadow-map", "forward", tonemapPass}))
        << test_support::passNames(plain.report);
    EXPECT_EQ(drawsOf(plain.report, "shadow-map"), 2);
    EXPECT_EQ(drawsOf(plain.report, "forward"), 2);

    Scene masked = scene;
    masked.materials[size_t(glass)].alphaMode = AlphaMode::Mask;
    EXPECT_FALSE(test_support::hasPassStartingWith(test_support::renderOneFrame(config(), masked, plainSettings()).report, "transparent"));

    // Nothing but blended meshes: nothing casts a shadow, so there is no shadow map.
    Scene onlyGlass = scene;
    onlyGlass.instances.erase(onlyGlass.instances.begin());
    const FrameOutput glassOnly = test_support::renderOneFrame(config(), onlyGlass, plainSettings());
    EXPECT_EQ(passNames(glassOnly.report), (std::vector<std::string>{"forward", "transparent", tonemapPass}))
        << test_support::passNames(glassOnly.report);

    // Tiled culling: the prepass draws only the opaque quad.
    Scene tiled = scene;
    tiled.lights.push_back(test_support::pointLight({0.0f, 0.0f, 0.5f}, glm::vec3(1.0f), 2.0f, 3.0f));
    const FrameOutput tiledOutput = test_support::renderOneFrame(config(), tiled, test_support::settingsFor(LightCulling::TilesDepth));
    const std::string cull = config().path == FeaturePath::Compute ? "light-cull-compute" : "light-cull-cpu";
    EXPECT_EQ(passNames(tiledOutput.report),
              (std::vector<std::string>{"shadow-map", "depth-prepass", cull, "forward", "transparent", tonemapPass}))
        << test_support::passNames(tiledOutput.report);
    EXPECT_EQ(drawsOf(tiledOutput.report, "depth-prepass"), 1);
}

// Lit like everything else: a blended surface under the directional light (with the shadow
// map), a point light, the sky's image-based light and over the sky background equals its own
// radiance (rendered opaque) blended over what is behind it (rendered without it):
// alpha * opaque + (1 - alpha) * behind, at every pixel. It casts no shadow on the wall behind.
TEST_P(AlphaBlendTest, ABlendedSurfaceIsLitLikeAnOpaqueOneAndBlendsOverTheSky) {
    Scene scene = stage("lit glass");
    scene.environment.map = fs::path(JANUS_SHARED_SCENES_DIR) / "env" / "chinese_garden_1k.hdr";
    Material wall;
    wall.name = "wall";
    wall.baseColorFactor = {0.8f, 0.3f, 0.2f, 1.0f};
    wall.metallicFactor = 0.0f;
    wall.roughnessFactor = 0.7f;
    scene.materials.push_back(wall);
    Material glass = wall;
    glass.name = "glass";
    glass.baseColorFactor = {0.1f, 0.3f, 0.9f, 0.4f};
    glass.roughnessFactor = 0.3f;
    glass.alphaMode = AlphaMode::Blend;
    scene.materials.push_back(glass);
    addQuad(scene, 0, {-0.4f, 0.0f, -1.0f}, {1.2f, 1.2f});
    addQuad(scene, 1, {0.7f, 0.0f, 0.0f}, {0.7f, 0.7f});   // its right part is in front of the sky
    Light sun;
    sun.direction = glm::normalize(glm::vec3(0.3f, -0.4f, -1.0f));   // from behind the camera: the glass would shadow the wall
    sun.intensity = 2.0f;
    scene.lights.push_back(sun);
    scene.lights.push_back(test_support::pointLight({0.3f, 0.5f, 1.0f}, glm::vec3(1.0f, 0.9f, 0.8f), 3.0f, 4.0f));

    Scene opaque = scene;
    opaque.materials[1].alphaMode = AlphaMode::Opaque;
    Scene behind = scene;
    behind.instances.pop_back();
    const FrameOutput blended = test_support::renderOneFrame(config(), scene, plainSettings());
    const FrameOutput front = test_support::renderOneFrame(config(), opaque, plainSettings(), {.depth = true});
    const FrameOutput back = test_support::renderOneFrame(config(), behind, plainSettings(), {.depth = true});
    EXPECT_EQ(passNames(blended.report).at(passNames(blended.report).size() - 2), "transparent")
        << test_support::passNames(blended.report);
    EXPECT_TRUE(test_support::hasPassStartingWith(blended.report, "sky"));

    const float alpha = glass.baseColorFactor.a;
    size_t covered = 0, overSky = 0, bad = 0;
    std::string first;
    const glm::uvec2 skyPixel = pixelOf(scene, {1.3f, 0.0f, 0.0f});   // right of the wall: the glass over the sky
    for (uint32_t y = 0; y < kSize; ++y)
        for (uint32_t x = 0; x < kSize; ++x) {
            const glm::vec4 b = hdrAt(back.hdr, {x, y}), f = hdrAt(front.hdr, {x, y}), actual = hdrAt(blended.hdr, {x, y});
            // Where the opaque glass is nearer than what is behind it. (Not where the images
            // differ: the opaque glass also shadows the wall beside it.)
            const size_t pixel = size_t(y) * kSize + x;
            const bool glassHere = front.depth.at(pixel) < back.depth.at(pixel);
            const glm::vec3 expected = glassHere ? alpha * glm::vec3(f) + (1.0f - alpha) * glm::vec3(b) : glm::vec3(b);
            covered += glassHere;
            if (glassHere && x == skyPixel.x && y == skyPixel.y) ++overSky;
            for (int c = 0; c < 3; ++c)
                if (!(std::abs(actual[c] - expected[c]) <= 2e-3f * std::abs(expected[c]) + 1e-4f) && bad++ == 0)
                    first = fmt::format("pixel ({}, {}) channel {}: expected {} = {} * {} + {} * {}, got {}", x, y, c, expected[c], alpha,
                                        f[c], 1.0f - alpha, b[c], actual[c]);
        }
    EXPECT_EQ(bad, 0u) << config().name() << ": blended radiance differs from alpha * opaque + (1 - alpha) * behind; first at "
                       << first;
    EXPECT_GT(covered, 1000u) << config().name();
    EXPECT_EQ(overSky, 1u) << config().name() << ": the glass is not in front of the sky where the test expects it";
}

// Forward+ with depth bounds: blended surfaces are not in the prepass depth, so the lists reach
// from the near plane (TileGrid::rangeFromNearPlane) and tiles without depth list the lights
// too. A short-range light next to the glass, far in front of the wall, lights it exactly as the
// naive loop does, also where no opaque surface is behind it.
TEST_P(AlphaBlendTest, TiledCullingListsTheLightsOfBlendedSurfacesInFrontOfTheDepth) {
    Scene scene = stage("tiled glass");
    scene.environment.ambientColor = glm::vec3(0.02f);
    Material wall;
    wall.baseColorFactor = {0.7f, 0.7f, 0.7f, 1.0f};
    wall.metallicFactor = 0.0f;
    wall.roughnessFactor = 0.8f;
    scene.materials.push_back(wall);
    Material glass = wall;
    glass.baseColorFactor = {0.9f, 0.9f, 0.9f, 0.5f};
    glass.alphaMode = AlphaMode::Blend;
    scene.materials.push_back(glass);
    addQuad(scene, 0, {-1.0f, 0.0f, -8.0f}, {2.0f, 4.0f});   // far wall on the left half
    addQuad(scene, 1, {0.0f, 0.0f, 0.0f}, {1.2f, 1.2f});     // glass half over the wall, half over nothing
    for (int i = 0; i < 9; ++i) {
        const float x = -1.0f + 1.0f * float(i % 3), y = -1.0f + 1.0f * float(i / 3);
        scene.lights.push_back(test_support::pointLight({x, y, 0.4f}, glm::vec3(1.0f, 0.8f, 0.6f), 2.0f, 0.9f));
    }
    const FrameOutput naive = test_support::renderOneFrame(config(), scene, test_support::settingsFor(LightCulling::Naive));
    const FrameOutput tiled = test_support::renderOneFrame(config(), scene, test_support::settingsFor(LightCulling::TilesDepth));
    ASSERT_TRUE(tiled.report.lightCulling.has_value());
    EXPECT_EQ(tiled.report.lightCulling->mode, LightCulling::TilesDepth);
    // The lights reach the glass: the glass is brighter than with ambient light only.
    const glm::vec4 lit = hdrAt(naive.hdr, pixelOf(scene, {0.5f, 0.5f, 0.0f}));
    EXPECT_GT(lit.r, 0.03f) << config().name();
    test_support::expectSameImage(naive, tiled, fmt::format("tiled-glass-{}", config().name()));
}

// Cube captures draw blended instances too, per face with the face's (mirrored) winding.
TEST_P(AlphaBlendTest, CubeCapturesDrawBlendedInstances) {
    rhi::IDevice& device = test_support::deviceFor(config().backend);
    device.takeDebugMessages();
    Scene scene = stage("capture");
    // Seen from the origin looking down -z: an opaque red quad at z = -2 behind a blue glass at -1.
    addQuad(scene, addEmissive(scene, "red", kRed, 1.0f, AlphaMode::Opaque), {0.0f, 0.0f, -2.0f}, {3.0f, 3.0f});
    addQuad(scene, addEmissive(scene, "blue glass", kBlue, 0.5f, AlphaMode::Blend), {0.0f, 0.0f, -1.0f}, {3.0f, 3.0f});
    constexpr uint32_t kFace = 32;
    const rhi::TextureHandle cube = device.createTexture(rhi::TextureDesc{}
                                                             .setDimension(rhi::TextureDimension::TextureCube)
                                                             .setFormat(rhi::Format::RGBA16_FLOAT)
                                                             .setSize(kFace, kFace)
                                                             .setUsage(rhi::TextureUsage::RenderTarget | rhi::TextureUsage::Sampled)
                                                             .setDebugName("capture cube"));
    FrameReport report;
    {
        RenderSettings settings = plainSettings(kFace);
        settings.path = config().path;
        Renderer renderer(device, scene, settings);
        CubeCaptureDesc capture;
        capture.position = glm::vec3(0.0f);
        capture.nearPlane = 0.1f;
        capture.farPlane = 50.0f;
        capture.target = cube;
        report = renderer.renderCubeCapture(capture);
    }
    std::vector<std::string> transparentViews;
    for (const PassReport& pass : report.passes)
        if (pass.name == "transparent") transparentViews.push_back(pass.view);
    EXPECT_EQ(transparentViews, (std::vector<std::string>{"cube +X", "cube -X", "cube +Y", "cube -Y", "cube +Z", "cube -Z"}))
        << test_support::passNames(report);
    // Face -Z (layer 5), centre: blue over red; face +Z (layer 4): nothing.
    auto centre = [&](uint32_t face) {
        const std::vector<std::byte> bytes = device.readTexture(cube, {0, face});
        std::vector<float> values(bytes.size() / 2);
        for (size_t i = 0; i < values.size(); ++i) {
            uint16_t half;
            std::memcpy(&half, bytes.data() + i * 2, 2);
            values[i] = glm::unpackHalf1x16(half);
        }
        const size_t i = (size_t(kFace / 2) * kFace + kFace / 2) * 4;
        return glm::vec3(values.at(i), values.at(i + 1), values.at(i + 2));
    };
    const glm::vec3 minusZ = centre(5), plusZ = centre(4);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(minusZ[c], (0.5f * kBlue + 0.5f * kRed)[c], 1e-3f) << config().name() << " channel " << c;
        EXPECT_NEAR(plusZ[c], 0.0f, 1e-3f) << config().name() << " channel " << c;
    }
    const std::vector<rhi::DebugMessage> messages = device.takeDebugMessages();
    EXPECT_TRUE(messages.empty()) << config().name() << ":" << test_support::joinMessages(messages);
}

INSTANTIATE_TEST_SUITE_P(Configs, AlphaBlendTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

// ---- Parity: the same transparent scenes on the five configurations ---------------------------

// The many-lights hall with glass boxes (one double-sided) under tiled culling with depth bounds
// (the compute builder against the CPU builder), and the probes scene with a glass pane, whose
// probe captures draw it too.
Scene manyLightsWithGlass() {
    Scene scene = manyLightsScene(ManyLightsOptions{.lightCount = 64});
    int boxes = 0;
    for (Material& material : scene.materials)
        if (material.name.starts_with("box ")) {
            if (boxes++ % 2 == 1) continue;
            material.alphaMode = AlphaMode::Blend;
            material.baseColorFactor.a = 0.45f;
            material.doubleSided = boxes == 1;
        }
    // The boxes stand on the floor: a double-sided glass box's bottom face would be coplanar with
    // it, and which of two coplanar surfaces passes the depth test differs between rasterisers.
    for (Instance& instance : scene.instances) {
        const int32_t material = scene.meshes[instance.mesh].material;
        if (material >= 0 && scene.materials[size_t(material)].alphaMode == AlphaMode::Blend)
            instance.world = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.02f, 0.0f)) * instance.world;
    }
    return scene;
}

Scene probesWithGlass() {
    Scene scene = probesScene();
    for (ReflectionProbe& probe : scene.reflectionProbes) {
        probe.update = ProbeUpdate::Once;
        probe.timeSlicing = ProbeTimeSlicing::None;
    }
    Material glass;
    glass.name = "glass";
    glass.baseColorFactor = {0.2f, 0.9f, 0.4f, 0.5f};
    glass.metallicFactor = 0.0f;
    glass.roughnessFactor = 0.05f;
    glass.alphaMode = AlphaMode::Blend;
    glass.doubleSided = true;
    scene.materials.push_back(glass);
    // A pane standing in the alcove's right half (inside both probes' boxes), reaching above its
    // walls (in front of the sky); the probes' captures see it from behind.
    scene.meshes.push_back(detail::makeQuad(int32_t(scene.materials.size() - 1)));
    scene.instances.push_back(Instance{uint32_t(scene.meshes.size() - 1),
                                       glm::translate(glm::mat4(1.0f), {0.8f, 1.6f, 0.2f}) *
                                           glm::rotate(glm::mat4(1.0f), 0.4f, glm::vec3(0, 1, 0)) *
                                           glm::scale(glm::mat4(1.0f), glm::vec3(0.6f, 1.4f, 1.0f))});
    return scene;
}

struct ParityCase {
    const char* name;
    Scene (*make)();
    LightCulling culling;
};
void PrintTo(const ParityCase& c, std::ostream* os) { *os << c.name; }

const ParityCase kParityCases[] = {
    {"ManyLightsGlass", manyLightsWithGlass, LightCulling::TilesDepth},
    {"ProbesGlass", probesWithGlass, LightCulling::Auto},
};

class AlphaBlendParity : public testing::TestWithParam<std::tuple<ParityCase, Config>> {};

TEST_P(AlphaBlendParity, MatchesVulkanComputeWithinOneStep) {
    const ParityCase& parity = std::get<0>(GetParam());
    const Config& config = std::get<1>(GetParam());
    const Scene scene = parity.make();
    static std::map<std::string, FrameOutput> references;
    auto it = references.find(parity.name);
    if (it == references.end())
        it = references.emplace(parity.name, test_support::renderOneFrame(test_support::allConfigs()[0], scene,
                                                                          test_support::settingsFor(parity.culling)))
                 .first;
    const FrameOutput& reference = it->second;
    const FrameOutput result = test_support::renderOneFrame(config, scene, test_support::settingsFor(parity.culling));
    test_support::expectFiniteHdr(result.hdr, config.name());
    // The main view's pass, and one per face of each probe capture.
    const auto transparentPasses = std::count_if(result.report.passes.begin(), result.report.passes.end(),
                                                 [](const PassReport& pass) { return pass.name == "transparent"; });
    EXPECT_EQ(size_t(transparentPasses), 1 + 6 * scene.reflectionProbes.size()) << test_support::passNames(result.report);
    // As the other parity tests: at most one 8-bit step, except a handful of silhouette pixels
    // (GL and Vulkan break rasterisation ties with opposite y).
    constexpr uint64_t kMaxSilhouettePixels = 4;
    const ImageDifference diff = compareImages(reference.display, result.display, 1);
    if (diff.differingPixels > kMaxSilhouettePixels) {
        const fs::path dir = test_support::outputDir();
        writePNG(dir / fmt::format("{}-{}.png", parity.name, config.name()), result.display);
        writePNG(dir / fmt::format("{}-vulkan_compute.png", parity.name), reference.display);
        writePNG(dir / fmt::format("{}-{}-diff.png", parity.name, config.name()), differenceHeatmap(reference.display, result.display));
        ADD_FAILURE() << config.name() << " differs from vulkan/compute by more than 1 step in " << diff.differingPixels
                      << " pixels (up to " << diff.maxChannelDifference << " steps); images in " << dir;
    }
}

INSTANTIATE_TEST_SUITE_P(Configs, AlphaBlendParity, testing::Combine(testing::ValuesIn(kParityCases), testing::ValuesIn(test_support::allConfigs())),
                         [](const testing::TestParamInfo<std::tuple<ParityCase, Config>>& info) {
                             return fmt::format("{}_{}", std::get<0>(info.param).name, std::get<1>(info.param).name());
                         });

}  // namespace
}  // namespace janus::renderer
