// A tiny line plot for `janus bench`: no plotting library in the dependency set, so lines,
// axes and a 3x5 bitmap font are drawn by hand into an RGBA8 image (written with writePNG).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "janus/renderer/image.h"

namespace janus::cli {

struct PlotSeries {
    std::string name;
    std::vector<std::pair<double, double>> points;   // (x, y), x > 0 and y > 0 (both axes are log10)
};

// The series called `name`, appended (without points) when `series` has none of that name: a
// bench adds its rows' points one by one, each to its line.
PlotSeries& seriesNamed(std::vector<PlotSeries>& series, const std::string& name);

// Log-log plot of every series with a legend; labels are upper-cased (the font has no lower case).
renderer::ImageRGBA8 drawLogXPlot(const std::vector<PlotSeries>& series, const std::string& xLabel, const std::string& yLabel);

}  // namespace janus::cli
