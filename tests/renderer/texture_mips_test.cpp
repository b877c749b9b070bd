// The CPU mip chain of scene textures (renderer/src/core/texture_mips.h): every level against the
// box filter written out the plain way, byte for byte, on sizes with odd sides.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "core/texture_mips.h"

namespace janus::renderer {
namespace {

// The recipe, one texel and channel at a time, in float: sRGB to linear by
// the formula, the four texels summed in row order, back to sRGB with std::lround.
std::vector<uint8_t> plainNextMip(const std::vector<uint8_t>& src, uint32_t width, uint32_t height, bool srgb) {
    auto toLinear = [](uint8_t v) {
        const float c = float(v) / 255.0f;
        return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
    };
    auto toSrgb = [](float c) {
        const float s = c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
        return uint8_t(std::clamp(std::lround(s * 255.0f), 0L, 255L));
    };
    const uint32_t w = std::max(width / 2, 1u), h = std::max(height / 2, 1u);
    std::vector<uint8_t> dst(size_t(w) * h * 4);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            for (uint32_t c = 0; c < 4; ++c) {
                float sum = 0.0f;
                for (uint32_t dy = 0; dy < 2; ++dy)
                    for (uint32_t dx = 0; dx < 2; ++dx) {
                        const uint32_t sx = std::min(x * 2 + dx, width - 1), sy = std::min(y * 2 + dy, height - 1);
                        const uint8_t v = src[(size_t(sy) * width + sx) * 4 + c];
                        sum += (srgb && c < 3) ? toLinear(v) : float(v);
                    }
                const float average = sum / 4.0f;
                dst[(size_t(y) * w + x) * 4 + c] =
                    (srgb && c < 3) ? toSrgb(average) : uint8_t(std::clamp(std::lround(average), 0L, 255L));
            }
    return dst;
}

TEST(TextureMips, EveryLevelIsThePlainBoxFilterByteForByte) {
    std::mt19937 random(7);
    std::uniform_int_distribution<int> byte(0, 255);
    for (const auto [width, height] : {std::pair{1u, 1u}, {2u, 2u}, {3u, 5u}, {7u, 2u}, {1u, 9u}, {64u, 33u}, {129u, 130u}}) {
        for (const bool srgb : {false, true}) {
            std::vector<uint8_t> level(size_t(width) * height * 4);
            for (uint8_t& v : level) v = uint8_t(byte(random));
            uint32_t w = width, h = height;
            while (w > 1 || h > 1) {
                const std::vector<uint8_t> expected = plainNextMip(level, w, h, srgb);
                const std::vector<uint8_t> actual = nextMipLevel(level, w, h, srgb);
                ASSERT_EQ(actual, expected) << width << "x" << height << (srgb ? " sRGB" : " linear") << " at level " << w << "x" << h;
                level = actual;
                w = std::max(w / 2, 1u);
                h = std::max(h / 2, 1u);
            }
        }
    }
}

TEST(TextureMips, TheChainIsEveryLevelDownToOneTexel) {
    std::vector<uint8_t> image(size_t(13) * 6 * 4);
    for (size_t i = 0; i < image.size(); ++i) image[i] = uint8_t(i * 37);
    const std::vector<std::vector<uint8_t>> chain = mipChainBelow(image, 13, 6, true);
    ASSERT_EQ(chain.size(), 3u);   // 6x3, 3x1, 1x1
    EXPECT_EQ(chain[0], nextMipLevel(image, 13, 6, true));
    EXPECT_EQ(chain[1], nextMipLevel(chain[0], 6, 3, true));
    EXPECT_EQ(chain[2], nextMipLevel(chain[1], 3, 1, true));
    EXPECT_EQ(chain[2].size(), 4u);
    EXPECT_TRUE(mipChainBelow(std::vector<uint8_t>{1, 2, 3, 4}, 1, 1, false).empty());
}

TEST(TextureMips, EveryPairOfSrgbValuesAveragesInLinearLight) {
    // Every pair of sRGB bytes (a 2x2 box of two columns): the whole table of what the filter can
    // meet between two texels, including the halves that round.
    for (int a = 0; a < 256; ++a) {
        std::vector<uint8_t> image;
        for (int b = 0; b < 256; ++b) {
            const uint8_t texel[8] = {uint8_t(a), uint8_t(b), uint8_t(a), uint8_t(a), uint8_t(b), uint8_t(a), uint8_t(b), uint8_t(b)};
            image.insert(image.end(), texel, texel + 8);
        }
        // 512 x 1: each output texel boxes texel 2k (a, b, a, a) with texel 2k+1 (b, a, b, b).
        for (const bool srgb : {false, true})
            ASSERT_EQ(nextMipLevel(image, 512, 1, srgb), plainNextMip(image, 512, 1, srgb)) << "a " << a << (srgb ? " sRGB" : "");
    }
    // Linear light, not the bytes' mean: black and white make 188, not 128; alpha is 128.
    const std::vector<uint8_t> blackWhite = {0, 0, 0, 0, 255, 255, 255, 255};
    EXPECT_EQ(nextMipLevel(blackWhite, 2, 1, true), (std::vector<uint8_t>{188, 188, 188, 128}));
    EXPECT_EQ(nextMipLevel(blackWhite, 2, 1, false), (std::vector<uint8_t>{128, 128, 128, 128}));
}

}  // namespace
}  // namespace janus::renderer
