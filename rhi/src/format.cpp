#include "janus/rhi/format.h"

#include <algorithm>
#include <array>

namespace janus::rhi {

namespace {
constexpr std::array kFormats = {
    FormatInfo{Format::Unknown, "unknown", 0, 0, FormatKind::UNorm, false},
    FormatInfo{Format::RGBA8_UNORM, "rgba8", 4, 4, FormatKind::UNorm, false},
    FormatInfo{Format::RGBA8_SRGB, "rgba8_srgb", 4, 4, FormatKind::UNorm, true},
    FormatInfo{Format::RGBA16_FLOAT, "rgba16f", 8, 4, FormatKind::Float, false},
    FormatInfo{Format::RGBA32_FLOAT, "rgba32f", 16, 4, FormatKind::Float, false},
    FormatInfo{Format::R11G11B10_FLOAT, "r11g11b10f", 4, 3, FormatKind::Float, false},
    FormatInfo{Format::R32_UINT, "r32ui", 4, 1, FormatKind::UInt, false},
    FormatInfo{Format::RGBA32_UINT, "rgba32ui", 16, 4, FormatKind::UInt, false},
    FormatInfo{Format::R32_FLOAT, "r32f", 4, 1, FormatKind::Float, false},
    FormatInfo{Format::D32_FLOAT, "d32f", 4, 1, FormatKind::Depth, false},
};
}  // namespace

const FormatInfo& formatInfo(Format format) {
    for (const auto& info : kFormats)
        if (info.format == format) return info;
    return kFormats[0];
}

std::optional<Format> parseFormat(std::string_view name) {
    for (const auto& info : kFormats)
        if (info.format != Format::Unknown && name == info.name) return info.format;
    return std::nullopt;
}

uint32_t fullMipCount(uint32_t width, uint32_t height, uint32_t depth) {
    uint32_t largest = std::max({width, height, depth, 1u});
    uint32_t levels = 1;
    while (largest > 1) { largest >>= 1; ++levels; }
    return levels;
}

}  // namespace janus::rhi
