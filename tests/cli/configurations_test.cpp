// Unit tests of how `janus parity` and `janus check` decide that two configurations agree
// (apps/janus/configurations.*): within --tolerance, or at most --edge-pixels pixels beyond it.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "cli_common.h"
#include "configurations.h"

namespace janus::cli {
namespace {

// A grey 8x8 image, with `changed` pixels (from the first) raised by `steps`.
renderer::ImageRGBA8 image(uint32_t changed = 0, uint8_t steps = 0) {
    renderer::ImageRGBA8 result{8, 8, std::vector<uint8_t>(8 * 8 * 4, 100)};
    for (uint32_t p = 0; p < changed; ++p) result.pixels[p * 4] = uint8_t(100 + steps);
    return result;
}

bool agree(const renderer::ImageRGBA8& a, const renderer::ImageRGBA8& b, uint32_t tolerance, uint64_t edgePixels) {
    const std::vector<PairComparison> pairs = compareAllPairs({&a, &b}, renderer::ParityRule{tolerance, edgePixels});
    EXPECT_EQ(pairs.size(), 1u);
    return pairs.at(0).passed;
}

TEST(PairAgreement, WithinTheToleranceEveryPixelMayDiffer) {
    EXPECT_TRUE(agree(image(), image(64, 1), 1, 0));
    EXPECT_FALSE(agree(image(), image(64, 2), 1, 0));
}

TEST(PairAgreement, UpToEdgePixelsMayExceedTheTolerance) {
    EXPECT_TRUE(agree(image(), image(1, 2), 1, kDefaultEdgePixels)) << "one tie-break pixel, as DamagedHelmet at 512x512";
    EXPECT_TRUE(agree(image(), image(4, 200), 1, 4));
    EXPECT_FALSE(agree(image(), image(5, 2), 1, 4)) << "more pixels than the allowance: a real difference";
    EXPECT_FALSE(agree(image(), image(1, 2), 1, 0)) << "--edge-pixels 0 allows none";
}

TEST(PairAgreement, TheResultSaysWhenEdgePixelsWereAllowed) {
    const renderer::ImageRGBA8 a = image(), b = image(1, 2), c = image(5, 2);
    const renderer::ParityRule rule{1, 4};
    const PairComparison oneOver = compareAllPairs({&a, &b}, rule).at(0);
    EXPECT_EQ(pairResultText(*oneOver.difference, 1, oneOver.passed, oneOver.roundingPixels), "ok (1 edge pixel)");
    const PairComparison same = compareAllPairs({&a, &a}, rule).at(0);
    EXPECT_EQ(pairResultText(*same.difference, 1, same.passed, same.roundingPixels), "ok");
    const PairComparison fiveOver = compareAllPairs({&a, &c}, rule).at(0);
    EXPECT_EQ(pairResultText(*fiveOver.difference, 1, fiveOver.passed, fiveOver.roundingPixels), "FAIL");
}

rhi::DeviceInfo device(rhi::Backend backend, const char* name) {
    rhi::DeviceInfo info;
    info.backend = backend;
    info.deviceName = name;
    return info;
}

// --compiler-rounding auto: vulkan against gl on one hardware driver gets the allowance of
// janus/renderer/parity.h; the same images on Mesa (one compiler) or with off do not.
TEST(PairAgreement, TwoShaderCompilersMayRoundAFewPixelsFurther) {
    renderer::ImageRGBA8 a{40, 40, std::vector<uint8_t>(40 * 40 * 4, 100)};   // 1600 pixels: 4 of rounding
    renderer::ImageRGBA8 b = a;
    for (uint32_t p = 0; p < 8; ++p) b.pixels[p * 4] = 103;   // 8 pixels 3 steps off: 4 edge + 4 rounding
    const renderer::ParityRule rule{1, 4};
    const rhi::DeviceInfo vulkan = device(rhi::Backend::Vulkan, "NVIDIA H100 80GB HBM3");
    const rhi::DeviceInfo gl = device(rhi::Backend::GL, "NVIDIA H100 80GB HBM3/PCIe/SSE2");
    const PairComparison hardware = compareAllPairs({&a, &b}, rule, {&vulkan, &gl}).at(0);
    EXPECT_TRUE(hardware.twoCompilers);
    EXPECT_TRUE(hardware.passed);
    EXPECT_EQ(pairResultText(*hardware.difference, 1, hardware.passed, hardware.roundingPixels), "ok (8 pixels of compiler rounding)");
    const rhi::DeviceInfo lavapipe = device(rhi::Backend::Vulkan, "llvmpipe (LLVM 15.0.6, 256 bits)");
    const rhi::DeviceInfo llvmpipe = device(rhi::Backend::GL, "llvmpipe (LLVM 15.0.6, 256 bits)");
    const PairComparison mesa = compareAllPairs({&a, &b}, rule, {&lavapipe, &llvmpipe}).at(0);
    EXPECT_FALSE(mesa.twoCompilers);
    EXPECT_FALSE(mesa.passed);
    EXPECT_FALSE(compareAllPairs({&a, &b}, rule, {nullptr, nullptr}).at(0).passed) << "--compiler-rounding off passes no devices";
    // Beyond 4 steps the allowance takes nothing: a feature gone wrong.
    for (uint32_t p = 0; p < 8; ++p) b.pixels[p * 4] = 105;
    EXPECT_FALSE(compareAllPairs({&a, &b}, rule, {&vulkan, &gl}).at(0).passed);
}

TEST(CompilerRoundingOption, AutoOrOff) {
    EXPECT_TRUE(parseCompilerRounding("auto"));
    EXPECT_FALSE(parseCompilerRounding("off"));
    for (const char* bad : {"", "on", "AUTO", "1"}) EXPECT_THROW(parseCompilerRounding(bad), UsageError) << bad;
}

TEST(PairAgreement, ANotRenderedImageIsNotCompared) {
    const renderer::ImageRGBA8 a = image();
    const std::vector<PairComparison> pairs = compareAllPairs({&a, nullptr}, renderer::ParityRule{1, 4});
    ASSERT_EQ(pairs.size(), 1u);
    EXPECT_FALSE(pairs[0].difference.has_value());
    EXPECT_FALSE(pairs[0].passed);
}

TEST(EdgePixelsOption, AcceptsCountsAndRefusesTheRest) {
    EXPECT_EQ(parseEdgePixels("0"), 0u);
    EXPECT_EQ(parseEdgePixels("4"), 4u);
    for (const char* bad : {"", "-1", "four", "4.5", "99999999999"}) EXPECT_THROW(parseEdgePixels(bad), UsageError) << bad;
}

TEST(ConfigurationsOption, NamesEitherFormInTheUsualOrderOnce) {
    auto stems = [](std::string_view list) {
        std::vector<std::string> result;
        for (const Configuration& c : parseConfigurations(list)) result.push_back(configurationFileStem(c.backend, c.path));
        return result;
    };
    EXPECT_EQ(stems("gles/fallback,gl-compute"), (std::vector<std::string>{"gl-compute", "gles-fallback"}));
    EXPECT_EQ(stems("vulkan/compute,vulkan-compute"), (std::vector<std::string>{"vulkan-compute"}));
    EXPECT_EQ(stems("vulkan/compute,vulkan/fallback,gl/compute,gl/fallback,gles/fallback").size(), 5u);
}

TEST(ConfigurationsOption, RefusesWhatIsNoConfiguration) {
    for (const char* bad : {"", "gl", "gles/compute", "gl/compute,", ",gl/compute", "GL/compute", "gl/compute metal"}) {
        SCOPED_TRACE(bad);
        EXPECT_THROW(parseConfigurations(bad), UsageError);
    }
    try {
        parseConfigurations("gl/compute,metal");
        FAIL() << "metal was accepted";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("'metal' is not a configuration"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("gles/fallback"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace janus::cli
