// Probe GI (docs/GI.md): scene parsing, the bake's SH transfer math (CPU), and on every
// configuration: analytic irradiance in an emissive box, bricks = per-surfel, negative
// coefficients survive the volume's encoding, colour bleeding and parity on the cornell box,
// relight only when needed, the multi-frame schedule, hard cases that must stay finite.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <utility>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "core/gpu_scene.h"
#include "gi/gi_bake.h"
#include "gi/gi_bake_file.h"
#include "ibl/cube_geometry.h"
#include "ibl/spherical_harmonics.h"
#include "janus/renderer/gi_reference.h"
#include "janus/renderer/light_grid.h"
#include "janus/renderer/renderer.h"
#include "renderer/renderer_test_support.h"
#include "scene/scene_internal.h"

namespace janus::renderer {
namespace {

namespace fs = std::filesystem;
using test_support::Config;

const fs::path kCornellBox = fs::path(JANUS_SHARED_SCENES_DIR) / "cornell-box" / "cornellBox.gltf";

fs::path writeSceneFile(const std::string& name, const std::string& volume) {
    const fs::path path = test_support::outputDir() / fmt::format("gi-{}.json", name);
    std::ofstream(path) << fmt::format(R"({{"gltf": "{}", "irradianceVolume": {}}})", kCornellBox.generic_string(), volume);
    return path;
}

// ---- Scenes -------------------------------------------------------------------------------

TEST(IrradianceVolumeScenes, ASceneFileGivesEveryField) {
    const Scene scene = loadScene(writeSceneFile("full", R"({"name": "hall", "bounds": {"min": [-1, 0, -1], "max": [1, 2, 1]},
        "probes": [2, 3, 4], "surfelsPerProbe": 128, "brickSize": 0.25, "bricks": false, "bounces": 3, "shOrder": 1,
        "probesPerFrame": 5, "normalBias": 0.05, "invalidBackFaceFraction": 0.3, "near": 0.02, "far": 9,
        "maxSurfelsPerBrick": 8, "parallelReduction": false, "relocateProbes": false,
        "visibility": false})"));
    ASSERT_TRUE(scene.irradianceVolume.has_value());
    const IrradianceVolume& v = *scene.irradianceVolume;
    EXPECT_EQ(v.name, "hall");
    EXPECT_EQ(v.bounds, (Box{{-1, 0, -1}, {1, 2, 1}}));
    EXPECT_EQ(v.probeCounts, glm::uvec3(2, 3, 4));
    EXPECT_EQ(v.surfelsPerProbe, 128u);
    EXPECT_FLOAT_EQ(v.brickSize, 0.25f);
    EXPECT_FALSE(v.bricks);
    EXPECT_EQ(v.bounces, 3u);
    EXPECT_EQ(v.shOrder, 1u);
    EXPECT_EQ(v.probesPerFrame, 5u);
    EXPECT_FLOAT_EQ(v.normalBias, 0.05f);
    EXPECT_FLOAT_EQ(v.invalidBackFaceFraction, 0.3f);
    EXPECT_FLOAT_EQ(v.nearPlane, 0.02f);
    EXPECT_FLOAT_EQ(v.farPlane, 9.0f);
    EXPECT_EQ(v.maxSurfelsPerBrick, 8u);
    EXPECT_FALSE(v.parallelReduction);
    EXPECT_FALSE(v.relocateProbes);
    EXPECT_FALSE(v.visibility);
    EXPECT_TRUE(IrradianceVolume{}.visibility) << "the test is on by default";
    // Spacing instead of counts: ceil(size / spacing) per axis.
    const Scene spaced = loadScene(writeSceneFile("spacing", R"({"bounds": {"min": [0, 0, 0], "max": [3, 1, 2]}, "spacing": 0.75})"));
    EXPECT_EQ(spaced.irradianceVolume->probeCounts, glm::uvec3(4, 2, 3));
}

TEST(IrradianceVolumeScenes, TheCornellBoxMarkerPlacesAVolumeOverTheScene) {
    const Scene scene = loadScene(kCornellBox);
    ASSERT_TRUE(scene.irradianceVolume.has_value());
    EXPECT_EQ(scene.irradianceVolume->name, "IrradianceVolume");
    const Box bounds = detail::sceneBounds(scene);
    EXPECT_TRUE(glm::all(glm::greaterThan(scene.irradianceVolume->bounds.min, bounds.min)));
    EXPECT_TRUE(glm::all(glm::lessThan(scene.irradianceVolume->bounds.max, bounds.max)));
}

TEST(IrradianceVolumeScenes, BadVolumesAreSceneErrorsNamingTheProblem) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {R"({"probes": [0, 2, 2]})", "probes along x"},
        {R"({"probes": 65})", "each axis needs 1 to 64"},
        {R"({"probes": [2, 2]})", "[x, y, z] counts"},
        {R"({"probes": 2, "spacing": 1})", "not both"},
        {R"({"spacing": 0})", "spacing must be"},
        {R"({"surfelsPerProbe": 8})", "8 surfels per probe"},
        {R"({"brickSize": -1})", "brick size -1"},
        {R"({"bounces": 0})", "0 bounces"},
        {R"({"maxSurfelsPerBrick": 0})", "maxSurfelsPerBrick"},
        {R"({"parallelReduction": 1})", "parallelReduction must be true or false"},
        {R"({"relocateProbes": "yes"})", "relocateProbes must be true or false"},
        {R"({"visibility": 0})", "visibility must be true or false"},
        {R"({"shOrder": 3})", "SH order 3"},
        {R"({"normalBias": -0.1})", "normal bias"},
        {R"({"invalidBackFaceFraction": 0})", "invalidBackFaceFraction"},
        {R"({"bounds": {"min": [1, 0, 0], "max": [0, 1, 1]}})", "above max"},
        {R"({"near": 2, "far": 1})", "0 < near < far"},
        {R"([1])", "must be an object"},
    };
    for (size_t i = 0; i < cases.size(); ++i) {
        try {
            loadScene(writeSceneFile(fmt::format("bad{}", i), cases[i].first));
            ADD_FAILURE() << cases[i].first << " was accepted";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(cases[i].second), std::string::npos) << e.what();
        }
    }
}

// ---- Bake math (CPU) ------------------------------------------------------------------------

TEST(GiBake, SampleDirectionsAreUnitAndBalanced) {
    const std::vector<glm::vec3> directions = giSampleDirections(256);
    glm::dvec3 sum(0.0);
    for (const glm::vec3& d : directions) {
        EXPECT_NEAR(glm::length(d), 1.0f, 1e-5f);
        sum += glm::dvec3(d);
    }
    EXPECT_LT(glm::length(sum) / 256.0, 0.01);   // evenly spread: no direction favoured
}

TEST(GiBake, CubeTexelOfInvertsTexelDirections) {
    for (uint32_t face = 0; face < 6; ++face)
        for (uint32_t y = 0; y < 8; ++y)
            for (uint32_t x = 0; x < 8; ++x) {
                const CubeTexel t = cubeTexelOf(cubeTexelDirection(face, x, y, 8), 8);
                EXPECT_EQ(t.face, face);
                EXPECT_EQ(t.x, x);
                EXPECT_EQ(t.y, y);
            }
}

TEST(GiBake, OctahedralMapsRoundTrip) {
    for (const glm::vec3& d : giSampleDirections(257)) {
        const glm::vec2 e = giOctahedralEncode(d);
        EXPECT_LE(std::abs(e.x) + 0.0f, 1.0f);
        EXPECT_LE(std::abs(e.y) + 0.0f, 1.0f);
        const glm::vec3 back = giOctahedralDecode(e);
        EXPECT_NEAR(glm::distance(back, d), 0.0f, 1e-5f) << d.x << " " << d.y << " " << d.z;
    }
}

// The visibility maps' moments: a probe at the centre of a cube room sees each wall at
// h / cos; a texel gets about the distance along its centre's direction (the lobe is about 10
// degrees wide), a mean square of at least the mean squared; a probe that sees one distance
// everywhere gets exactly it.
TEST(GiBake, DistanceMomentsAreTheLobeWeightedDistancesAroundEachTexel) {
    constexpr uint32_t kFace = 32;
    const GiDistanceMomentFilter filter(kFace);
    std::vector<float> constant(6 * kFace * kFace, 2.5f);
    for (const glm::vec2& m : filter.moments(constant)) {
        EXPECT_NEAR(m.x, 2.5f, 1e-5f);
        EXPECT_NEAR(m.y, 6.25f, 1e-4f);
    }
    const float h = 1.5f;
    std::vector<float> room(6 * kFace * kFace);
    for (uint32_t face = 0; face < 6; ++face)
        for (uint32_t y = 0; y < kFace; ++y)
            for (uint32_t x = 0; x < kFace; ++x) {
                const glm::dvec3 d = cubeTexelDirection(face, x, y, kFace);
                const double major = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
                room[(face * kFace + y) * kFace + x] = float(h / major);
            }
    const std::vector<glm::vec2> moments = filter.moments(room);
    ASSERT_EQ(moments.size(), size_t(kGiVisibilityResolution) * kGiVisibilityResolution);
    for (uint32_t t = 0; t < moments.size(); ++t) {
        const glm::vec2 centre = (glm::vec2(t % kGiVisibilityResolution, t / kGiVisibilityResolution) + 0.5f) /
                                     float(kGiVisibilityResolution) * 2.0f - 1.0f;
        const glm::vec3 d = giOctahedralDecode(centre);
        const float major = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
        const float expected = h / major;
        // Within 35 degrees of a wall's centre the distance is smooth under the lobe: within 4 %.
        // Towards the room's edges and corners the lobe averages across the distance's ridge.
        if (major > 0.82f) EXPECT_NEAR(moments[t].x, expected, 0.04f * expected) << "texel " << t;
        // Near a wall's centre the lobe's mean of h / cos is a little above h / cos at its axis.
        if (major > 0.95f) EXPECT_NEAR(moments[t].x, expected * 1.012f, 0.012f * expected) << "texel " << t;
        EXPECT_GE(moments[t].x, h) << "texel " << t;
        EXPECT_LE(moments[t].x, h * std::sqrt(3.0f)) << "texel " << t;
        EXPECT_GE(moments[t].y, moments[t].x * moments[t].x * (1.0f - 1e-5f)) << "texel " << t;
    }
    EXPECT_THROW(filter.moments(std::vector<float>(10, 1.0f)), RendererError);
}

IrradianceVolume oneProbeVolume(bool bricks) {
    IrradianceVolume v;
    v.bounds = Box{glm::vec3(-1.0f), glm::vec3(1.0f)};
    v.probeCounts = glm::uvec3(1);
    v.surfelsPerProbe = 1024;
    v.bricks = bricks;
    v.brickSize = 0.5f;
    return v;
}

// The probe's irradiance / pi SH from the bake with every brick at its surfels' mean emission:
// what the relight computes with no lights and no bounce.
ShRgb cpuIrradianceOverPi(const GiBake& bake, uint32_t probe) {
    ShRgb radiance{};
    for (uint32_t t = bake.probeFirstTransfer[probe]; t < bake.probeFirstTransfer[probe] + bake.probeTransferCount[probe]; ++t) {
        const GiTransfer& transfer = bake.transfers[t];
        const GiBrick& brick = bake.bricks[transfer.brick];
        glm::dvec3 mean(0.0);
        for (uint32_t s = brick.firstSurfel; s < brick.firstSurfel + brick.surfelCount; ++s) mean += glm::dvec3(bake.surfels[s].emission);
        if (brick.surfelCount) mean /= double(brick.surfelCount);
        for (size_t k = 0; k < 9; ++k) radiance[k] += mean * double(transfer.sh[k]);
    }
    return shConvolveIrradiance(radiance);
}

TEST(GiBake, OneBrightSurfelGivesTheClampedCosineLobe) {
    const IrradianceVolume volume = oneProbeVolume(true);
    const std::vector<glm::vec3> directions = giSampleDirections(volume.surfelsPerProbe);
    std::vector<GiSample> samples(directions.size());
    for (size_t i = 0; i < samples.size(); ++i) samples[i].direction = directions[i];   // sky (black: no brick radiance here)
    GiSample& bright = samples[37];
    bright.kind = GiSample::Kind::Surface;
    bright.position = bright.direction * 0.8f;
    bright.normal = -bright.direction;
    bright.emission = glm::vec3(1000.0f);
    const GiBake bake = buildGiBake(volume, {samples});
    const ShRgb sh = cpuIrradianceOverPi(bake, 0);
    // A radiance L over the sample's solid angle 4 pi / N from direction d: irradiance / pi =
    // L (4 pi / N) / pi * max(0, n.d), whose SH is (L (4 pi / N) / pi) * the clamped-cosine SH.
    const double scale = 1000.0 * (4.0 * 3.14159265358979 / volume.surfelsPerProbe) / 3.14159265358979;
    const ShRgb lobe = shClampedCosineRadiance(glm::dvec3(bright.direction), glm::dvec3(scale));
    for (size_t k = 0; k < 9; ++k) EXPECT_NEAR(sh[k].x, lobe[k].x, 1e-4 * scale) << "coefficient " << k;
}

// Bricks that hold light (a sky bin or surfels): a bake also keeps empty slots (giBrickSlot).
size_t bricksWithLight(const GiBake& bake) {
    return size_t(std::count_if(bake.bricks.begin(), bake.bricks.end(), [](const GiBrick& b) { return b.holdsLight(); }));
}

TEST(GiBake, BricksAndPerSurfelGiveTheSameShForTheSameSurfels) {
    // A uniformly emissive closed room: every surfel of a brick has the same radiance, so
    // grouping changes nothing but the number of terms.
    std::vector<GiSample> samples;
    for (const glm::vec3& d : giSampleDirections(512)) {
        GiSample s;
        s.kind = GiSample::Kind::Surface;
        s.direction = d;
        s.position = d / glm::max(glm::abs(d.x), glm::max(glm::abs(d.y), glm::abs(d.z)));   // on the cube |p| = 1
        s.normal = -d;
        s.emission = glm::vec3(2.0f, 1.0f, 0.5f);
        samples.push_back(s);
    }
    IrradianceVolume bricks = oneProbeVolume(true), perSurfel = oneProbeVolume(false);
    bricks.surfelsPerProbe = perSurfel.surfelsPerProbe = 512;
    const GiBake a = buildGiBake(bricks, {samples}), b = buildGiBake(perSurfel, {samples});
    EXPECT_LT(bricksWithLight(a), bricksWithLight(b));
    EXPECT_EQ(bricksWithLight(b), 512u);
    const ShRgb shA = cpuIrradianceOverPi(a, 0), shB = cpuIrradianceOverPi(b, 0);
    for (size_t k = 0; k < 9; ++k)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(shA[k][c], shB[k][c], 1e-5) << "coefficient " << k;
    // And the closed form: constant radiance E gives irradiance / pi = E for every normal.
    for (const glm::dvec3 n : {glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0), glm::normalize(glm::dvec3(1, 2, 3))})
        EXPECT_NEAR(shEvaluate(shA, n).x, 2.0, 0.02);
}

// Bricks bound the relight's work: sky samples share direction bins, a brick lights at most
// maxSurfelsPerBrick surfels; the per-surfel path keeps one brick per sample.
// A brick's surfels share its radiance, so they must be lit by the same lights: surfels of
// different rendering layers never share a brick, whatever their cell and normal.
// Bricks are placed so that those lit side by side keep about as many surfels: the ranks fill 4 x 4
// texel blocks, and a bake's bricks, read in rank order, keep ever fewer surfels. The fallback
// relight's fragments ran as long as the longest brick of their block (bricks were 1.9x slower
// there than on the compute path, per-surfel bricks as fast).
TEST(GiBake, BricksLitSideBySideKeepAboutAsManySurfels) {
    std::set<uint32_t> slots;
    for (uint32_t rank = 0; rank < 3 * 4096 + 100; ++rank) EXPECT_TRUE(slots.insert(giBrickSlot(rank)).second) << rank;
    for (uint32_t rank = 0; rank < 16; ++rank) {
        EXPECT_EQ(giBrickSlot(rank) % kGiBrickRowTexels, rank % 4) << rank;
        EXPECT_EQ(giBrickSlot(rank) / kGiBrickRowTexels, rank / 4) << rank;
    }
    EXPECT_EQ(giBrickSlot(16), 4u);
    EXPECT_EQ(giBrickSlot(4096), 4u * kGiBrickRowTexels);
    // Walls at many distances: bricks seen by many samples or few.
    IrradianceVolume volume = oneProbeVolume(true);
    volume.maxSurfelsPerBrick = 4096;   // every brick keeps all its surfels
    std::vector<GiSample> samples;
    for (const glm::vec3& d : giSampleDirections(volume.surfelsPerProbe)) {
        GiSample s;
        s.kind = GiSample::Kind::Surface;
        s.direction = d;
        s.position = d * (0.5f + 3.0f * std::abs(d.y)) / glm::max(glm::abs(d.x), glm::max(glm::abs(d.y), glm::abs(d.z)));
        s.normal = -d;
        samples.push_back(s);
    }
    const GiBake bake = buildGiBake(volume, {samples});
    std::set<uint32_t> counts;
    uint32_t previous = ~0u;
    for (uint32_t rank = 0; rank < bricksWithLight(bake); ++rank) {
        const GiBrick& brick = bake.bricks.at(giBrickSlot(rank));
        EXPECT_LE(brick.surfelCount, previous) << "rank " << rank;
        EXPECT_GT(brick.surfelCount, 0u) << "rank " << rank;
        previous = brick.surfelCount;
        counts.insert(brick.surfelCount);
    }
    EXPECT_GT(counts.size(), 3u) << "the test needs bricks of many sizes";
    for (const GiTransfer& t : bake.transfers) EXPECT_GT(bake.bricks.at(t.brick).surfelCount, 0u) << "a transfer names an empty slot";
}

TEST(GiBake, SurfelsOfOtherRenderingLayersAreOtherBricks) {
    const IrradianceVolume volume = oneProbeVolume(true);
    std::vector<GiSample> samples;
    for (uint32_t i = 0; i < 8; ++i) {
        GiSample s;
        s.kind = GiSample::Kind::Surface;
        s.direction = glm::normalize(glm::vec3(0.01f * float(i), -1.0f, 0.0f));
        s.position = glm::vec3(0.01f * float(i), -1.0f, 0.0f);   // one cell, one normal
        s.normal = glm::vec3(0.0f, 1.0f, 0.0f);
        s.renderingLayers = i % 2 == 0 ? 1u : 0x80000000u;
        samples.push_back(s);
    }
    const GiBake bake = buildGiBake(volume, {samples});
    ASSERT_EQ(bake.bricks.size(), 2u);
    for (const GiBrick& brick : bake.bricks) {
        ASSERT_EQ(brick.surfelCount, 4u);
        for (uint32_t i = 0; i < brick.surfelCount; ++i)
            EXPECT_EQ(bake.surfels[brick.firstSurfel + i].renderingLayers, bake.surfels[brick.firstSurfel].renderingLayers);
    }
}

TEST(GiBake, SkySamplesShareDirectionBinsAndBricksKeepAtMostTheirCap) {
    const IrradianceVolume volume = oneProbeVolume(true);   // 1024 samples
    std::vector<GiSample> sky(volume.surfelsPerProbe);
    const std::vector<glm::vec3> directions = giSampleDirections(volume.surfelsPerProbe);
    for (size_t i = 0; i < sky.size(); ++i) sky[i].direction = directions[i];
    const GiBake binned = buildGiBake(volume, {sky});
    EXPECT_LE(bricksWithLight(binned), 6u * kGiSkyBinsPerFace * kGiSkyBinsPerFace);
    EXPECT_GT(bricksWithLight(binned), 300u) << "1024 spread directions should reach most of the 384 bins";
    // Every bin's direction is the unit mean of its samples: within a bin (about 11 degrees) of each.
    for (const GiTransfer& t : binned.transfers) {
        const GiBrick& brick = binned.bricks[t.brick];
        EXPECT_TRUE(brick.sky);
        EXPECT_NEAR(glm::length(brick.skyDirection), 1.0f, 1e-5f);
    }
    EXPECT_EQ(bricksWithLight(buildGiBake(oneProbeVolume(false), {sky})), 1024u);
    // A constant sky still integrates to its radiance: every bin's transfer sums its samples'.
    ShRgb radiance{};
    for (const GiTransfer& t : binned.transfers)
        for (size_t k = 0; k < 9; ++k) radiance[k] += glm::dvec3(3.0) * double(t.sh[k]);
    EXPECT_NEAR(shEvaluate(shConvolveIrradiance(radiance), glm::dvec3(0, 1, 0)).x, 3.0, 0.03);

    // One wall brick seen by every sample: at most maxSurfelsPerBrick surfels, spread over the list.
    std::vector<GiSample> wall = sky;
    for (GiSample& s : wall) {
        s.kind = GiSample::Kind::Surface;
        s.position = glm::vec3(0.9f, 0.1f, 0.1f);
        s.normal = glm::vec3(-1, 0, 0);
        s.emission = glm::vec3(1.0f);
    }
    IrradianceVolume capped = volume;
    capped.maxSurfelsPerBrick = 7;
    const GiBake one = buildGiBake(capped, {wall});
    ASSERT_EQ(one.bricks.size(), 1u);
    EXPECT_EQ(one.bricks[0].surfelCount, 7u);
    EXPECT_EQ(one.surfels.size(), 7u);
}

TEST(GiBake, ProbesSeeingMostlyBackFacesAreInvalid) {
    const IrradianceVolume volume = oneProbeVolume(true);
    std::vector<GiSample> samples(volume.surfelsPerProbe);
    for (size_t i = 0; i < samples.size(); ++i) samples[i].kind = i % 3 == 0 ? GiSample::Kind::Surface : GiSample::Kind::BackFace;
    const GiBake bake = buildGiBake(volume, {samples});
    EXPECT_FALSE(bake.valid[0]);
    EXPECT_NEAR(bake.backFaceFraction[0], 2.0f / 3.0f, 0.01f);
    for (GiSample& s : samples) s.kind = GiSample::Kind::Sky;
    EXPECT_TRUE(buildGiBake(volume, {samples}).valid[0]);
}

// Six back faces around a probe (the inside of a box), the nearest `nearest` away along +X.
std::vector<GiSample> insideABox(const glm::vec3& at, float nearest) {
    std::vector<GiSample> samples;
    for (const glm::vec3 direction : {glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, -1, 0), glm::vec3(0, 0, 1),
                                      glm::vec3(0, 0, -1)}) {
        GiSample s;
        s.kind = GiSample::Kind::BackFace;
        s.direction = direction;
        s.position = at + direction * (direction.x > 0.0f ? nearest : 0.4f);
        samples.push_back(s);
    }
    return samples;
}

TEST(GiBake, AProbeInsideSomethingMovesThroughTheNearestInsideFace) {
    const glm::vec3 grid(1.0f, 2.0f, 3.0f), spacing(1.0f, 2.0f, 0.5f);   // a tenth of the smallest: 0.05 beyond the face
    const std::optional<glm::vec3> moved = giRelocatedPosition(insideABox(grid, 0.2f), grid, grid, spacing, 0.5f);
    ASSERT_TRUE(moved.has_value());
    EXPECT_NEAR(moved->x, 1.25f, 1e-5f);
    EXPECT_EQ(moved->y, 2.0f);
    EXPECT_EQ(moved->z, 3.0f);
    // From where it already moved to: the offset is the grid's, clamped to 45 % of the spacing.
    const glm::vec3 there(1.3f, 2.0f, 3.0f);
    EXPECT_NEAR(giRelocatedPosition(insideABox(there, 0.3f), there, grid, spacing, 0.5f)->x, 1.45f, 1e-5f);
    // Not inside anything: it stays.
    std::vector<GiSample> outside = insideABox(grid, 0.2f);
    for (size_t i = 0; i < 3; ++i) outside[i].kind = GiSample::Kind::Surface;
    EXPECT_FALSE(giRelocatedPosition(outside, grid, grid, spacing, 0.5f).has_value());
    EXPECT_FALSE(giRelocatedPosition({}, grid, grid, spacing, 0.5f).has_value());
}

// ---- Bake files ---------------------------------------------------------------------------

GiBake smallBake(const IrradianceVolume& volume) {
    std::vector<std::vector<GiSample>> samples(size_t(volume.probeCounts.x) * volume.probeCounts.y * volume.probeCounts.z);
    const std::vector<glm::vec3> directions = giSampleDirections(volume.surfelsPerProbe);
    for (size_t p = 0; p < samples.size(); ++p)
        for (size_t i = 0; i < directions.size(); ++i) {
            GiSample s;
            s.direction = directions[i];
            s.kind = i % 3 == 0 ? GiSample::Kind::Sky : i % 7 == 0 ? GiSample::Kind::BackFace : GiSample::Kind::Surface;
            s.position = directions[i] * (1.0f + float(p));
            s.normal = -directions[i];
            // Half of them on a tilted triangle; the others leave it to the normal.
            if (i % 2 == 0) s.faceNormal = glm::normalize(s.normal + glm::vec3(0.25f, 0.0f, 0.0f));
            if (i % 4 == 0) s.renderingLayers = 0x80000002u;
            s.albedo = glm::vec3(0.5f, 0.25f, float(i % 5) / 5.0f);
            s.emission = glm::vec3(float(i % 11));
            samples[p].push_back(s);
        }
    std::vector<glm::vec3> positions = giProbePositions(volume);
    if (positions.size() > 1) positions[1].x += 0.1f;   // a relocated probe keeps its position through a file
    GiBake bake = buildGiBake(volume, samples, positions);
    for (size_t i = 0; i < samples.size() * kGiVisibilityResolution * kGiVisibilityResolution; ++i) {
        const float mean = 0.5f + float(i % 13) * 0.25f;
        bake.distanceMoments.push_back(glm::vec2(mean, mean * mean + float(i % 3) * 0.125f));
    }
    return bake;
}

TEST(GiBakeFiles, ABakeReadsBackAsWritten) {
    IrradianceVolume volume = oneProbeVolume(true);
    volume.probeCounts = glm::uvec3(2, 1, 1);
    volume.surfelsPerProbe = 64;
    const GiBake bake = smallBake(volume);
    const fs::path path = test_support::outputDir() / "gi-roundtrip.bake";
    writeGiBakeFile(path, bake, volume, 42);
    const GiBake read = readGiBakeFile(path, volume, 42);
    EXPECT_EQ(read.probePositions, bake.probePositions);
    EXPECT_EQ(read.backFaceFraction, bake.backFaceFraction);
    EXPECT_EQ(read.valid, bake.valid);
    EXPECT_EQ(read.probeFirstTransfer, bake.probeFirstTransfer);
    EXPECT_EQ(read.probeTransferCount, bake.probeTransferCount);
    ASSERT_EQ(read.surfels.size(), bake.surfels.size());
    for (size_t i = 0; i < bake.surfels.size(); ++i) {
        EXPECT_EQ(read.surfels[i].position, bake.surfels[i].position);
        EXPECT_EQ(read.surfels[i].normal, bake.surfels[i].normal);
        EXPECT_EQ(read.surfels[i].albedo, bake.surfels[i].albedo);
        EXPECT_EQ(read.surfels[i].emission, bake.surfels[i].emission);
        EXPECT_EQ(read.surfels[i].faceNormal, bake.surfels[i].faceNormal);
        EXPECT_EQ(read.surfels[i].renderingLayers, bake.surfels[i].renderingLayers);
    }
    EXPECT_TRUE(std::any_of(bake.surfels.begin(), bake.surfels.end(), [](const GiSurfel& s) { return s.renderingLayers == 0x80000002u; }));
    // A sample that names no triangle plane gets its shading normal's; the others keep theirs.
    size_t tilted = 0;
    for (const GiSurfel& surfel : bake.surfels) {
        EXPECT_NEAR(glm::length(surfel.faceNormal), 1.0f, 1e-5f);
        if (surfel.faceNormal != surfel.normal) ++tilted;
    }
    EXPECT_GT(tilted, 0u);
    EXPECT_LT(tilted, bake.surfels.size());
    ASSERT_EQ(read.bricks.size(), bake.bricks.size());
    for (size_t i = 0; i < bake.bricks.size(); ++i) {
        EXPECT_EQ(read.bricks[i].firstSurfel, bake.bricks[i].firstSurfel);
        EXPECT_EQ(read.bricks[i].sky, bake.bricks[i].sky);
        EXPECT_EQ(read.bricks[i].skyDirection, bake.bricks[i].skyDirection);
    }
    ASSERT_EQ(read.transfers.size(), bake.transfers.size());
    for (size_t i = 0; i < bake.transfers.size(); ++i) {
        EXPECT_EQ(read.transfers[i].brick, bake.transfers[i].brick);
        EXPECT_EQ(read.transfers[i].sh, bake.transfers[i].sh);
    }
    EXPECT_EQ(read.distanceMoments, bake.distanceMoments);
    // A bake without visibility maps (made by hand) stays without them.
    GiBake without = bake;
    without.distanceMoments.clear();
    writeGiBakeFile(path, without, volume, 42);
    EXPECT_TRUE(readGiBakeFile(path, volume, 42).distanceMoments.empty());
}

TEST(GiBakeFiles, BadBakeFilesAreClearErrors) {
    IrradianceVolume volume = oneProbeVolume(true);
    volume.surfelsPerProbe = 64;
    const fs::path dir = test_support::outputDir();
    const fs::path good = dir / "gi-good.bake";
    writeGiBakeFile(good, smallBake(volume), volume, 7);
    std::ifstream in(good, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto write = [&](const std::string& name, const std::string& content) {
        const fs::path path = dir / name;
        std::ofstream(path, std::ios::binary) << content;
        return path;
    };
    auto expectError = [&](const fs::path& path, uint64_t hash, const IrradianceVolume& v, const std::string& words) {
        try {
            readGiBakeFile(path, v, hash);
            ADD_FAILURE() << path << " was accepted";
        } catch (const GiBakeFileError& e) {
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
        }
    };
    expectError(dir / "gi-no-such.bake", 7, volume, "cannot open");
    expectError(write("gi-text.bake", "hello, this is not a bake"), 7, volume, "not a Janus GI bake");
    std::string version = bytes;
    version[8] = char(99);
    expectError(write("gi-version.bake", version), 7, volume, "format version 99");
    expectError(write("gi-truncated.bake", bytes.substr(0, bytes.size() / 2)), 7, volume, "truncated");
    expectError(write("gi-header-only.bake", bytes.substr(0, 20)), 7, volume, "truncated");
    std::string flipped = bytes;
    flipped[bytes.size() / 2] = char(flipped[bytes.size() / 2] ^ 0x10);
    expectError(write("gi-flipped.bake", flipped), 7, volume, "checksum");
    expectError(good, 8, volume, "another scene");
    IrradianceVolume other = volume;
    other.probeCounts = glm::uvec3(2, 2, 2);
    expectError(good, 7, other, "the scene asks for 2x2x2");
    EXPECT_NO_THROW(readGiBakeFile(good, volume, 7));
    // Values a relight would turn into NaN or Inf light, under a checksum that holds (a faulty
    // writer's): each is refused, naming what is wrong. They were read, and the relight spread
    // them over every probe that sees the brick.
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const GiBake sound = smallBake(volume);
    auto expectRefused = [&](const std::string& name, const std::string& words, auto&& spoil) {
        GiBake bad = sound;
        spoil(bad);
        const fs::path path = dir / name;
        writeGiBakeFile(path, bad, volume, 7);
        expectError(path, 7, volume, words);
    };
    expectRefused("gi-nan-transfer.bake", "transfer 3 has a weight that is not finite", [&](GiBake& b) { b.transfers.at(3).sh[4] = nan; });
    expectRefused("gi-inf-emission.bake", "surfel 5 has an emission that is not finite", [&](GiBake& b) { b.surfels.at(5).emission.g = inf; });
    expectRefused("gi-nan-position.bake", "surfel 0 has a position that is not finite", [&](GiBake& b) { b.surfels.at(0).position.x = nan; });
    expectRefused("gi-zero-normal.bake", "surfel 2 has a normal that is not a unit vector", [&](GiBake& b) { b.surfels.at(2).normal = glm::vec3(0.0f); });
    expectRefused("gi-long-face-normal.bake", "surfel 1 has a face normal that is not a unit vector",
                  [&](GiBake& b) { b.surfels.at(1).faceNormal *= 3.0f; });
    expectRefused("gi-negative-albedo.bake", "surfel 4 has an albedo outside [0, 1]", [&](GiBake& b) { b.surfels.at(4).albedo.b = -0.5f; });
    expectRefused("gi-nan-probe.bake", "probe 0 has a position that is not finite", [&](GiBake& b) { b.probePositions.at(0).z = nan; });
    expectRefused("gi-fraction.bake", "probe 0 has a back-face fraction outside [0, 1]", [&](GiBake& b) { b.backFaceFraction.at(0) = 2.0f; });
    expectRefused("gi-nan-moments.bake", "visibility texel 7 has distance moments that are negative or not finite",
                  [&](GiBake& b) { b.distanceMoments.at(7).y = nan; });
    expectRefused("gi-negative-moments.bake", "visibility texel 9 has distance moments that are negative or not finite",
                  [&](GiBake& b) { b.distanceMoments.at(9).x = -1.0f; });
    expectRefused("gi-moments-variance.bake", "visibility texel 3 has a mean square distance below its mean distance squared",
                  [&](GiBake& b) { b.distanceMoments.at(3) = glm::vec2(2.0f, 3.0f); });
    expectRefused("gi-sky.bake", "has a sky direction that is not a unit vector", [&](GiBake& b) {
        for (GiBrick& brick : b.bricks)
            if (brick.sky) {
                brick.skyDirection = glm::vec3(nan);
                return;
            }
        FAIL() << "the small bake has no sky brick";
    });
}

TEST(GiBakeFiles, TheSceneHashFollowsWhatTheBakeDependsOn) {
    const Scene scene = loadScene(kCornellBox);
    const uint64_t hash = giSceneHash(scene);
    EXPECT_EQ(giSceneHash(loadScene(kCornellBox)), hash) << "the same file must hash the same";
    Scene moved = scene;
    moved.instances[0].world[3].x += 0.01f;
    EXPECT_NE(giSceneHash(moved), hash);
    Scene recoloured = scene;
    recoloured.materials[0].baseColorFactor.r *= 0.5f;
    EXPECT_NE(giSceneHash(recoloured), hash);
    Scene denser = scene;
    denser.irradianceVolume->surfelsPerProbe = 512;
    EXPECT_NE(giSceneHash(denser), hash);
    Scene unmoved = scene;   // relocation moves probes: another bake
    unmoved.irradianceVolume->relocateProbes = false;
    EXPECT_NE(giSceneHash(unmoved), hash);
    Scene relit = scene;   // lights and relight settings do not change a bake
    relit.lights.clear();
    relit.irradianceVolume->bounces = 3;
    EXPECT_EQ(giSceneHash(relit), hash);
    Scene unhidden = scene;   // every bake keeps the visibility maps: shading decides whether to test
    unhidden.irradianceVolume->visibility = false;
    EXPECT_EQ(giSceneHash(unhidden), hash);
}

// ---- On every configuration ---------------------------------------------------------------

class ProbeGiTest : public test_support::ConfigTest {
protected:
    RenderSettings settings(uint32_t width = 96, uint32_t height = 96) const { return settingsOfSize(width, height); }
    // size x size, the `--debug gi-light` view: the volume's light alone.
    RenderSettings giLightSettings(uint32_t size) const {
        RenderSettings debug = settings(size, size);
        debug.debugView = DebugView::GiLight;
        return debug;
    }
};

// A read-back probe's SH in the CPU's double type.
ShRgb shOf(const IrradianceProbe& probe) {
    ShRgb sh{};
    for (size_t k = 0; k < 9; ++k) sh[k] = glm::dvec3(probe.sh[k]);
    return sh;
}

// Mean HDR red / green over a rectangle of the image.
glm::dvec3 meanHdr(const ImageRGBAF& image, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1) {
    glm::dvec3 sum(0.0);
    for (uint32_t y = y0; y < y1; ++y)
        for (uint32_t x = x0; x < x1; ++x) {
            const float* p = &image.pixels[(size_t(y) * image.width + x) * 4];
            sum += glm::dvec3(p[0], p[1], p[2]);
        }
    return sum / double((x1 - x0) * (y1 - y0));
}

// A closed 2 m box whose double-sided inside emits `emission` per face (+X, -X, +Y, -Y, +Z, -Z
// walls) and reflects `albedo` (black by default), no lights, one probe at the centre.
Scene emissiveRoom(const std::array<glm::vec3, 6>& emission, bool bricks = true, float albedo = 0.0f) {
    Scene scene;
    scene.name = "emissive room";
    scene.environment.ambientColor = glm::vec3(0.0f);
    test_support::addGlowingRoom(scene, emission, albedo);
    scene.camera.position = glm::vec3(0.0f, 0.0f, 0.8f);
    scene.camera.target = glm::vec3(0.0f, -0.2f, -1.0f);
    IrradianceVolume volume;
    volume.bounds = Box{glm::vec3(-0.1f), glm::vec3(0.1f)};
    volume.probeCounts = glm::uvec3(1);
    volume.surfelsPerProbe = 1024;
    volume.bricks = bricks;
    volume.bounces = 1;
    scene.irradianceVolume = volume;
    return scene;
}

// Every sample of the bake's G-buffer sees the wall its direction points at (six walls, six
// emissions): no face, and no face's mirror image, is mixed up.
// A bake file for a scene without an irradiance volume was ignored without a word (janus render
// refused it, the library did not).
TEST_P(ProbeGiTest, ABakeFileForASceneWithoutAVolumeIsRefused) {
    RenderSettings withFile = settings(32, 32);
    withFile.giBakeFile = "no-volume.bake";
    try {
        Renderer renderer(device(), defaultScene(), withFile);
        ADD_FAILURE() << "the bake file was ignored";
    } catch (const GiBakeFileError& e) {
        EXPECT_NE(std::string(e.what()).find("no irradiance volume"), std::string::npos) << e.what();
    }
    expectNoMessages();
}

TEST_P(ProbeGiTest, BakeSamplesSeeTheWallTheirDirectionPointsAt) {
    device().takeDebugMessages();
    const std::array<glm::vec3, 6> colours = {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1),
                                              glm::vec3(1, 1, 0), glm::vec3(0, 1, 1), glm::vec3(1, 0, 1)};
    Scene scene = emissiveRoom(colours);
    // Shading normals leaning 30 degrees off every wall: the G-buffer keeps both normals.
    const float lean = glm::radians(30.0f);
    for (Mesh& mesh : scene.meshes)
        for (Vertex& v : mesh.vertices) v.normal = glm::vec3(std::sin(lean), 0.0f, std::cos(lean));   // the quads face +Z
    // Each wall its own rendering layers, the top bit among them: the sample keeps its wall's.
    std::array<uint32_t, 6> layers{};
    for (uint32_t face = 0; face < 6; ++face) scene.instances.at(face).renderingLayers = layers[face] = (2u << face) | (face == 5 ? 0x80000000u : 0u);
    const GpuScene gpuScene(device(), scene);
    IrradianceVolume volume = *scene.irradianceVolume;
    volume.surfelsPerProbe = 512;
    const std::vector<std::vector<GiSample>> samples = captureGiSamples(device(), gpuScene, volume, giProbePositions(volume), 32);
    expectNoMessages();
    ASSERT_EQ(samples.size(), 1u);
    uint32_t wrong = 0;
    for (const GiSample& s : samples[0]) {
        const glm::vec3 a = glm::abs(s.direction);
        // Skip directions within 2 degrees of an edge of the cube (a texel may hold the neighbour).
        const float major = std::max(a.x, std::max(a.y, a.z));
        const float second = a.x + a.y + a.z - major - std::min(a.x, std::min(a.y, a.z));
        if (major - second < 0.035f * major) continue;
        const int axis = a.x == major ? 0 : a.y == major ? 1 : 2;
        const int face = axis * 2 + (s.direction[axis] < 0.0f ? 1 : 0);
        EXPECT_EQ(s.kind, GiSample::Kind::Surface);
        if (glm::distance(s.emission, colours[face]) > 0.01f) ++wrong;
        // On the wall: the surfel is where the texel's own ray met it, to the half float's
        // precision of the distance (2^-11 relative). It was placed along the sample's direction
        // at the texel's distance, off the wall by up to ~3 % of the distance towards the face's
        // edges: below the floor for half the samples at grazing angles, where the shadow map
        // then shadowed them (the cornell box's first bounce was 7 % too dark, 26 % with a 4096 map).
        EXPECT_NEAR(std::abs(s.position[axis]), 1.0f, 2e-3f) << glm::length(s.position);
        // And within the texel's footprint on the wall (2/32 wide at distance 1) from where the
        // sample's own direction meets it.
        EXPECT_LE(glm::distance(s.position, s.direction / major), 0.0443f);
        glm::vec3 inward(0.0f);
        inward[axis] = s.direction[axis] < 0.0f ? 1.0f : -1.0f;
        EXPECT_NEAR(glm::dot(s.normal, inward), std::cos(lean), 2e-3f);
        EXPECT_LT(glm::distance(s.faceNormal, inward), 2e-3f) << "the triangle's plane, from the derivatives";
        EXPECT_EQ(s.renderingLayers, layers[face]);
    }
    EXPECT_EQ(wrong, 0u) << GetParam().name();
}

TEST_P(ProbeGiTest, AUniformlyEmissiveRoomGivesTheAnalyticIrradiance) {
    device().takeDebugMessages();
    const glm::vec3 e(1.5f, 1.0f, 0.25f);
    for (bool bricks : {true, false}) {
        Renderer renderer(device(), emissiveRoom({e, e, e, e, e, e}, bricks), settings(32, 32));
        renderer.renderFrame();
        const std::vector<IrradianceProbe> probes = renderer.readIrradianceProbes();
        ASSERT_EQ(probes.size(), 1u);
        EXPECT_TRUE(probes[0].valid);
        const ShRgb sh = shOf(probes[0]);
        // Constant radiance E: irradiance / pi = E for every normal. 1024 surfels and half floats:
        // within 1 %.
        for (const glm::dvec3 n : {glm::dvec3(1, 0, 0), glm::dvec3(0, 0, -1), glm::normalize(glm::dvec3(-1, 2, 1))}) {
            const glm::dvec3 value = shEvaluate(sh, n);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(value[c], e[c], 0.01 * e[c] + 1e-3) << GetParam().name() << " bricks " << bricks;
        }
    }
    expectNoMessages();
}

// With albedo a, light bounces: after n cycles the room's radiance is e (1 + a + ... + a^(n-1)),
// and the relight must agree with the reference path tracer (gi_reference_test.cpp checks that
// against the closed form) at every bounce count.
TEST_P(ProbeGiTest, MultipleBouncesMatchTheReferenceInAReflectiveEmissiveRoom) {
    device().takeDebugMessages();
    const glm::vec3 e(1.0f, 0.5f, 0.25f);
    for (uint32_t bounces : {1u, 3u}) {
        Scene scene = emissiveRoom({e, e, e, e, e, e}, true, 0.5f);
        scene.irradianceVolume->bounces = bounces;
        // Further bounces read the volume at the surfels: it must reach the walls.
        scene.irradianceVolume->bounds = Box{glm::vec3(-1.0f), glm::vec3(1.0f)};
        Renderer renderer(device(), scene, settings(32, 32));
        renderer.renderFrame();
        const std::vector<IrradianceProbe> probes = renderer.readIrradianceProbes();
        const GiReference reference(scene);
        const std::vector<glm::vec3> positions = {probes.at(0).position};
        const GiError error = compareProbeIrradiance(probes, reference.probes(positions, GiReferenceSettings{}.setBounces(bounces)));
        // Half floats in the volume and 1024 surfels: within 1 %.
        EXPECT_EQ(error.compared, 64u);
        EXPECT_LT(error.relativeRmse, 0.01) << GetParam().name() << ", " << bounces << " bounces";
        const double expected = (1.0 - std::pow(0.5, bounces)) / 0.5;
        EXPECT_NEAR(shEvaluate(shOf(probes[0]), glm::dvec3(0, 1, 0)).r, expected, 0.01 * expected) << GetParam().name();
    }
    expectNoMessages();
}

// The relight's bounces come from above each surfel's triangle only, as forward shading's lookup
// and the reference's paths do: in a reflective glowing room whose normals lean 60 degrees, a
// wall reflects (1 + cos 60) / 2 = 3/4 of the room's light, so two bounces give e (1 + 3/4 a).
// The relight evaluated the plain SH at the leaning normal and gave e (1 + a): on the cornell
// box's smoothed floor every further bounce added light from below the floor (docs/GI.md).
TEST_P(ProbeGiTest, TheRelightsBouncesComeOnlyFromAboveTheirSurfaces) {
    device().takeDebugMessages();
    const glm::vec3 e(1.0f, 0.5f, 0.25f);
    const float albedo = 0.5f, lean = glm::radians(60.0f);
    Scene scene = emissiveRoom({e, e, e, e, e, e}, true, albedo);
    scene.irradianceVolume->bounces = 2;
    scene.irradianceVolume->bounds = Box{glm::vec3(-1.0f), glm::vec3(1.0f)};   // the bounce's lookup reaches the walls
    for (Mesh& mesh : scene.meshes)
        for (Vertex& v : mesh.vertices) v.normal = glm::vec3(std::sin(lean), 0.0f, std::cos(lean));   // the quads face +Z
    Renderer renderer(device(), scene, settings(32, 32));
    renderer.renderFrame();
    const std::vector<IrradianceProbe> probes = renderer.readIrradianceProbes();
    ASSERT_EQ(probes.size(), 1u);
    const double expected = 1.0 + albedo * 0.5 * (1.0 + std::cos(lean));
    for (const glm::dvec3 n : {glm::dvec3(0, 1, 0), glm::dvec3(-1, 0, 0), glm::normalize(glm::dvec3(1, -1, 2))}) {
        const glm::dvec3 value = shEvaluate(shOf(probes[0]), n);
        // 1024 surfels, half floats: within 1 %.
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(value[c], expected * e[c], 0.01 * expected * e[c]) << GetParam().name() << " channel " << c;
    }
    const GiReference reference(scene);
    const GiError error = compareProbeIrradiance(probes, reference.probes(std::vector<glm::vec3>{probes[0].position}, GiReferenceSettings{}.setBounces(2)));
    EXPECT_LT(error.relativeRmse, 0.01) << GetParam().name();
    expectNoMessages();
}

// `scene` with one probe at the origin (1024 surfels, one bounce) under a camera looking at it:
// the probe's irradiance / pi SH after the first relight, and the reference's.
std::pair<ShRgb, ShRgb> oneProbeAndItsReference(rhi::IDevice& device, Scene scene, const RenderSettings& settings) {
    scene.camera.position = glm::vec3(0.0f, 0.5f, 2.0f);
    IrradianceVolume volume;
    volume.bounds = Box{glm::vec3(-0.1f), glm::vec3(0.1f)};
    volume.probeCounts = glm::uvec3(1);
    volume.surfelsPerProbe = 1024;
    volume.bounces = 1;
    scene.irradianceVolume = volume;
    Renderer renderer(device, scene, settings);
    renderer.renderFrame();
    const std::vector<IrradianceProbe> probes = renderer.readIrradianceProbes();
    EXPECT_EQ(probes.size(), 1u);
    const GiReference reference(scene);
    const std::vector<GiReferenceProbe> truth = reference.probes(std::vector<glm::vec3>{probes.at(0).position}, GiReferenceSettings{}.setBounces(1));
    return {shOf(probes.at(0)), truth.at(0).irradianceSh};
}

// A light below a surfel's triangle does not reach it, though its shading normal leans towards
// the light (the reference's rule): the floor's normals lean 60 degrees to -X, and a sun just
// below the floor's plane on that side lit the floor in the relight and not in the reference.
// The same sun just above the plane lights it in both.
TEST_P(ProbeGiTest, ALightBelowASurfelsTriangleDoesNotReachIt) {
    device().takeDebugMessages();
    for (const float height : {-0.3f, 0.3f}) {
        Scene scene;
        scene.name = "leaning floor";
        scene.environment.ambientColor = glm::vec3(0.0f);
        const int32_t grey = detail::addMaterial(scene, "floor", glm::vec3(0.8f), 0.0f, 1.0f);
        Mesh floor = detail::makeQuad(grey);
        const float lean = glm::radians(60.0f);
        for (Vertex& v : floor.vertices) v.normal = glm::vec3(std::sin(lean), 0.0f, std::cos(lean));
        scene.instances.push_back(Instance{detail::addMesh(scene, std::move(floor)),
                                           test_support::quadFacing(glm::vec3(0.0f, -1.0f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f), 4.0f), 1u,
                                           "floor"});
        Light sun;
        sun.direction = -glm::normalize(glm::vec3(-0.9f, height, 0.0f));   // travels towards the floor from -X
        sun.intensity = 3.0f;
        scene.lights.push_back(sun);
        const auto [probe, truth] = oneProbeAndItsReference(device(), scene, settings(32, 32));
        const double fromBelow = shEvaluate(probe, glm::dvec3(0, -1, 0)).g;
        const double truthFromBelow = shEvaluate(truth, glm::dvec3(0, -1, 0)).g;
        if (height < 0.0f) {
            EXPECT_EQ(truthFromBelow, 0.0);
            EXPECT_LT(std::abs(fromBelow), 1e-4) << GetParam().name() << ": the floor was lit from below its plane";
        } else {
            EXPECT_GT(truthFromBelow, 0.05);
            EXPECT_NEAR(fromBelow, truthFromBelow, 0.03 * truthFromBelow) << GetParam().name();   // 1024 surfels of a 4 m floor: 3 %
        }
    }
    expectNoMessages();
}

// The relight lights a surfel only with the lights that light its mesh in forward shading (their
// rendering layers share a bit): a floor in two halves, layers 1 (x < 0) and 2 (x > 0), under a
// sun and then a point light of layers 2, gives the probe above it light from the right half only,
// as the reference. The relight lit both halves before.
TEST_P(ProbeGiTest, ASurfelIsLitOnlyByTheLightsOfItsRenderingLayers) {
    device().takeDebugMessages();
    for (const LightType type : {LightType::Directional, LightType::Point}) {
        Scene scene;
        scene.name = "floor in two layers";
        scene.environment.ambientColor = glm::vec3(0.0f);
        const int32_t grey = detail::addMaterial(scene, "floor", glm::vec3(0.8f), 0.0f, 1.0f);
        for (const float side : {-1.0f, 1.0f})
            scene.instances.push_back(Instance{detail::addMesh(scene, detail::makeQuad(grey)),
                                               test_support::quadFacing(glm::vec3(side, -1.0f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f), 2.0f),
                                               side < 0.0f ? 1u : 2u, side < 0.0f ? "left" : "right"});
        Light light;
        light.type = type;
        light.direction = glm::normalize(glm::vec3(0.1f, -1.0f, 0.2f));
        light.position = glm::vec3(0.0f, 0.5f, 0.0f);
        light.intensity = 3.0f;
        light.renderingLayers = 2u;
        scene.lights.push_back(light);
        const auto [probe, truth] = oneProbeAndItsReference(device(), scene, settings(32, 32));
        const glm::dvec3 downLeft = glm::normalize(glm::dvec3(-1, -1, 0)), downRight = glm::normalize(glm::dvec3(1, -1, 0));
        const double left = shEvaluate(probe, downLeft).g, right = shEvaluate(probe, downRight).g;
        const double truthLeft = shEvaluate(truth, downLeft).g, truthRight = shEvaluate(truth, downRight).g;
        const char* name = type == LightType::Directional ? "sun" : "point light";
        // 1024 surfels of a 4 m floor, L2 SH of a field lit on one side: 3 % of the lit side.
        EXPECT_NEAR(right, truthRight, 0.03 * truthRight) << GetParam().name() << ", " << name;
        EXPECT_NEAR(left, truthLeft, 0.03 * truthRight) << GetParam().name() << ", " << name << ": the left half was lit";
    }
    expectNoMessages();
}

// The glowing room with 2 x 2 x 2 probes filling it (bounds = the walls), 512 surfels each.
Scene roomFilledByTheVolume(const std::array<glm::vec3, 6>& emission) {
    Scene scene = emissiveRoom(emission);
    scene.irradianceVolume->bounds = Box{glm::vec3(-1.0f), glm::vec3(1.0f)};
    scene.irradianceVolume->probeCounts = glm::uvec3(2);
    scene.irradianceVolume->surfelsPerProbe = 512;
    return scene;
}

// A closed box (faces outwards, single-sided) glowing `emission` with black albedo.
void addGlowingBox(Scene& scene, const glm::vec3& centre, float halfSize, const glm::vec3& emission) {
    const int32_t glowing = detail::addMaterial(scene, "box", glm::vec3(0.0f), 0.0f, 1.0f, emission);
    glm::mat4 world(halfSize);
    world[3] = glm::vec4(centre, 1.0f);
    scene.instances.push_back(Instance{detail::addMesh(scene, detail::makeBox(glowing)), world, 1u, "box"});
}

// Channels of the HDR image further than `tolerance` (relative) from `expected`, and the first.
std::pair<uint32_t, std::string> channelsOff(const ImageRGBAF& hdr, const glm::vec3& expected, float tolerance) {
    uint32_t off = 0;
    std::string first;
    for (size_t i = 0; i < hdr.pixels.size(); i += 4)
        for (int c = 0; c < 3; ++c)
            if (std::abs(hdr.pixels[i + c] - expected[c]) > tolerance * expected[c] && off++ == 0)
                first = fmt::format("pixel {} channel {}: {} (expected {})", i / 4, c, hdr.pixels[i + c], expected[c]);
    return {off, first};
}

// The volume covers its bounds: a room whose bounds are the volume's has its walls fully covered
// (coverage once fell off from the outer probes' centres, half a spacing inside the walls, and the
// walls got ~60 % of their GI).
TEST_P(ProbeGiTest, TheVolumeCoversItsBoundsUpToTheWalls) {
    device().takeDebugMessages();
    const glm::vec3 e(0.5f, 1.0f, 0.75f);
    Renderer renderer(device(), roomFilledByTheVolume({e, e, e, e, e, e}), giLightSettings(32));
    renderer.renderFrame();
    const auto [dim, first] = channelsOff(renderer.readHdrImage(), e, 0.03f);   // 512 surfels, half floats: 3 %
    EXPECT_EQ(dim, 0u) << GetParam().name() << ": channels whose indirect light is not the room's; first " << first;
    expectNoMessages();
}

// Beyond the outer probes the lookup clamps, and all its weight falls on the outer layer; where the
// probe there is invalid (inside something), its valid neighbours must give the light. They gave
// none: the cornell box's floor and Suzanne beside the probe inside her were black in the volume's
// light. Here a glowing box (the room's emission: the light stays uniform) holds the probe nearest
// the room's upper right back corner, and the camera looks into that corner.
TEST_P(ProbeGiTest, AnInvalidProbeAtTheBorderLeavesItsLightToItsValidNeighbours) {
    device().takeDebugMessages();
    const glm::vec3 e(0.5f, 1.0f, 0.75f);
    Scene scene = roomFilledByTheVolume({e, e, e, e, e, e});   // probes at +-0.5
    scene.irradianceVolume->relocateProbes = false;              // the boxed probe stays invalid
    addGlowingBox(scene, glm::vec3(0.5f, 0.5f, -0.5f), 0.1f, e);
    scene.camera.target = glm::vec3(0.75f, 0.75f, -1.0f);
    Renderer renderer(device(), scene, giLightSettings(32));
    renderer.renderFrame();
    const std::vector<IrradianceProbe> probes = renderer.readIrradianceProbes();
    ASSERT_EQ(probes.size(), 8u);
    EXPECT_EQ(std::count_if(probes.begin(), probes.end(), [](const IrradianceProbe& p) { return !p.valid; }), 1) << GetParam().name();
    const auto [off, first] = channelsOff(renderer.readHdrImage(), e, 0.03f);   // 512 surfels, half floats: 3 %
    EXPECT_EQ(off, 0u) << GetParam().name() << ": channels without the room's light; first " << first;
    expectNoMessages();
}

// A probe inside a glowing box is moved out through the box's nearest face at bake time, and then
// sees the room (valid, the room's light); without relocation it stays inside, invalid.
TEST_P(ProbeGiTest, AProbeInsideSomethingMovesOutAndSeesTheRoom) {
    device().takeDebugMessages();
    const glm::vec3 e(0.5f, 1.0f, 0.75f);
    const glm::vec3 boxed(0.5f, 0.5f, -0.5f), boxCentre(0.45f, 0.5f, -0.5f);   // its nearest face: +X, 0.05 away
    for (const bool relocate : {true, false}) {
        SCOPED_TRACE(relocate ? "relocated" : "not relocated");
        Scene scene = roomFilledByTheVolume({e, e, e, e, e, e});   // probes at +-0.5, spacing 1
        scene.irradianceVolume->relocateProbes = relocate;
        addGlowingBox(scene, boxCentre, 0.1f, e);
        Renderer renderer(device(), scene, giLightSettings(16));
        renderer.renderFrame();
        const std::vector<IrradianceProbe> probes = renderer.readIrradianceProbes();
        ASSERT_EQ(probes.size(), 8u);
        const auto it = std::find_if(probes.begin(), probes.end(), [&](const IrradianceProbe& p) { return glm::distance(p.position, boxed) < 0.46f; });
        ASSERT_NE(it, probes.end());
        const IrradianceProbe& probe = *it;
        if (!relocate) {
            EXPECT_FALSE(probe.valid) << GetParam().name();
            EXPECT_EQ(probe.position, boxed) << GetParam().name();
            continue;
        }
        EXPECT_TRUE(probe.valid) << GetParam().name();
        // Through +X, a tenth of the spacing beyond the face (0.55 + 0.1), so outside the box. Along
        // the nearest of 512 sample directions, which is a few degrees off +X: 0.03.
        EXPECT_NEAR(probe.position.x, 0.65f, 0.03f) << GetParam().name();
        EXPECT_NEAR(probe.position.y, boxed.y, 0.03f) << GetParam().name();
        EXPECT_NEAR(probe.position.z, boxed.z, 0.03f) << GetParam().name();
        for (int c = 0; c < 3; ++c)   // the room's (and the box's) uniform light: coefficient 0 alone, e / Y00
            EXPECT_NEAR(probe.sh[0][c], e[c] / float(kShY00), 0.03f * e[c] / float(kShY00)) << GetParam().name() << " channel " << c;
        EXPECT_TRUE(std::all_of(probes.begin(), probes.end(), [](const IrradianceProbe& p) { return p.valid; })) << GetParam().name();
    }
    expectNoMessages();
}

// Shading normals that lean away from their surface (smoothed vertex normals, normal maps) take
// only the light that arrives from above the surface's plane: in a uniformly glowing room, a
// normal leaning 60 degrees gets (1 + cos 60) / 2 = 3/4 of the room's irradiance. Evaluated at the
// leaning normal alone, the volume gave all of it (the cornell box's smooth floor saw itself:
// docs/GI.md, "Bent normals").
// Two halves of the glowing room split by a black wall from floor to ceiling: only the left
// half's far wall (-X) glows, so nothing in the right half gets any light. The lookup's probes
// straddle the wall (4 x 1 x 1 at x = -0.75 .. 0.75, the wall at |x| < 0.05), and trilinear
// weights alone leak the left probes' light onto the right half's floor and walls near the wall
// (DDGI's light leak). With the visibility test the left probes see the wall closer than those
// points and lose their weight there.
Scene roomSplitByAWall(bool visibility) {
    std::array<glm::vec3, 6> emission{};
    emission[1] = glm::vec3(2.0f);   // -X
    Scene scene = emissiveRoom(emission);
    const int32_t black = detail::addMaterial(scene, "wall", glm::vec3(0.0f), 0.0f, 1.0f);
    scene.instances.push_back(Instance{detail::addMesh(scene, detail::makeBox(black)),
                                       glm::scale(glm::mat4(1.0f), glm::vec3(0.05f, 1.0f, 1.0f)), 1u, "dividing wall"});
    scene.irradianceVolume->bounds = Box{glm::vec3(-1.0f), glm::vec3(1.0f)};
    scene.irradianceVolume->probeCounts = glm::uvec3(2, 1, 1);
    scene.irradianceVolume->surfelsPerProbe = 512;
    scene.irradianceVolume->visibility = visibility;
    // In the right half, looking down at its floor along the wall.
    scene.camera.position = glm::vec3(0.9f, 0.6f, 0.0f);
    scene.camera.target = glm::vec3(0.05f, -1.0f, 0.0f);
    return scene;
}

TEST_P(ProbeGiTest, LightDoesNotLeakThroughAWallBetweenProbes) {
    device().takeDebugMessages();
    auto rightHalf = [&](bool visibility) {
        Renderer renderer(device(), roomSplitByAWall(visibility), giLightSettings(32));
        renderer.renderFrame();
        const std::vector<IrradianceProbe> probes = renderer.readIrradianceProbes();
        EXPECT_EQ(probes.size(), 2u);
        float leftLight = 0.0f;   // the brightest left probe's irradiance / pi towards the glowing wall
        for (size_t p = 0; p < 1 && p < probes.size(); ++p)
            leftLight = std::max(leftLight, float(shEvaluate(shOf(probes[p]), glm::dvec3(-1, 0, 0)).x));
        const ImageRGBAF hdr = renderer.readHdrImage();
        float brightest = 0.0f;
        for (size_t i = 0; i < hdr.pixels.size(); i += 4) brightest = std::max({brightest, hdr.pixels[i], hdr.pixels[i + 1], hdr.pixels[i + 2]});
        return std::pair{leftLight, brightest};
    };
    const auto [leftLight, leaked] = rightHalf(false);
    const auto [leftLightToo, kept] = rightHalf(true);
    ASSERT_GT(leftLight, 0.3f) << GetParam().name() << ": the left half must be lit for the test to mean anything";
    EXPECT_EQ(leftLight, leftLightToo) << "the visibility test changes shading, not the probes";
    EXPECT_GT(leaked, 0.05f * leftLight) << GetParam().name() << ": without the test the left probes' light leaks (the case it guards)";
    // Not exactly 0 (0.49 % here on every configuration, against 12.7 % without): where the wall
    // meets the floor the left probe's map averages the wall with the floor beyond it (the lobe is
    // about 10 degrees wide), so its variance lets a little through at the contact line, as DDGI's does.
    EXPECT_LT(kept, 0.01f * leftLight) << GetParam().name() << ": light leaked through the wall (without the test: " << leaked << ")";
    expectNoMessages();
}

// The built-in gi-rooms scene (two rooms, a wall with a doorway, the volume's probes either side
// of the wall), its indirect light against the path-traced reference: the visibility test halves
// the error (bench: 64 % -> 28 % at 96 x 96 and 512 paths), and without it the image is too
// bright (the left room's light on the right room's side of the wall).
TEST_P(ProbeGiTest, TheBuiltInRoomsSceneAgreesWithTheReferenceOnlyWithVisibility) {
    device().takeDebugMessages();
    constexpr uint32_t kWidth = 48, kHeight = 36;
    const Scene scene = giRoomsScene();
    ASSERT_TRUE(scene.irradianceVolume.has_value());
    ASSERT_TRUE(scene.irradianceVolume->visibility);
    const ImageRGBAF reference = GiReference(scene).indirectIrradiance(
        scene.camera, kWidth, kHeight, GiReferenceSettings{}.setBounces(scene.irradianceVolume->bounces).setSamplesPerPixel(128));
    auto errorOf = [&](bool visibility) {
        Scene variant = scene;
        variant.irradianceVolume->visibility = visibility;
        RenderSettings debug = settings(kWidth, kHeight);
        debug.debugView = DebugView::GiLight;
        Renderer renderer(device(), variant, debug);
        renderer.renderFrame();
        return compareIndirectImage(renderer.readHdrImage(), reference);
    };
    const GiError with = errorOf(true), without = errorOf(false);
    // The reference's own noise at 128 paths a pixel is about 30 % here: the margins are wide.
    EXPECT_LT(with.relativeRmse, 0.75 * without.relativeRmse) << GetParam().name() << ": " << with.relativeRmse << " against "
                                                              << without.relativeRmse << " without the test";
    EXPECT_GT(without.relativeBias, with.relativeBias + 0.2) << GetParam().name() << ": the leak makes the image too bright";
    expectNoMessages();
}

TEST_P(ProbeGiTest, ALeaningNormalGetsOnlyTheLightAboveItsSurface) {
    device().takeDebugMessages();
    const glm::vec3 e(0.5f, 1.0f, 0.75f);
    Scene scene = roomFilledByTheVolume({e, e, e, e, e, e});
    const float lean = glm::radians(60.0f);
    for (Mesh& mesh : scene.meshes)
        for (Vertex& v : mesh.vertices) v.normal = glm::vec3(std::sin(lean), 0.0f, std::cos(lean));   // the quads face +Z
    Renderer renderer(device(), scene, giLightSettings(32));
    renderer.renderFrame();
    const auto [wrong, first] = channelsOff(renderer.readHdrImage(), e * 0.5f * (1.0f + std::cos(lean)), 0.03f);   // 512 surfels, half floats: 3 %
    EXPECT_EQ(wrong, 0u) << GetParam().name() << ": values off the leaning normal's share of the room's light; first " << first;
    expectNoMessages();
}

// The same lean under light from six colours (every SH band): each pixel against the CPU's closed
// form (shEvaluateAboveSurface) at the probe as read back, with the wall the pixel's ray meets.
TEST_P(ProbeGiTest, ALeaningNormalMatchesTheCpuClosedFormOnEveryWall) {
    device().takeDebugMessages();
    const std::array<glm::vec3, 6> emission = {glm::vec3(2.0f, 0.2f, 0.2f), glm::vec3(0.2f, 2.0f, 0.2f), glm::vec3(0.2f, 0.2f, 2.0f),
                                               glm::vec3(1.0f, 1.0f, 0.2f), glm::vec3(0.2f, 1.0f, 1.0f), glm::vec3(1.0f, 0.2f, 1.0f)};
    Scene scene = emissiveRoom(emission);
    scene.irradianceVolume->bounds = Box{glm::vec3(-1.0f), glm::vec3(1.0f)};   // one probe, covering every wall
    const double lean = glm::radians(60.0);
    for (Mesh& mesh : scene.meshes)
        for (Vertex& v : mesh.vertices) v.normal = glm::vec3(float(std::sin(lean)), 0.0f, float(std::cos(lean)));
    Renderer renderer(device(), scene, giLightSettings(32));
    renderer.renderFrame();
    const ImageRGBAF hdr = renderer.readHdrImage();
    const std::vector<IrradianceProbe> probes = renderer.readIrradianceProbes();
    ASSERT_EQ(probes.size(), 1u);
    const ShRgb sh = shOf(probes[0]);
    const glm::dmat4 inverseViewProjection =
        glm::inverse(glm::dmat4(makeProjection(scene.camera, 32, 32)) * glm::dmat4(makeView(scene.camera)));
    uint32_t compared = 0, wrong = 0, discriminating = 0;
    std::string first;
    for (uint32_t y = 0; y < 32; ++y)
        for (uint32_t x = 0; x < 32; ++x) {
            // The pixel centre's ray (NDC y = -1 is row 0) to the wall it leaves the 2 m room through.
            const glm::dvec2 ndc((x + 0.5) / 32.0 * 2.0 - 1.0, (y + 0.5) / 32.0 * 2.0 - 1.0);
            const glm::dvec4 nearPoint = inverseViewProjection * glm::dvec4(ndc, 0.0, 1.0), farPoint = inverseViewProjection * glm::dvec4(ndc, 1.0, 1.0);
            const glm::dvec3 origin = glm::dvec3(nearPoint) / nearPoint.w;
            const glm::dvec3 direction = glm::normalize(glm::dvec3(farPoint) / farPoint.w - origin);
            double nearest = 1e30;
            int face = -1;
            for (int axis = 0; axis < 3; ++axis) {
                if (direction[axis] == 0.0) continue;
                const double t = ((direction[axis] > 0.0 ? 1.0 : -1.0) - origin[axis]) / direction[axis];
                if (t < nearest) nearest = t, face = 2 * axis + (direction[axis] > 0.0 ? 0 : 1);
            }
            const glm::dvec3 hit = origin + direction * nearest;
            const int axis = face / 2;
            if (std::abs(hit[(axis + 1) % 3]) > 0.9 || std::abs(hit[(axis + 2) % 3]) > 0.9) continue;   // near an edge: either wall
            // quadFacing's frame: the wall faces into the room, its local +X is `right`.
            glm::dvec3 inward(0.0);
            inward[axis] = face % 2 == 0 ? -1.0 : 1.0;
            const glm::dvec3 up = std::abs(inward.y) > 0.5 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
            const glm::dvec3 right = glm::normalize(glm::cross(up, inward));
            const glm::dvec3 leaning = std::sin(lean) * right + std::cos(lean) * inward;
            const glm::dvec3 expected = glm::max(shEvaluateAboveSurface(sh, leaning, inward), glm::dvec3(0.0));
            const glm::dvec3 plain = glm::max(shEvaluate(sh, leaning), glm::dvec3(0.0));
            const float* p = &hdr.pixels[(size_t(y) * 32 + x) * 4];
            ++compared;
            if (glm::length(plain - expected) > 0.1 * glm::length(expected)) ++discriminating;
            for (int c = 0; c < 3; ++c)
                if (std::abs(p[c] - expected[c]) > 2e-3 * (1.0 + expected[c])) {   // float arithmetic on the same half-float SH
                    if (wrong++ == 0) first = fmt::format("pixel ({}, {}) wall {} channel {}: {} (expected {}, plain {})", x, y, face, c, p[c], expected[c], plain[c]);
                }
        }
    EXPECT_GT(compared, 500u) << GetParam().name();
    EXPECT_GT(discriminating, compared / 2) << GetParam().name() << ": the plain evaluation would pass too";
    EXPECT_EQ(wrong, 0u) << GetParam().name() << ": " << wrong << " values off the closed form; first " << first;
    expectNoMessages();
}

// Probes written into the volume are what it holds and what shading reads, until a relight
// replaces them (what `janus bench gi` does with the reference's probes).
TEST_P(ProbeGiTest, WrittenProbesAreWhatShadingReadsUntilTheNextRelight) {
    device().takeDebugMessages();
    const glm::vec3 e(0.5f, 1.0f, 0.75f);
    Renderer renderer(device(), roomFilledByTheVolume({e, e, e, e, e, e}), giLightSettings(32));
    auto expectEveryPixel = [&](const glm::vec3& expected, float tolerance, const std::string& when) {
        const auto [wrong, first] = channelsOff(renderer.readHdrImage(), expected, tolerance);
        EXPECT_EQ(wrong, 0u) << GetParam().name() << ": " << when << "; first " << first;
    };
    renderer.renderFrame();
    std::vector<IrradianceProbe> probes = renderer.readIrradianceProbes();
    ASSERT_EQ(probes.size(), 8u);
    // Uniform irradiance / pi q everywhere: coefficient 0 alone, q / Y00; one probe invalid.
    const glm::vec3 q(0.2f, 0.4f, 0.8f);
    for (IrradianceProbe& probe : probes) {
        probe.sh = {};
        probe.sh[0] = q / float(kShY00);
        probe.valid = true;
    }
    probes[5].valid = false;
    probes[5].sh[0] = glm::vec3(100.0f);   // no weight: must not show
    renderer.writeIrradianceProbes(probes);
    EXPECT_FALSE(renderer.irradiancePending());
    const std::vector<IrradianceProbe> stored = renderer.readIrradianceProbes();
    for (size_t p = 0; p < probes.size(); ++p) {
        EXPECT_EQ(stored[p].valid, probes[p].valid) << "probe " << p;
        for (size_t k = 0; k < 9; ++k)
            for (int c = 0; c < 3; ++c)   // half floats: 11 bits
                EXPECT_NEAR(stored[p].sh[k][c], probes[p].sh[k][c], 1e-3f * std::abs(probes[p].sh[k][c])) << "probe " << p << " coefficient " << k;
    }
    const FrameReport written = renderer.renderFrame();
    EXPECT_EQ(test_support::passNames(written).find("gi-"), std::string::npos) << test_support::passNames(written);
    expectEveryPixel(q, 2e-3f, "the written probes' light");   // half floats
    renderer.markIrradianceDirty();
    renderer.renderFrame();
    expectEveryPixel(e, 0.03f, "the room's light after a relight");   // 512 surfels, half floats: 3 %
    expectNoMessages();
}

TEST_P(ProbeGiTest, WritingProbesThatDoNotFitTheVolumeIsAClearError) {
    device().takeDebugMessages();
    const glm::vec3 e(0.5f);
    Scene scene = emissiveRoom({e, e, e, e, e, e});
    scene.irradianceVolume->probeCounts = glm::uvec3(2, 1, 1);
    scene.irradianceVolume->surfelsPerProbe = 64;
    Renderer renderer(device(), scene, settings(16, 16));
    renderer.renderFrame();
    const std::vector<IrradianceProbe> probes = renderer.readIrradianceProbes();
    ASSERT_EQ(probes.size(), 2u);
    auto expectError = [&](std::vector<IrradianceProbe> bad, const std::string& says) {
        try {
            renderer.writeIrradianceProbes(bad);
            ADD_FAILURE() << GetParam().name() << ": no error; expected one saying '" << says << "'";
        } catch (const RendererError& error) {
            EXPECT_NE(std::string(error.what()).find(says), std::string::npos) << error.what();
        }
    };
    expectError({probes[0]}, "1 probes given, the volume has 2");
    std::vector<IrradianceProbe> swapped = {probes[1], probes[0]};
    expectError(swapped, "probe 0 is at");
    std::vector<IrradianceProbe> notFinite = probes;
    notFinite[1].sh[4].g = std::numeric_limits<float>::quiet_NaN();
    expectError(notFinite, "probe 1 coefficient 4 channel 1 is nan");
    std::vector<IrradianceProbe> huge = probes;
    huge[0].sh[0].r = 1e6f;
    expectError(huge, "finite half floats");
    // What the volume held is untouched by the refused writes.
    const std::vector<IrradianceProbe> after = renderer.readIrradianceProbes();
    for (size_t p = 0; p < probes.size(); ++p) EXPECT_EQ(after[p].sh[0], probes[p].sh[0]) << "probe " << p;

    Scene without = scene;
    without.irradianceVolume.reset();
    Renderer plain(device(), without, settings(16, 16));
    try {
        plain.writeIrradianceProbes(probes);
        ADD_FAILURE() << "no error without a volume";
    } catch (const RendererError& error) {
        EXPECT_NE(std::string(error.what()).find("no irradiance volume"), std::string::npos) << error.what();
    }
    expectNoMessages();
}

// The serial SH sum (a compute-path option, for `janus bench gi`) computes what the reduction does.
TEST_P(ProbeGiTest, TheSerialSumGivesTheReductionsProbes) {
    if (GetParam().path != FeaturePath::Compute) GTEST_SKIP() << "a compute-path option";
    device().takeDebugMessages();
    Scene scene = loadScene(kCornellBox);
    scene.reflectionProbes.clear();
    scene.irradianceVolume->probeCounts = glm::uvec3(2);
    Renderer parallel(device(), scene, settings(32, 32));
    parallel.renderFrame();
    scene.irradianceVolume->parallelReduction = false;
    Renderer serial(device(), scene, settings(32, 32));
    serial.renderFrame();
    const std::vector<IrradianceProbe> a = parallel.readIrradianceProbes(), b = serial.readIrradianceProbes();
    ASSERT_EQ(a.size(), b.size());
    for (size_t p = 0; p < a.size(); ++p)
        for (size_t k = 0; k < 9; ++k)
            for (int c = 0; c < 3; ++c)   // another summation order, rounded to half floats
                EXPECT_NEAR(a[p].sh[k][c], b[p].sh[k][c], 2e-3f * (1.0f + std::abs(a[p].sh[0][c]))) << "probe " << p << " coefficient " << k;
    expectNoMessages();
}

// A white floor between a red glowing wall (-X) and a green one (+X), lit only through the
// volume (4 probes along x): shading must read the probes where the floor is.
TEST_P(ProbeGiTest, ShadingReadsTheProbesWhereTheSurfaceIs) {
    device().takeDebugMessages();
    std::array<glm::vec3, 6> emission{};
    emission[0] = glm::vec3(0.0f, 2.0f, 0.0f);   // +X green
    emission[1] = glm::vec3(2.0f, 0.0f, 0.0f);   // -X red
    Scene scene = emissiveRoom(emission);
    scene.materials[3].baseColorFactor = glm::vec4(1.0f);   // the floor (-Y) reflects
    scene.irradianceVolume->bounds = Box{glm::vec3(-0.9f, -0.9f, -0.9f), glm::vec3(0.9f, 0.9f, 0.9f)};
    scene.irradianceVolume->probeCounts = glm::uvec3(4, 3, 2);   // every axis, so no two are mixed up
    scene.camera.position = glm::vec3(0.0f, 0.9f, 0.0f);
    scene.camera.target = glm::vec3(0.0f, -1.0f, 0.0f);
    scene.camera.up = glm::vec3(0.0f, 0.0f, -1.0f);   // +X to the right of the image
    Renderer renderer(device(), scene, settings(32, 32));
    renderer.renderFrame();
    const ImageRGBAF hdr = renderer.readHdrImage();
    expectNoMessages();
    const glm::dvec3 left = meanHdr(hdr, 2, 12, 8, 20), right = meanHdr(hdr, 24, 12, 30, 20);
    EXPECT_GT(left.r, 1.5 * left.g) << GetParam().name() << " left " << left.r << " " << left.g;
    EXPECT_GT(right.g, 1.5 * right.r) << GetParam().name() << " right " << right.r << " " << right.g;
}

TEST_P(ProbeGiTest, NegativeCoefficientsSurviveTheVolume) {
    device().takeDebugMessages();
    // Only the -X wall glows: the x coefficient (index 3) is negative, and so is (2, 2)... of the
    // lobe's SH; the stored values match the CPU bake's.
    std::array<glm::vec3, 6> emission{};
    emission[1] = glm::vec3(4.0f);
    const Scene scene = emissiveRoom(emission);
    Renderer renderer(device(), scene, settings(32, 32));
    renderer.renderFrame();
    const std::vector<IrradianceProbe> probes = renderer.readIrradianceProbes();
    expectNoMessages();
    ASSERT_EQ(probes.size(), 1u);
    EXPECT_LT(probes[0].sh[3].x, -0.1f) << "L1 x of a light from -X must be negative";
    // Bright from -X, dark towards +X.
    const ShRgb sh = shOf(probes[0]);
    EXPECT_GT(shEvaluate(sh, glm::dvec3(-1, 0, 0)).x, 1.0);
    EXPECT_LT(std::abs(shEvaluate(sh, glm::dvec3(1, 0, 0)).x), 0.2);
}

// Renders until the volume has no relight left (at most 32 frames).
test_support::FrameOutput renderSettled(rhi::IDevice& device, const Scene& scene, const RenderSettings& settings) {
    test_support::FrameOutput output;
    Renderer renderer(device, scene, settings);
    for (int frame = 0; frame < 32; ++frame) {
        output.report = renderer.renderFrame();
        if (!renderer.probesPending() && frame > 0 && !test_support::hasPassStartingWith(output.report, "gi-")) break;
    }
    output.display = renderer.readDisplayImage();
    output.hdr = renderer.readHdrImage();
    return output;
}


TEST_P(ProbeGiTest, TheRedWallBleedsOntoTheFloor) {
    device().takeDebugMessages();
    Scene withGi = loadScene(kCornellBox);
    withGi.reflectionProbes.clear();   // GI alone: the probe's glossy light would differ between the two
    // A plain grey floor facing straight up. The shared file's floor has a test texture with
    // coloured patches near its edges, and smooth normals that lean away from each wall (45 degrees
    // at the edges: the floor next to the red wall faces the green one, and is rightly lit by it).
    int32_t ground = -1;
    for (size_t i = 0; i < withGi.materials.size(); ++i)
        if (withGi.materials[i].name == "cornellBox.ground.000") ground = int32_t(i);
    ASSERT_GE(ground, 0);
    withGi.materials[size_t(ground)].baseColorTexture = -1;
    withGi.materials[size_t(ground)].baseColorFactor = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
    for (Mesh& mesh : withGi.meshes)
        if (mesh.material == ground)
            for (Vertex& v : mesh.vertices) v.normal = glm::vec3(0.0f, 1.0f, 0.0f);
    Scene without = withGi;
    without.irradianceVolume.reset();
    const RenderSettings s = settings(96, 96);
    const test_support::FrameOutput a = renderSettled(device(), withGi, s);
    const test_support::FrameOutput b = renderSettled(device(), without, s);
    expectNoMessages();
    test_support::expectFiniteHdr(a.hdr, GetParam().name());
    // The floor next to the red wall (left) and next to the green wall (right): what GI changes
    // there, per channel (with / without; the floor's texture and the light's colour cancel).
    const uint32_t y0 = 66, y1 = 80;
    const glm::dvec3 gainLeft = meanHdr(a.hdr, 20, y0, 28, y1) / glm::max(meanHdr(b.hdr, 20, y0, 28, y1), glm::dvec3(1e-6));
    const glm::dvec3 gainRight = meanHdr(a.hdr, 70, y0, 78, y1) / glm::max(meanHdr(b.hdr, 70, y0, 78, y1), glm::dvec3(1e-6));
    const std::string values = fmt::format("{}: gain left ({:.3f}, {:.3f}, {:.3f}) right ({:.3f}, {:.3f}, {:.3f})", GetParam().name(),
                                           gainLeft.r, gainLeft.g, gainLeft.b, gainRight.r, gainRight.g, gainRight.b);
    // Next to the red wall GI adds more red than green, next to the green wall more green than red.
    EXPECT_GT(gainLeft.r / gainLeft.g, 1.02) << values;
    EXPECT_GT(gainRight.g / gainRight.r, 1.02) << values;
    EXPECT_GT(gainLeft.r / gainLeft.g, gainRight.r / gainRight.g * 1.05) << values;
    if (HasFailure()) {
        writePNG(test_support::outputDir() / fmt::format("gi-cornell-{}.png", GetParam().name()), a.display);
        writePNG(test_support::outputDir() / fmt::format("gi-cornell-{}-without.png", GetParam().name()), b.display);
    }
}

TEST_P(ProbeGiTest, TheCornellBoxWithGiMatchesVulkanCompute) {
    device().takeDebugMessages();
    const Scene scene = loadScene(kCornellBox);
    static const test_support::FrameOutput reference = renderSettled(test_support::deviceFor(rhi::Backend::Vulkan), scene, [] {
        RenderSettings s;
        s.width = 96, s.height = 96, s.path = FeaturePath::Compute;
        return s;
    }());
    const test_support::FrameOutput result = renderSettled(device(), scene, settings());
    expectNoMessages();
    test_support::expectMatchesVulkanCompute(reference.display, result.display, "gi-parity", GetParam());
}

using test_support::countPasses;

TEST_P(ProbeGiTest, AStaticSceneRelightsOnceAndADirtyVolumeRelightsAgain) {
    device().takeDebugMessages();
    Scene scene = loadScene(kCornellBox);
    scene.irradianceVolume->probeCounts = glm::uvec3(2);
    scene.irradianceVolume->bounces = 2;
    scene.reflectionProbes.clear();
    Renderer renderer(device(), scene, settings(48, 48));
    const FrameReport first = renderer.renderFrame();
    EXPECT_EQ(countPasses(first, "gi-bake"), 1u);
    EXPECT_EQ(countPasses(first, "gi-brick-radiance"), 2u) << "two bounces: two cycles";
    EXPECT_EQ(countPasses(first, "gi-probe-sh"), 2u);
    for (int frame = 0; frame < 3; ++frame) EXPECT_EQ(countPasses(renderer.renderFrame(), "gi-"), 0u) << "frame " << frame + 2;
    renderer.markIrradianceDirty();
    EXPECT_EQ(countPasses(renderer.renderFrame(), "gi-probe-sh"), 2u);
    EXPECT_EQ(countPasses(renderer.renderFrame(), "gi-"), 0u);
    expectNoMessages();
}

TEST_P(ProbeGiTest, KProbesPerFrameRelightNearestTheCameraFirstAndEveryProbeWithinCeilPOverK) {
    device().takeDebugMessages();
    Scene scene = loadScene(kCornellBox);
    scene.irradianceVolume->probeCounts = glm::uvec3(3, 2, 2);   // 12 probes
    scene.irradianceVolume->probesPerFrame = 5;                  // 3 frames per cycle
    scene.irradianceVolume->bounces = 1;
    scene.reflectionProbes.clear();
    Renderer renderer(device(), scene, settings(32, 32));
    std::vector<bool> relit(12, false);
    const glm::vec3 camera = scene.camera.position;
    float farthestRelit = 0.0f;
    for (int frame = 1; frame <= 3; ++frame) {
        const FrameReport report = renderer.renderFrame();
        EXPECT_EQ(countPasses(report, "gi-probe-sh"), 1u) << "frame " << frame;
        // Bricks are lit once per cycle, in its first frame; later frames only sum their probes.
        EXPECT_EQ(countPasses(report, "gi-brick-radiance"), frame == 1 ? 1u : 0u) << "frame " << frame;
        const std::vector<IrradianceProbe> probes = renderer.readIrradianceProbes();
        uint32_t count = 0;
        float nearestNew = 1e30f;
        for (size_t i = 0; i < probes.size(); ++i) {
            const bool lit = probes[i].valid || glm::length(probes[i].sh[0]) > 0.0f;
            if (lit && !relit[i]) nearestNew = std::min(nearestNew, glm::distance(probes[i].position, camera));
            relit[i] = relit[i] || lit;
            count += relit[i] ? 1 : 0;
        }
        EXPECT_EQ(count, std::min(12u, 5u * frame)) << "frame " << frame;
        EXPECT_GE(nearestNew + 1e-4f, farthestRelit) << "frame " << frame << " relit a probe nearer than one of an earlier frame";
        for (size_t i = 0; i < probes.size(); ++i)
            if (relit[i]) farthestRelit = std::max(farthestRelit, glm::distance(probes[i].position, camera));
    }
    EXPECT_EQ(countPasses(renderer.renderFrame(), "gi-"), 0u) << "one bounce: done after ceil(12 / 5) = 3 frames";
    expectNoMessages();
}

TEST_P(ProbeGiTest, ABakeFileGivesTheImageOfABakeAtStartUp) {
    device().takeDebugMessages();
    Scene scene = loadScene(kCornellBox);
    scene.reflectionProbes.clear();
    scene.irradianceVolume->probeCounts = glm::uvec3(2);
    const fs::path file = test_support::outputDir() / fmt::format("gi-cornell-{}.bake", GetParam().name());
    const IrradianceBakeSummary summary = bakeIrradianceVolume(device(), scene, file);
    EXPECT_EQ(summary.probes, 8u);
    EXPECT_GT(summary.bricks, 0u);
    // The bricks that hold light, not the empty slots of their placement.
    const GiBake written = readGiBakeFile(file, *scene.irradianceVolume, giSceneHash(scene));
    EXPECT_EQ(summary.bricks, bricksWithLight(written));
    EXPECT_LT(summary.bricks, written.bricks.size()) << "the test needs a bake with empty slots";
    RenderSettings fromFile = settings(48, 48);
    fromFile.giBakeFile = file;
    const test_support::FrameOutput baked = renderSettled(device(), scene, settings(48, 48));
    Renderer renderer(device(), scene, fromFile);
    const FrameReport report = renderer.renderFrame();
    EXPECT_EQ(countPasses(report, "gi-bake"), 0u) << "a bake file means no bake at start-up";
    EXPECT_EQ(renderer.readDisplayImage().pixels, baked.display.pixels) << GetParam().name();
    // Another scene's file is refused.
    Scene other = scene;
    other.irradianceVolume->surfelsPerProbe = 128;
    EXPECT_THROW(Renderer(device(), other, fromFile), GiBakeFileError);
    expectNoMessages();
}

TEST_P(ProbeGiTest, HardCasesStayFinite) {
    device().takeDebugMessages();
    struct Case {
        const char* name;
        void (*edit)(Scene&);
    };
    const Case cases[] = {
        {"a probe inside the block", [](Scene& s) { s.irradianceVolume->bounds = Box{{-1.1f, 0.2f, -1.1f}, {-0.9f, 0.4f, -0.9f}}; s.irradianceVolume->probeCounts = glm::uvec3(1); }},
        {"probes that see only sky", [](Scene& s) { s.irradianceVolume->bounds = Box{{50, 50, 50}, {60, 60, 60}}; s.irradianceVolume->probeCounts = glm::uvec3(2); }},
        {"black albedo", [](Scene& s) { for (Material& m : s.materials) m.baseColorFactor = glm::vec4(0, 0, 0, 1); }},
        {"an emission of 1e4", [](Scene& s) { for (Material& m : s.materials) m.emissiveFactor = glm::vec3(1e4f); }},
        {"one probe", [](Scene& s) { s.irradianceVolume->probeCounts = glm::uvec3(1); }},
        {"a light exactly at a probe",
         [](Scene& s) {
             s.irradianceVolume->probeCounts = glm::uvec3(1);
             s.lights.push_back(test_support::pointLight(s.irradianceVolume->bounds.center(), glm::vec3(1.0f), 50.0f, std::nullopt));
         }},
        {"the camera outside the volume", [](Scene& s) { s.camera.position = glm::vec3(0, 1.5f, 30.0f); }},
        {"every probe inside geometry",
         [](Scene& s) {
             s.irradianceVolume->invalidBackFaceFraction = 1e-6f;
             s.irradianceVolume->bounds = Box{{-1.1f, 0.2f, -1.1f}, {-0.9f, 0.4f, -0.9f}};
         }},
    };
    for (const Case& c : cases) {
        Scene scene = loadScene(kCornellBox);
        scene.reflectionProbes.clear();
        scene.irradianceVolume->probeCounts = glm::uvec3(2);
        c.edit(scene);
        const test_support::FrameOutput output = renderSettled(device(), scene, settings(32, 32));
        test_support::expectFiniteHdr(output.hdr, fmt::format("{} {}", GetParam().name(), c.name));
    }
    expectNoMessages();
}

INSTANTIATE_TEST_SUITE_P(Configs, ProbeGiTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
