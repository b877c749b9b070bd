#include "core/texture_mips.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace janus::renderer {
namespace {

const std::array<float, 256> kSrgbToLinear = [] {
    std::array<float, 256> table{};
    for (size_t i = 0; i < table.size(); ++i) {
        const float c = float(i) / 255.0f;
        table[i] = c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
    }
    return table;
}();

// A linear value >= 0 to the nearest sRGB byte. Rounds half away from zero as std::lround would,
// without its call: the fraction of a float below 2^23 is exact.
uint8_t linearToSrgb(float c) {
    const float s = (c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f) * 255.0f;
    if (!(s > 0.0f)) return 0;
    if (s >= 255.0f) return 255;
    const int whole = int(s);
    return uint8_t(whole + (s - float(whole) >= 0.5f ? 1 : 0));
}

// Rows `top` and `bottom` of the level (the same row at an odd last one) into one output row.
template <bool kSrgb>
void boxRow(const uint8_t* top, const uint8_t* bottom, uint32_t width, uint8_t* out, uint32_t w) {
    for (uint32_t x = 0; x < w; ++x, out += 4) {
        const size_t left = size_t(std::min(2 * x, width - 1)) * 4, right = size_t(std::min(2 * x + 1, width - 1)) * 4;
        for (size_t c = 0; c < 4; ++c) {
            if (kSrgb && c < 3) {
                // Summed in this order, from the first: the same float on every machine.
                float sum = kSrgbToLinear[top[left + c]];
                sum += kSrgbToLinear[top[right + c]];
                sum += kSrgbToLinear[bottom[left + c]];
                sum += kSrgbToLinear[bottom[right + c]];
                out[c] = linearToSrgb(sum / 4.0f);
            } else {
                out[c] = uint8_t((unsigned(top[left + c]) + top[right + c] + bottom[left + c] + bottom[right + c] + 2) >> 2);
            }
        }
    }
}

}  // namespace

std::vector<uint8_t> nextMipLevel(std::span<const uint8_t> rgba, uint32_t width, uint32_t height, bool srgb) {
    const uint32_t w = std::max(width / 2, 1u), h = std::max(height / 2, 1u);
    std::vector<uint8_t> dst(size_t(w) * h * 4);
    const size_t stride = size_t(width) * 4;
    for (uint32_t y = 0; y < h; ++y) {
        const uint8_t* top = rgba.data() + std::min(2 * y, height - 1) * stride;
        const uint8_t* bottom = rgba.data() + std::min(2 * y + 1, height - 1) * stride;
        uint8_t* out = dst.data() + size_t(y) * w * 4;
        if (srgb)
            boxRow<true>(top, bottom, width, out, w);
        else
            boxRow<false>(top, bottom, width, out, w);
    }
    return dst;
}

std::vector<std::vector<uint8_t>> mipChainBelow(std::span<const uint8_t> rgba, uint32_t width, uint32_t height, bool srgb) {
    std::vector<std::vector<uint8_t>> levels;
    while (width > 1 || height > 1) {
        levels.push_back(nextMipLevel(levels.empty() ? rgba : std::span<const uint8_t>(levels.back()), width, height, srgb));
        width = std::max(width / 2, 1u);
        height = std::max(height / 2, 1u);
    }
    return levels;
}

}  // namespace janus::renderer
