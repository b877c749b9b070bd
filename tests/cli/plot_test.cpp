// The bench plots' tick labels (apps/janus/plot.cpp): measured values are labelled with three
// significant digits, and labels that would run into each other are left out rather than drawn
// over one another (`janus bench shadows` printed "1.10293.47455" under two close points).
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "plot.h"

namespace janus::cli {
namespace {

// Ink columns of the x tick labels: their rows (from y 508 of the 900x560 plot, below the x axis at
// 500-501 and the lowest y label, which ends at 505; above the axis title from 534), grouped into
// runs separated by 6 or more blank columns (inside a label, glyphs are 2 columns apart). Returns
// each run's width.
std::vector<int> labelWidths(const renderer::ImageRGBA8& plot) {
    std::vector<bool> ink(plot.width, false);
    for (uint32_t y = 507; y < 530; ++y)
        for (uint32_t x = 0; x < plot.width; ++x) {
            const uint8_t* p = &plot.pixels[(size_t(y) * plot.width + x) * 4];
            if (p[0] < 128 && p[1] < 128 && p[2] < 128) ink[x] = true;   // text is dark grey; grid lines are light
        }
    std::vector<int> widths;
    int start = -1, lastInk = -100;
    for (int x = 0; x < int(plot.width); ++x) {
        if (!ink[x]) continue;
        if (x - lastInk > 6) {
            if (start >= 0) widths.push_back(lastInk - start + 1);
            start = x;
        }
        lastInk = x;
    }
    if (start >= 0) widths.push_back(lastInk - start + 1);
    return widths;
}

TEST(Plot, CloseMeasuredValuesGetShortLabelsThatNeverRunTogether) {
    const PlotSeries shadows{"vulkan/compute", {{1.10293, 0.77}, {1.47455, 0.39}, {2.53963, 0.19}, {7.59487, 0.1}, {24.8737, 0.05}}};
    const std::vector<int> widths = labelWidths(drawLogXPlot({shadows}, "SHADOW PASS GPU MS", "MEAN ERROR (%)"));
    ASSERT_FALSE(widths.empty());
    // At most 4 characters a label ("24.9"): 4 glyphs of 6 columns and 3 gaps of 2 = 30 columns.
    for (int width : widths) EXPECT_LE(width, 30) << "a tick label is too long or runs into the next one";
    EXPECT_GE(widths.size(), 3u) << "the well-separated values keep their labels";
}

TEST(Plot, WholeNumbersKeepEveryDigit) {
    const PlotSeries forward{"naive", {{8, 1.0}, {2048, 100.0}}};
    const std::vector<int> widths = labelWidths(drawLogXPlot({forward}, "LIGHTS", "FRAME MS"));
    ASSERT_EQ(widths.size(), 2u);
    EXPECT_EQ(widths[1], 4 * 6 + 3 * 2) << "2048 should be written whole, not as 2.05e+03";
}

// A bench adds its rows' points one by one: each to the line of its name, lines in order of first use.
TEST(SeriesNamed, FindsTheLineOfANameOrAppendsIt) {
    std::vector<PlotSeries> series;
    seriesNamed(series, "vulkan/compute").points.push_back({1.0, 2.0});
    seriesNamed(series, "gl/compute").points.push_back({1.0, 3.0});
    seriesNamed(series, "vulkan/compute").points.push_back({2.0, 1.0});
    ASSERT_EQ(series.size(), 2u);
    EXPECT_EQ(series[0].name, "vulkan/compute");
    EXPECT_EQ(series[0].points.size(), 2u);
    EXPECT_EQ(series[1].name, "gl/compute");
    EXPECT_EQ(series[1].points.size(), 1u);
}

}  // namespace
}  // namespace janus::cli
