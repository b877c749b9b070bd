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
    const std::vector<PairComparison> pairs = compareAllPairs({&a, &b}, tolerance, edgePixels);
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
    const PairComparison oneOver = compareAllPairs({&a, &b}, 1, 4).at(0);
    EXPECT_EQ(pairResultText(*oneOver.difference, 1, oneOver.passed), "ok (1 edge pixel)");
    const PairComparison same = compareAllPairs({&a, &a}, 1, 4).at(0);
    EXPECT_EQ(pairResultText(*same.difference, 1, same.passed), "ok");
    const PairComparison fiveOver = compareAllPairs({&a, &c}, 1, 4).at(0);
    EXPECT_EQ(pairResultText(*fiveOver.difference, 1, fiveOver.passed), "FAIL");
}

TEST(PairAgreement, ANotRenderedImageIsNotCompared) {
    const renderer::ImageRGBA8 a = image();
    const std::vector<PairComparison> pairs = compareAllPairs({&a, nullptr}, 1, 4);
    ASSERT_EQ(pairs.size(), 1u);
    EXPECT_FALSE(pairs[0].difference.has_value());
    EXPECT_FALSE(pairs[0].passed);
}

TEST(EdgePixelsOption, AcceptsCountsAndRefusesTheRest) {
    EXPECT_EQ(parseEdgePixels("0"), 0u);
    EXPECT_EQ(parseEdgePixels("4"), 4u);
    for (const char* bad : {"", "-1", "four", "4.5", "99999999999"}) EXPECT_THROW(parseEdgePixels(bad), UsageError) << bad;
}

}  // namespace
}  // namespace janus::cli
