// Local-light hard cases (issue 3) on all five configurations, in every culling mode: the image
// and the tile lists stay finite and well formed, and the special cases report what they did.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "janus/renderer/renderer.h"
#include "janus/renderer/scene.h"
#include "renderer/renderer_test_support.h"

namespace janus::renderer {
namespace {

using namespace test_support;

constexpr uint32_t kHardCaseSize = 64;   // what these check does not depend on resolution
constexpr LightCulling kAllModes[] = {LightCulling::Naive, LightCulling::Tiles2D, LightCulling::TilesDepth};

// The default room: x in [-2, 2], y in [0, 3], z in [-2, 2], the camera at (0, 1.7, 1.9) looking
// at (0, 0.8, -1.2); the floor's centre and the back wall are in view.
Scene roomWith(std::vector<Light> localLights) {
    Scene scene = defaultScene();
    scene.lights.insert(scene.lights.end(), localLights.begin(), localLights.end());
    return scene;
}

struct HardCase {
    const char* name;
    Scene (*make)();
    uint32_t packedLights;   // local lights the renderer keeps
};

void PrintTo(const HardCase& hardCase, std::ostream* os) { *os << hardCase.name; }

const glm::vec3 kWhite(1.0f);
const glm::vec3 kDown(0.0f, -1.0f, 0.0f);

const HardCase kHardCases[] = {
    // scale = 1 / max(cosInner - cosOuter, 1e-4): the guard keeps the cone finite and sharp.
    {"SpotInnerEqualsOuter",
     [] {
         return roomWith({spotLight({0.0f, 2.5f, 0.0f}, kDown, kWhite, 10.0f, 4.0f, 0.4f, 0.4f),
                          spotLight({-1.0f, 2.5f, -1.0f}, kDown, kWhite, 10.0f, std::nullopt, 0.0f, 0.0f),
                          spotLight({1.0f, 2.0f, -1.0f}, kDown, kWhite, 10.0f, 3.0f, 0.7853982f, 0.7853982f)});
     },
     3},
    // A light with range <= 0 lights nothing and is not packed; the others still light the room.
    {"ZeroAndNegativeRange",
     [] {
         return roomWith({pointLight({0.0f, 1.0f, 0.0f}, kWhite, 5.0f, 0.0f), pointLight({0.5f, 1.0f, 0.0f}, kWhite, 5.0f, -1.0f),
                          spotLight({0.0f, 2.0f, 0.0f}, kDown, kWhite, 5.0f, 0.0f, 0.2f, 0.4f),
                          pointLight({-0.5f, 1.0f, -0.5f}, kWhite, 2.0f, 2.0f)});
     },
     1},
    // d = 0 at the shaded point: attenuation uses max(d^2, 1e-4) and the direction to the light
    // is zero-length.
    {"LightExactlyAtAShadedPoint",
     [] {
         return roomWith({pointLight({0.0f, 0.0f, 0.0f}, kWhite, 2.0f, 1.0f),                // on the floor
                          pointLight({0.0f, 1.5f, -2.0f}, kWhite, 2.0f, std::nullopt),       // on the back wall
                          spotLight({0.5f, 0.0f, -0.5f}, kDown, kWhite, 2.0f, 1.0f, 0.2f, 0.5f),   // on the floor, into it
                          spotLight({-0.5f, 0.0f, -0.5f}, -kDown, kWhite, 2.0f, 1.0f, 0.2f, 0.5f)});
     },
     4},
    // Radiance far above fp16's 65504 must be clamped before the RGBA16F store, not become Inf.
    {"Intensity1e6",
     [] {
         return roomWith({pointLight({0.0f, 1.5f, 0.0f}, kWhite, 1e6f, std::nullopt),
                          spotLight({0.0f, 0.3f, -1.0f}, kDown, kWhite, 1e6f, 2.0f, 0.1f, 0.3f)});
     },
     2},
};

using HardCaseParam = std::tuple<HardCase, Config>;

class LightHardCases : public testing::TestWithParam<HardCaseParam> {
protected:
    const HardCase& hardCase() const { return std::get<0>(GetParam()); }
    const Config& config() const { return std::get<1>(GetParam()); }
};

TEST_P(LightHardCases, ImageAndTileListsStayFiniteInEveryMode) {
    const Scene scene = hardCase().make();
    for (LightCulling mode : kAllModes) {
        const std::string label = fmt::format("{}-{}-{}", hardCase().name, config().name(), cullingName(mode));
        const FrameOutput output = renderOneFrame(config(), scene, settingsFor(mode, kHardCaseSize), ReadBack{.tiles = true});
        expectFiniteHdr(output.hdr, label);
        ASSERT_TRUE(output.report.lightCulling.has_value()) << label;
        const LightCullingReport& culling = *output.report.lightCulling;
        EXPECT_EQ(culling.mode, mode) << label;
        EXPECT_EQ(culling.localLights, hardCase().packedLights) << label;
        if (mode != LightCulling::Naive) {
            ASSERT_TRUE(output.tiles.has_value()) << label;
            expectWellFormedTileLists(*output.tiles, culling, kHardCaseSize, kHardCaseSize, label);
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Configs, LightHardCases, testing::Combine(testing::ValuesIn(kHardCases), testing::ValuesIn(allConfigs())),
                         [](const testing::TestParamInfo<HardCaseParam>& info) {
                             return fmt::format("{}_{}", std::get<0>(info.param).name, std::get<1>(info.param).name());
                         });

// gtest allows one stderr capture at a time; ending it on every path (an exception thrown by a
// failing renderer included) keeps the next test from aborting.
class StderrCapture {
public:
    StderrCapture() { testing::internal::CaptureStderr(); }
    ~StderrCapture() {
        if (m_capturing) testing::internal::GetCapturedStderr();
    }
    StderrCapture(const StderrCapture&) = delete;
    StderrCapture& operator=(const StderrCapture&) = delete;
    std::string take() {
        m_capturing = false;
        return testing::internal::GetCapturedStderr();
    }

private:
    bool m_capturing = true;
};

class LightSpecialCases : public testing::TestWithParam<Config> {
protected:
    const Config& config() const { return GetParam(); }
};

TEST_P(LightSpecialCases, NoLocalLightsRunsNoCullPass) {
    for (LightCulling mode : kAllModes) {
        const std::string label = fmt::format("{} {}", config().name(), cullingName(mode));
        const FrameOutput output = renderOneFrame(config(), defaultScene(), settingsFor(mode, kHardCaseSize));
        expectFiniteHdr(output.hdr, label);
        EXPECT_FALSE(output.report.lightCulling.has_value()) << label;
        EXPECT_FALSE(hasPassStartingWith(output.report, "light-cull")) << label << ": " << passNames(output.report);
    }
}

TEST_P(LightSpecialCases, AllLightsOffScreenListNothingAndLightNothing) {
    const glm::vec3 up(0.0f, 1.0f, 0.0f);
    // Behind the camera, beside the frustum, below the floor and beyond the far plane (20), each
    // with a range that keeps it clear of the view, and a spot behind the camera.
    const Scene scene = roomWith({pointLight({0.0f, 1.5f, 30.0f}, kWhite, 5.0f, 2.0f), pointLight({-40.0f, 1.0f, 0.0f}, kWhite, 5.0f, 3.0f),
                                  pointLight({40.0f, 1.0f, -5.0f}, kWhite, 5.0f, 3.0f), pointLight({0.0f, 1.0f, -60.0f}, kWhite, 5.0f, 5.0f),
                                  pointLight({0.0f, -50.0f, 0.0f}, kWhite, 5.0f, 4.0f), spotLight({0.0f, 1.5f, 25.0f}, up, kWhite, 5.0f, 2.0f, 0.2f, 0.4f)});
    const FrameOutput unlit = renderOneFrame(config(), defaultScene(), settingsFor(LightCulling::Naive, kHardCaseSize));
    for (LightCulling mode : kAllModes) {
        const std::string label = fmt::format("AllLightsOffScreen-{}-{}", config().name(), cullingName(mode));
        const FrameOutput output = renderOneFrame(config(), scene, settingsFor(mode, kHardCaseSize), ReadBack{.tiles = true});
        ASSERT_TRUE(output.report.lightCulling.has_value()) << label;
        EXPECT_EQ(output.report.lightCulling->localLights, 6u) << label;
        // Out of range, every light adds exactly 0: the image is the room without them.
        expectSameImage(unlit, output, label);
        if (mode != LightCulling::Naive) {
            ASSERT_TRUE(output.tiles.has_value()) << label;
            expectWellFormedTileLists(*output.tiles, *output.report.lightCulling, kHardCaseSize, kHardCaseSize, label);
            for (size_t t = 0; t < output.tiles->counts.size(); ++t) EXPECT_EQ(output.tiles->counts[t], 0u) << label << " tile " << t;
            EXPECT_EQ(output.report.lightCulling->listedLights, 0u) << label;
        }
    }
}

// `count` point lights on a rising circle around the room's centre, each reaching every visible
// surface (range 6 m), together as bright as 24 of 0.2 cd: every tile meets all of them.
std::vector<Light> lightsAroundTheCentre(uint32_t count) {
    std::vector<Light> lights;
    for (uint32_t i = 0; i < count; ++i) {
        const float turn = float(i) / float(count);
        const float angle = 6.2831853f * turn;
        lights.push_back(pointLight({0.3f * std::cos(angle), 1.2f + 0.48f * turn, 0.3f * std::sin(angle)}, kWhite, 4.8f / float(count), 6.0f));
    }
    return lights;
}

TEST_P(LightSpecialCases, MoreLightsThanTheCapOverflowLoudlyAndStayFinite) {
    // 24 lights around the room's centre, each reaching every visible surface; a cap of 4.
    const Scene scene = roomWith(lightsAroundTheCentre(24));
    const FrameOutput naive = renderOneFrame(config(), scene, settingsFor(LightCulling::Naive, kHardCaseSize));
    for (LightCulling mode : {LightCulling::Tiles2D, LightCulling::TilesDepth}) {
        const std::string label = fmt::format("Overflow-{}-{}", config().name(), cullingName(mode));
        RenderSettings settings = settingsFor(mode, kHardCaseSize);
        settings.lighting.maxLightsPerTile = 4;
        StderrCapture capture;
        const FrameOutput output = renderOneFrame(config(), scene, settings, ReadBack{.tiles = true});
        const std::string warnings = capture.take();
        expectFiniteHdr(output.hdr, label);
        ASSERT_TRUE(output.report.lightCulling.has_value()) << label;
        const LightCullingReport& culling = *output.report.lightCulling;
        EXPECT_EQ(culling.maxLightsPerTile, 4u) << label;
        EXPECT_GT(culling.overflowTiles, 0u) << label;
        EXPECT_GT(culling.droppedLights, 0u) << label;
        // Every tile sees all 24 lights: each overflowing tile drops 20.
        EXPECT_EQ(culling.droppedLights, uint64_t(culling.overflowTiles) * 20u) << label;
        // ... so the densest tile met all 24, and the warning says which cap would drop none.
        EXPECT_EQ(culling.densestTileLights, 24u) << label;
        EXPECT_NE(warnings.find("The densest tile met 24 lights: set maxLightsPerTile to 24 or more"), std::string::npos)
            << label << ": overflow must be warned about on stderr, with the cap that fits; got: " << warnings;
        ASSERT_TRUE(output.tiles.has_value()) << label;
        expectWellFormedTileLists(*output.tiles, culling, kHardCaseSize, kHardCaseSize, label);
        uint32_t fullTiles = 0;
        for (size_t t = 0; t < output.tiles->counts.size(); ++t) {
            if (output.tiles->counts[t] != 4u) continue;
            ++fullTiles;
            // The highest indices are the ones dropped.
            for (uint32_t k = 0; k < 4; ++k) EXPECT_EQ(output.tiles->indices[t * 4 + k], k) << label << " tile " << t;
        }
        EXPECT_EQ(fullTiles, culling.overflowTiles) << label;
        // Dropped lights are visible (which is why overflow must never be silent); this also shows
        // that the tiled-vs-naive image comparison of forward_plus_test.cpp catches missing lights.
        EXPECT_GT(compareImages(naive.display, output.display).maxChannelDifference, 1u) << label;
    }
}

// More lights than the former fixed cap of 256, each reaching every surface: the default
// (automatic) cap is the light count, so every tile lists every light and the image is naive's,
// bit for bit; the old fixed cap drops lights in the same scene.
TEST_P(LightSpecialCases, TheDefaultCapListsEveryLightATileMeets) {
    constexpr uint32_t kLights = 300;
    const Scene scene = roomWith(lightsAroundTheCentre(kLights));
    const FrameOutput naive = renderOneFrame(config(), scene, settingsFor(LightCulling::Naive, kHardCaseSize));
    for (LightCulling mode : {LightCulling::Tiles2D, LightCulling::TilesDepth}) {
        const std::string label = fmt::format("DefaultCap-{}-{}", config().name(), cullingName(mode));
        StderrCapture capture;
        const FrameOutput output = renderOneFrame(config(), scene, settingsFor(mode, kHardCaseSize), ReadBack{.tiles = true});
        const std::string warnings = capture.take();
        ASSERT_TRUE(output.report.lightCulling.has_value()) << label;
        const LightCullingReport& culling = *output.report.lightCulling;
        EXPECT_TRUE(culling.maxLightsPerTileAuto) << label;
        EXPECT_EQ(culling.maxLightsPerTile, kLights) << label;
        EXPECT_EQ(culling.densestTileLights, kLights) << label;
        EXPECT_EQ(culling.overflowTiles, 0u) << label;
        EXPECT_EQ(culling.droppedLights, 0u) << label;
        EXPECT_EQ(warnings.find("maxLightsPerTile"), std::string::npos) << label << ": " << warnings;
        ASSERT_TRUE(output.tiles.has_value()) << label;
        expectWellFormedTileLists(*output.tiles, culling, kHardCaseSize, kHardCaseSize, label);
        expectSameImage(naive, output, label);

        RenderSettings fixed = settingsFor(mode, kHardCaseSize);
        fixed.lighting.maxLightsPerTile = 256;
        StderrCapture quiet;
        const FrameOutput capped = renderOneFrame(config(), scene, fixed);
        EXPECT_FALSE(capped.report.lightCulling->maxLightsPerTileAuto) << label;
        EXPECT_GT(capped.report.lightCulling->droppedLights, 0u) << label << ": the scene must overflow a cap of 256";
    }
}

// More lights than the largest cap, each reaching every surface: the automatic cap stops at 1024,
// and the overflow warning says that an automatic cap was held there, and by what.
TEST_P(LightSpecialCases, AnAutomaticCapHeldAtTheLargestSaysSo) {
    constexpr uint32_t kLights = kMaxLightsPerTileLimit + 40;
    const std::string label = fmt::format("HeldCap-{}", config().name());
    StderrCapture capture;
    const FrameOutput output = renderOneFrame(config(), roomWith(lightsAroundTheCentre(kLights)), settingsFor(LightCulling::Tiles2D, 32));
    const std::string warnings = capture.take();
    expectFiniteHdr(output.hdr, label);
    ASSERT_TRUE(output.report.lightCulling.has_value()) << label;
    const LightCullingReport& culling = *output.report.lightCulling;
    EXPECT_TRUE(culling.maxLightsPerTileAuto) << label;
    EXPECT_EQ(culling.maxLightsPerTile, kMaxLightsPerTileLimit) << label;
    EXPECT_EQ(culling.densestTileLights, kLights) << label;
    EXPECT_EQ(culling.droppedLights, uint64_t(culling.overflowTiles) * 40u) << label;
    EXPECT_NE(warnings.find("lights (automatic, held at the largest cap, 1024)"), std::string::npos) << label << ": " << warnings;
    EXPECT_NE(warnings.find("more than maxLightsPerTile can be (1024): use smaller tiles"), std::string::npos) << label << ": " << warnings;
}

INSTANTIATE_TEST_SUITE_P(Configs, LightSpecialCases, testing::ValuesIn(allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
