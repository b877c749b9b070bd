// The mip chains of scene textures, made on the CPU rather than with generateMips so that every
// backend samples the same texels (docs/ARCHITECTURE.md, the frame's upload step).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace janus::renderer {

// The next mip level of a width x height RGBA8 image (rows tightly packed): a 2x2 box filter,
// max(width / 2, 1) x max(height / 2, 1); an odd last column or row repeats into its box. sRGB
// colour is averaged in linear light (alpha, and every channel of a linear image, as integers
// rounded half up). Each level is exact: the same bytes on every machine.
std::vector<uint8_t> nextMipLevel(std::span<const uint8_t> rgba, uint32_t width, uint32_t height, bool srgb);

// Every level below a width x height image, each from the one above it: level 1 first, down to
// 1 x 1 (rhi::fullMipCount(width, height) - 1 levels).
std::vector<std::vector<uint8_t>> mipChainBelow(std::span<const uint8_t> rgba, uint32_t width, uint32_t height, bool srgb);

}  // namespace janus::renderer
