// See plot.h.
#include "plot.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>

namespace janus::cli {
namespace {

// 3x5 glyphs, rows top to bottom, '#' = ink.
const char* glyph(char c) {
    // Rows separated by spaces for legibility; glyph() skips them.
    switch (std::toupper(static_cast<unsigned char>(c))) {
    case '0': return "### #.# #.# #.# ###";
    case '1': return ".#. ##. .#. .#. ###";
    case '2': return "### ..# ### #.. ###";
    case '3': return "### ..# ### ..# ###";
    case '4': return "#.# #.# ### ..# ..#";
    case '5': return "### #.. ### ..# ###";
    case '6': return "### #.. ### #.# ###";
    case '7': return "### ..# ..# ..# ..#";
    case '8': return "### #.# ### #.# ###";
    case '9': return "### #.# ### ..# ###";
    case 'A': return ".#. #.# ### #.# #.#";
    case 'B': return "##. #.# ##. #.# ##.";
    case 'C': return "### #.. #.. #.. ###";
    case 'D': return "##. #.# #.# #.# ##.";
    case 'E': return "### #.. ### #.. ###";
    case 'F': return "### #.. ### #.. #..";
    case 'G': return "### #.. #.# #.# ###";
    case 'H': return "#.# #.# ### #.# #.#";
    case 'I': return "### .#. .#. .#. ###";
    case 'J': return "..# ..# ..# #.# ###";
    case 'K': return "#.# #.# ##. #.# #.#";
    case 'L': return "#.. #.. #.. #.. ###";
    case 'M': return "#.# ### #.# #.# #.#";
    case 'N': return "##. #.# #.# #.# #.#";
    case 'O': return "### #.# #.# #.# ###";
    case 'P': return "### #.# ### #.. #..";
    case 'Q': return "### #.# #.# ### ..#";
    case 'R': return "### #.# ##. #.# #.#";
    case 'S': return "### #.. ### ..# ###";
    case 'T': return "### .#. .#. .#. .#.";
    case 'U': return "#.# #.# #.# #.# ###";
    case 'V': return "#.# #.# #.# #.# .#.";
    case 'W': return "#.# #.# #.# ### #.#";
    case 'X': return "#.# #.# .#. #.# #.#";
    case 'Y': return "#.# #.# .#. .#. .#.";
    case 'Z': return "### ..# .#. #.. ###";
    case '.': return "... ... ... ... .#.";
    case '-': return "... ... ### ... ...";
    case '/': return "..# ..# .#. #.. #..";
    case '(': return ".#. #.. #.. #.. .#.";
    case ')': return ".#. ..# ..# ..# .#.";
    case '%': return "#.. ..# .#. #.. ..#";
    case ',': return "... ... ... .#. #..";
    case ':': return "... .#. ... .#. ...";
    case '+': return "... .#. ### .#. ...";
    case '*': return "... #.# .#. #.# ...";
    default: return "... ... ... ... ...";
    }
}

constexpr int kGlyphAdvance = 8;   // a 3x5 glyph at scale 2 and its one-column space
constexpr int kLabelGap = 8;       // pixels between two tick labels at least

struct Canvas {
    renderer::ImageRGBA8 image;
    void pixel(int x, int y, uint32_t rgb) {
        if (x < 0 || y < 0 || x >= int(image.width) || y >= int(image.height)) return;
        uint8_t* p = &image.pixels[(size_t(y) * image.width + size_t(x)) * 4];
        p[0] = uint8_t(rgb >> 16), p[1] = uint8_t(rgb >> 8), p[2] = uint8_t(rgb), p[3] = 255;
    }
    void line(double x0, double y0, double x1, double y1, uint32_t rgb, int thickness = 1) {
        const int steps = int(std::max(std::abs(x1 - x0), std::abs(y1 - y0))) + 1;
        for (int i = 0; i <= steps; ++i) {
            const double t = double(i) / steps;
            const int x = int(std::lround(x0 + (x1 - x0) * t)), y = int(std::lround(y0 + (y1 - y0) * t));
            for (int dy = 0; dy < thickness; ++dy)
                for (int dx = 0; dx < thickness; ++dx) pixel(x + dx, y + dy, rgb);
        }
    }
    void text(int x, int y, const std::string& s, uint32_t rgb, int scale = 2) {
        for (char c : s) {
            const char* g = glyph(c);
            for (int row = 0; row < 5; ++row)
                for (int col = 0; col < 3; ++col)
                    if (g[row * 4 + col] == '#')
                        for (int sy = 0; sy < scale; ++sy)
                            for (int sx = 0; sx < scale; ++sx) pixel(x + col * scale + sx, y + row * scale + sy, rgb);
            x += kGlyphAdvance / 2 * scale;
        }
    }
};

// Three significant digits at most (measured times carry many): 1.10293 -> 1.1, 24.8737 -> 24.9;
// whole numbers up to 99999 whole (light counts: 2048).
std::string tickLabel(double value) {
    if (value >= 1 && value < 1e5 && value == std::floor(value)) return fmt::format("{:g}", value);
    return fmt::format("{:.3g}", value);
}

}  // namespace

PlotSeries& seriesNamed(std::vector<PlotSeries>& series, const std::string& name) {
    for (PlotSeries& s : series)
        if (s.name == name) return s;
    return series.emplace_back(PlotSeries{name, {}});
}

renderer::ImageRGBA8 drawLogXPlot(const std::vector<PlotSeries>& series, const std::string& xLabel, const std::string& yLabel) {
    constexpr int width = 900, height = 560, left = 70, right = 330, top = 30, bottom = 60;
    Canvas canvas{renderer::ImageRGBA8{width, height, std::vector<uint8_t>(size_t(width) * height * 4, 255)}};
    double xMin = INFINITY, xMax = -INFINITY, yMin = INFINITY, yMax = -INFINITY;
    for (const PlotSeries& s : series)
        for (const auto& [x, y] : s.points)
            if (x > 0 && y > 0) xMin = std::min(xMin, x), xMax = std::max(xMax, x), yMin = std::min(yMin, y), yMax = std::max(yMax, y);
    if (!(xMin < INFINITY)) xMin = 1, xMax = 10, yMin = 1, yMax = 10;
    // Whole decades on y, so the grid lines are round numbers.
    const double lx0 = std::log10(xMin) - 0.05, lx1 = std::log10(std::max(xMax, xMin * 10)) + 0.05;
    const double ly0 = std::floor(std::log10(yMin)), ly1 = std::max(std::ceil(std::log10(yMax)), ly0 + 1);
    const int plotW = width - left - right, plotH = height - top - bottom;
    auto px = [&](double x) { return left + (std::log10(x) - lx0) / (lx1 - lx0) * plotW; };
    auto py = [&](double y) { return top + plotH - (std::log10(y) - ly0) / (ly1 - ly0) * plotH; };

    for (double d = ly0; d <= ly1 + 1e-9; d += 1) {   // y decades
        const double y = py(std::pow(10.0, d));
        canvas.line(left, y, left + plotW, y, 0xDDDDDD);
        canvas.text(8, int(y) - 5, tickLabel(std::pow(10.0, d)), 0x333333);
    }
    std::vector<double> xs;
    for (const PlotSeries& s : series)
        for (const auto& point : s.points)
            if (std::find(xs.begin(), xs.end(), point.first) == xs.end()) xs.push_back(point.first);
    if (xs.size() > 12) {   // measured x values (times) would overlap: ticks at 1, 2, 5 x 10^k instead
        xs.clear();
        for (double d = std::floor(std::log10(xMin)); d <= std::ceil(std::log10(xMax)); d += 1)
            for (double m : {1.0, 2.0, 5.0})
                if (const double x = m * std::pow(10.0, d); x >= std::pow(10.0, lx0) && x <= std::pow(10.0, lx1)) xs.push_back(x);
    }
    std::sort(xs.begin(), xs.end());
    int labelsEnd = -1000;   // right edge of the last x label drawn: a label that would touch it is left out
    for (double x : xs) {
        canvas.line(px(x), top, px(x), top + plotH, 0xEEEEEE);
        const std::string label = tickLabel(x);
        const int start = int(px(x)) - 8;
        if (start < labelsEnd + kLabelGap) continue;
        canvas.text(start, top + plotH + 8, label, 0x333333);
        labelsEnd = start + int(label.size()) * kGlyphAdvance;
    }
    canvas.line(left, top, left, top + plotH, 0x000000, 2);
    canvas.line(left, top + plotH, left + plotW, top + plotH, 0x000000, 2);
    canvas.text(left + plotW / 2 - 30, height - 26, xLabel, 0x000000);
    canvas.text(8, 8, yLabel, 0x000000);

    const uint32_t palette[] = {0xD62728, 0x1F77B4, 0x2CA02C, 0xFF7F0E, 0x9467BD, 0x8C564B, 0xE377C2, 0x7F7F7F,
                                0xBCBD22, 0x17BECF, 0x000000, 0xAEC7E8};
    for (size_t i = 0; i < series.size(); ++i) {
        const uint32_t colour = palette[i % std::size(palette)];
        std::vector<std::pair<double, double>> points = series[i].points;
        std::sort(points.begin(), points.end());
        for (size_t p = 0; p + 1 < points.size(); ++p)
            canvas.line(px(points[p].first), py(points[p].second), px(points[p + 1].first), py(points[p + 1].second), colour, 2);
        for (const auto& [x, y] : points) canvas.line(px(x) - 2, py(y) - 2, px(x) + 2, py(y) + 2, colour, 2);
        const int legendY = top + 16 * int(i);
        canvas.line(width - right + 15, legendY + 5, width - right + 40, legendY + 5, colour, 3);
        canvas.text(width - right + 48, legendY, series[i].name, 0x000000);
    }
    return canvas.image;
}

}  // namespace janus::cli
