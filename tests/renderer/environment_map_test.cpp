// The environment map (renderer/src/ibl/environment_map.*): the Radiance HDR loader, the
// equirect <-> direction mapping on the CPU, and the GPU conversion to a cube on every
// configuration (validation on).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "janus/renderer/image.h"
#include "renderer_test_support.h"
// Internal to the renderer.
#include "../../renderer/src/ibl/environment_map.h"
#include "../../renderer/src/ibl/ggx_prefilter.h"

namespace janus::renderer {
namespace {

using test_support::Config;

const std::filesystem::path kSharedSky = std::filesystem::path(JANUS_SHARED_SCENES_DIR) / "env" / "chinese_garden_1k.hdr";

TEST(RadianceHdr, TheSharedSkyLoadsAs1024x512FiniteRadiance) {
    ASSERT_TRUE(std::filesystem::exists(kSharedSky)) << kSharedSky << " is missing: the suite runs with ../shared beside the repository";
    const ImageRGBAF sky = readRadianceHDR(kSharedSky);
    ASSERT_EQ(sky.width, 1024u);
    ASSERT_EQ(sky.height, 512u);
    ASSERT_EQ(sky.pixels.size(), size_t(1024) * 512 * 4);
    float brightest = 0.0f;
    for (size_t i = 0; i < sky.pixels.size(); ++i) {
        ASSERT_TRUE(std::isfinite(sky.pixels[i]) && sky.pixels[i] >= 0.0f) << "value " << i;
        if (i % 4 == 3) ASSERT_EQ(sky.pixels[i], 1.0f);
        else brightest = std::max(brightest, sky.pixels[i]);
    }
    EXPECT_GT(brightest, 1.0f) << "an HDR sky has radiance above 1 somewhere";
}

std::string messageOf(const std::filesystem::path& path) {
    try {
        readRadianceHDR(path);
    } catch (const ImageIOError& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(RadianceHdr, AMissingOrGarbageFileGivesAClearError) {
    const std::filesystem::path dir = test_support::outputDir();
    std::filesystem::create_directories(dir);
    const std::filesystem::path missing = dir / "no_such_sky.hdr";
    std::filesystem::remove(missing);
    EXPECT_NE(messageOf(missing).find("no such file"), std::string::npos) << messageOf(missing);

    const std::filesystem::path garbage = dir / "garbage_sky.hdr";
    std::ofstream(garbage, std::ios::binary) << "this is not a picture of the sky";
    EXPECT_NE(messageOf(garbage).find("not a Radiance HDR"), std::string::npos) << messageOf(garbage);

    // An LDR image would decode through stbi_loadf (gamma-converted); it is refused instead.
    const std::filesystem::path png = dir / "ldr_sky.hdr";
    ImageRGBA8 tiny{2, 2, std::vector<uint8_t>(16, 200)};
    writePNG(png, tiny);
    EXPECT_NE(messageOf(png).find("not a Radiance HDR"), std::string::npos) << messageOf(png);

    // A header that claims an absurd size is refused before anything is decoded.
    const std::filesystem::path huge = dir / "huge_sky.hdr";
    std::ofstream(huge, std::ios::binary) << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 100000\n";
    EXPECT_NE(messageOf(huge).find("outside"), std::string::npos) << messageOf(huge);
}

TEST(EquirectMapping, DirectionsAndUvsAgreeWithTheDocumentedConvention) {
    auto near = [](glm::dvec3 a, glm::dvec3 b) { return glm::length(a - b) < 1e-12; };
    EXPECT_TRUE(near(equirectDirection({0.5, 0.5}), {0, 0, -1}));   // image centre: -Z
    EXPECT_TRUE(near(equirectDirection({0.75, 0.5}), {1, 0, 0}));   // +X
    EXPECT_TRUE(near(equirectDirection({0.25, 0.5}), {-1, 0, 0}));  // -X
    EXPECT_TRUE(near(equirectDirection({0.0, 0.5}), {0, 0, 1}));    // +Z at u = 0 (and 1)
    EXPECT_TRUE(near(equirectDirection({0.3, 0.0}), {0, 1, 0}));    // row 0: +Y
    for (double u = 0.05; u < 1.0; u += 0.1)
        for (double v = 0.05; v < 1.0; v += 0.1) {
            const glm::dvec2 back = equirectUv(equirectDirection({u, v}));
            EXPECT_NEAR(back.x, u, 1e-12);
            EXPECT_NEAR(back.y, v, 1e-12);
        }
    double total = 0.0;
    for (uint32_t y = 0; y < 7; ++y)
        for (uint32_t x = 0; x < 7; ++x) total += cubeTexelSolidAngle(x, y, 7);
    EXPECT_NEAR(6.0 * total, 4.0 * 3.14159265358979323846, 1e-12);
}

class EnvironmentMapTest : public testing::TestWithParam<Config> {
protected:
    rhi::IDevice& device() { return test_support::deviceFor(GetParam().backend); }
    void expectNoMessages() {
        const std::vector<rhi::DebugMessage> messages = device().takeDebugMessages();
        EXPECT_TRUE(messages.empty()) << GetParam().name() << ":" << test_support::joinMessages(messages);
    }
};

// An equirect whose colour is 0.5 + 0.5 * (the direction at each pixel centre): the cube must show
// 0.5 + 0.5 * (its own texel directions).
TEST_P(EnvironmentMapTest, AnAnalyticEquirectLandsOnTheRightCubeTexels) {
    device().takeDebugMessages();
    constexpr uint32_t kWidth = 512, kHeight = 256, kFace = 32;
    ImageRGBAF equirect{kWidth, kHeight, std::vector<float>(size_t(kWidth) * kHeight * 4)};
    for (uint32_t y = 0; y < kHeight; ++y)
        for (uint32_t x = 0; x < kWidth; ++x) {
            const glm::dvec3 d = equirectDirection({(x + 0.5) / kWidth, (y + 0.5) / kHeight});
            float* p = equirect.pixels.data() + (size_t(y) * kWidth + x) * 4;
            p[0] = float(0.5 + 0.5 * d.x), p[1] = float(0.5 + 0.5 * d.y), p[2] = float(0.5 + 0.5 * d.z), p[3] = 1.0f;
        }
    EnvironmentMap environment(device(), equirect, kFace, GetParam().path);
    const PassReport report = environment.convert();
    if (GetParam().path == FeaturePath::Compute) {
        EXPECT_EQ(report.name, "equirect-to-cube-compute");
        EXPECT_EQ(report.dispatches, 1u);   // all six faces in one dispatch
        EXPECT_EQ(report.draws, 0u);
    } else {
        EXPECT_EQ(report.name, "equirect-to-cube-fallback");
        EXPECT_EQ(report.draws, 6u);        // one per face
        EXPECT_EQ(report.dispatches, 0u);
    }
    EXPECT_EQ(environment.cube()->desc().mipLevels, rhi::fullMipCount(kFace, kFace));
    const FloatCube cube = readCube(device(), environment.cube(), 0);
    // Tolerance: fp16 storage rounds values in [0.5, 1] to 2.4e-4; bilinear interpolation of a
    // unit vector between pixel centres 0.7 degrees apart is off by < 2e-5; within half a row of
    // a pole v is clamped (up to 0.35 degrees, 3e-3), but no 32^2 face texel centre is that close.
    constexpr double kTolerance = 1e-3;
    double worst = 0.0;
    for (uint32_t face = 0; face < 6; ++face)
        for (uint32_t y = 0; y < kFace; ++y)
            for (uint32_t x = 0; x < kFace; ++x) {
                const glm::dvec3 expected = 0.5 + 0.5 * cubeTexelDirection(face, x, y, kFace);
                const glm::dvec3 got = cube.texel(face, x, y);
                const double error = glm::length(got - expected) / std::sqrt(3.0);
                worst = std::max(worst, error);
                ASSERT_LT(error, kTolerance) << GetParam().name() << " face " << face << " texel (" << x << ", " << y << ")";
            }
    RecordProperty("max_error", fmt::format("{:.2e}", worst));
    std::cout << GetParam().name() << ": equirect->cube max error " << worst << "\n";
    expectNoMessages();
}

TEST_P(EnvironmentMapTest, TheSharedSkyConvertsAndPrefiltersToFiniteRadiance) {
    ASSERT_TRUE(std::filesystem::exists(kSharedSky)) << kSharedSky << " is missing: the suite runs with ../shared beside the repository";
    device().takeDebugMessages();
    static const ImageRGBAF sky = readRadianceHDR(kSharedSky);
    EnvironmentMap environment(device(), sky, 32, GetParam().path);
    GgxPrefilter prefilter(device(), GetParam().path);
    // The two as passes of one graph, as a frame would add them.
    PassGraph graph;
    const ViewTarget cube = environment.addPasses(graph);
    const ViewTarget prefiltered = prefilter.addPasses(graph, cube);
    graph.markOutput(prefiltered.resource);
    graph.compile(device());
    const std::vector<PassReport> reports = graph.execute(device(), device().createCommandList());
    ASSERT_EQ(reports.size(), 2u);
    for (uint32_t mip = 0; mip < prefilter.mipCount(); ++mip) {
        const FloatCube image = readCube(device(), prefilter.prefiltered(), mip);
        for (uint32_t face = 0; face < 6; ++face)
            for (float v : image.faces[face]) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << "mip " << mip << " face " << face;
    }
    expectNoMessages();
}

INSTANTIATE_TEST_SUITE_P(Configs, EnvironmentMapTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
