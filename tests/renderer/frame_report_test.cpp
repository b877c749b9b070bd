// FrameReport::toJson and the FeaturePath / LightCulling / DebugView names: what `janus render
// --report` and benchmarks read. Also the tile heat map debug view on every configuration.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "janus/renderer/image.h"
#include "janus/renderer/renderer.h"
#include "renderer_test_support.h"

namespace janus::renderer {
namespace {

TEST(FrameReport, JsonHasEveryFieldAndNullForMissingTimers) {
    FrameReport report;
    report.backend = "gles";
    report.path = "fallback";
    report.width = 128;
    report.height = 64;
    report.views.push_back(ViewReport{"main", 128, 64});
    report.passes.push_back(PassReport{"forward", 1.5, 0.25, 18, 0, "main"});
    report.passes.push_back(PassReport{"tonemap-fallback", std::nullopt, 0.125, 1, 0});
    const nlohmann::json json = report.toJson();
    EXPECT_EQ(json.at("backend"), "gles");
    EXPECT_EQ(json.at("path"), "fallback");
    EXPECT_EQ(json.at("width"), 128);
    EXPECT_EQ(json.at("height"), 64);
    ASSERT_EQ(json.at("passes").size(), 2u);
    const nlohmann::json& forward = json["passes"][0];
    EXPECT_EQ(forward.at("name"), "forward");
    EXPECT_EQ(forward.at("view"), "main");
    ASSERT_EQ(json.at("views").size(), 1u);
    EXPECT_EQ(json["views"][0].at("name"), "main");
    EXPECT_EQ(json["views"][0].at("width"), 128);
    EXPECT_EQ(json["views"][0].at("height"), 64);
    EXPECT_EQ(json["passes"][1].at("view"), "");
    EXPECT_EQ(forward.at("gpuMs"), 1.5);
    EXPECT_EQ(forward.at("cpuMs"), 0.25);
    EXPECT_EQ(forward.at("draws"), 18);
    EXPECT_EQ(forward.at("dispatches"), 0);
    EXPECT_TRUE(json["passes"][1].at("gpuMs").is_null());
    EXPECT_EQ(json.at("performanceMessages"), nlohmann::json::array());
}


TEST(FeaturePath, NamesRoundTrip) {
    for (FeaturePath path : {FeaturePath::Compute, FeaturePath::Fallback}) EXPECT_EQ(parseFeaturePath(toString(path)), path);
    EXPECT_EQ(parseFeaturePath("Compute"), std::nullopt);
    EXPECT_EQ(parseFeaturePath(""), std::nullopt);
}

TEST(LightCulling, NamesRoundTrip) {
    for (LightCulling mode : {LightCulling::Auto, LightCulling::Naive, LightCulling::Tiles2D, LightCulling::TilesDepth})
        EXPECT_EQ(parseLightCulling(toString(mode)), mode);
    EXPECT_STREQ(toString(LightCulling::Tiles2D), "tiles-2d");
    EXPECT_STREQ(toString(LightCulling::TilesDepth), "tiles-depth");
    EXPECT_EQ(parseLightCulling("Naive"), std::nullopt);
    EXPECT_EQ(parseLightCulling("tiles"), std::nullopt);
}

TEST(DebugView, NamesRoundTrip) {
    for (DebugView view : {DebugView::None, DebugView::Tiles, DebugView::Gi, DebugView::GiLight, DebugView::Shadow})
        EXPECT_EQ(parseDebugView(toString(view)), view);
    EXPECT_STREQ(toString(DebugView::Shadow), "shadow");
    EXPECT_EQ(parseDebugView("heatmap"), std::nullopt);
    EXPECT_EQ(parseDebugView("Shadow"), std::nullopt);
}

TEST(FrameReport, JsonHasTheLightCullingReportOnlyWhenPresent) {
    FrameReport report;
    EXPECT_FALSE(report.toJson().contains("lightCulling"));
    LightCullingReport culling;
    culling.mode = LightCulling::TilesDepth;
    culling.builder = "cpu";
    culling.directionalLights = 1;
    culling.localLights = 300;
    culling.tileSize = 16;
    culling.tilesX = 8;
    culling.tilesY = 4;
    culling.maxLightsPerTile = 64;
    culling.listedLights = 5000000000ull;   // past 32 bits: the JSON must keep it
    culling.overflowTiles = 3;
    culling.droppedLights = 7;
    report.lightCulling = culling;
    const nlohmann::json json = report.toJson().at("lightCulling");
    EXPECT_EQ(json.at("mode"), "tiles-depth");
    EXPECT_EQ(json.at("builder"), "cpu");
    EXPECT_EQ(json.at("directionalLights"), 1);
    EXPECT_EQ(json.at("localLights"), 300);
    EXPECT_EQ(json.at("tileSize"), 16);
    EXPECT_EQ(json.at("tilesX"), 8);
    EXPECT_EQ(json.at("tilesY"), 4);
    EXPECT_EQ(json.at("maxLightsPerTile"), 64);
    EXPECT_EQ(json.at("listedLights"), 5000000000ull);
    EXPECT_EQ(json.at("overflowTiles"), 3);
    EXPECT_EQ(json.at("droppedLights"), 7);
}

using test_support::Config;

class TileHeatmap : public testing::TestWithParam<Config> {};

// The heat map joins the plan after tonemapping, changes the display image (not the HDR image)
// and marks tiles at the cap; without tiles it is left out.
TEST_P(TileHeatmap, DrawsOverTheDisplayImageOnlyWhenTilesExist) {
    const Config& config = GetParam();
    const Scene scene = manyLightsScene(ManyLightsOptions{64});
    RenderSettings plain = test_support::settingsFor(LightCulling::TilesDepth);
    plain.lighting.maxLightsPerTile = 4;   // low enough that some tiles reach the cap
    RenderSettings debug = plain;
    debug.debugView = DebugView::Tiles;
    const test_support::FrameOutput without = test_support::renderOneFrame(config, scene, plain);
    const test_support::FrameOutput with = test_support::renderOneFrame(config, scene, debug);

    ASSERT_FALSE(with.report.passes.empty());
    EXPECT_EQ(with.report.passes.back().name, "tile-heatmap") << test_support::passNames(with.report);
    EXPECT_FALSE(test_support::hasPassStartingWith(without.report, "tile-heatmap"));
    ASSERT_TRUE(with.report.lightCulling);
    EXPECT_GT(with.report.lightCulling->overflowTiles, 0u) << "the test needs tiles at the cap";
    EXPECT_EQ(with.hdr.pixels, without.hdr.pixels) << "the debug view must not change the radiance";
    // Most pixels change (every tile gets a colour); the hatch of tiles at the cap is opaque white,
    // which nothing else produces: each heat colour has a zero channel, blended at 45 %.
    const ImageDifference diff = compareImages(without.display, with.display, 0);
    EXPECT_GT(diff.differingPixels, uint64_t(with.display.width) * with.display.height / 2);
    bool white = false;
    for (size_t i = 0; i + 3 < with.display.pixels.size() && !white; i += 4)
        white = with.display.pixels[i] == 255 && with.display.pixels[i + 1] == 255 && with.display.pixels[i + 2] == 255;
    EXPECT_TRUE(white) << "no hatch on tiles at the cap";
    writePNG(test_support::outputDir() / fmt::format("tile-heatmap-{}.png", config.name()), with.display);

    RenderSettings naive = test_support::settingsFor(LightCulling::Naive);
    naive.debugView = DebugView::Tiles;
    const test_support::FrameOutput noTiles = test_support::renderOneFrame(config, scene, naive);
    EXPECT_FALSE(test_support::hasPassStartingWith(noTiles.report, "tile-heatmap")) << test_support::passNames(noTiles.report);
}

// The hatch marks tiles that may have dropped lights. An automatic cap is the light count, so a
// tile at it met every light and dropped none: no hatch, though tiles are at the cap.
TEST_P(TileHeatmap, AnAutomaticCapOfEveryLightHatchesNoTile) {
    const Config& config = GetParam();
    ManyLightsOptions options;
    options.lightCount = 3;
    options.rangeFraction = 2.0f;   // every light reaches every tile
    RenderSettings debug = test_support::settingsFor(LightCulling::TilesDepth);
    debug.debugView = DebugView::Tiles;
    const test_support::FrameOutput with = test_support::renderOneFrame(config, manyLightsScene(options), debug);
    ASSERT_TRUE(with.report.lightCulling);
    const LightCullingReport& culling = *with.report.lightCulling;
    EXPECT_TRUE(culling.maxLightsPerTileAuto);
    EXPECT_EQ(culling.maxLightsPerTile, 3u);
    EXPECT_EQ(culling.densestTileLights, 3u) << "the test needs tiles at the cap";
    EXPECT_EQ(culling.overflowTiles, 0u);
    EXPECT_TRUE(test_support::hasPassStartingWith(with.report, "tile-heatmap")) << test_support::passNames(with.report);
    for (size_t i = 0; i + 3 < with.display.pixels.size(); i += 4)
        ASSERT_FALSE(with.display.pixels[i] == 255 && with.display.pixels[i + 1] == 255 && with.display.pixels[i + 2] == 255)
            << "pixel " << i / 4 << " is hatched, but no tile can have dropped a light";
}

// One colour is one density: red at 256 lights (or a lower cap), so a scene's heat map does not
// change when an automatic cap above 256 was chosen for it.
TEST_P(TileHeatmap, TheColourScaleDoesNotDependOnAnAutomaticCap) {
    const Config& config = GetParam();
    const Scene scene = manyLightsScene(ManyLightsOptions{300});
    RenderSettings automatic = test_support::settingsFor(LightCulling::TilesDepth);
    automatic.debugView = DebugView::Tiles;
    RenderSettings fixed = automatic;
    fixed.lighting.maxLightsPerTile = 256;
    const test_support::FrameOutput a = test_support::renderOneFrame(config, scene, automatic);
    const test_support::FrameOutput b = test_support::renderOneFrame(config, scene, fixed);
    ASSERT_TRUE(a.report.lightCulling && b.report.lightCulling);
    EXPECT_EQ(a.report.lightCulling->maxLightsPerTile, 300u);
    EXPECT_LT(b.report.lightCulling->densestTileLights, 256u) << "the test needs no tile at the fixed cap (no hatch)";
    EXPECT_EQ(a.display.pixels, b.display.pixels);
}

INSTANTIATE_TEST_SUITE_P(Configs, TileHeatmap, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

class PerformanceMessages : public testing::TestWithParam<Config> {};

// The driver's performance messages during a frame land in its report (and so in `janus render`'s
// output and JSON), not among the validation messages the suites fail on.
TEST_P(PerformanceMessages, AreCountedInTheFrameReport) {
    rhi::IDevice& device = test_support::deviceFor(GetParam().backend);
    RenderSettings settings = test_support::settingsFor(LightCulling::Naive, 32);
    settings.path = GetParam().path;
    Renderer renderer(device, defaultScene(), settings);
    renderer.renderFrame();
    device.takeDebugMessages();
    device.insertPerformanceMessageForTesting("janus test: a slow path before the frame");
    const FrameReport report = renderer.renderFrame();
    ASSERT_EQ(report.performanceMessages.size(), 1u) << GetParam().name();
    EXPECT_NE(report.performanceMessages[0].find("janus test: a slow path before the frame"), std::string::npos)
        << report.performanceMessages[0];
    EXPECT_EQ(report.toJson().at("performanceMessages").size(), 1u);
    EXPECT_TRUE(device.takeDebugMessages().empty()) << GetParam().name();
    EXPECT_TRUE(renderer.renderFrame().performanceMessages.empty()) << "each message is reported once";
}

INSTANTIATE_TEST_SUITE_P(Configs, PerformanceMessages, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
