#include "janus/rhi/format.h"

#include <algorithm>
#include <array>

namespace janus::rhi {

std::string FormatCapabilities::sampleCountText(uint32_t counts, std::string_view separator) {
    std::string text;
    for (uint32_t count = 1; count != 0; count <<= 1)
        if (counts & count) {
            if (!text.empty()) text += separator;
            text += std::to_string(count);
        }
    return text.empty() ? "none" : text;
}

namespace {
// The one table of what formats are made of. Adding a format: a row here (in enum order), the
// enum entry in format.h, and each backend's mapping (toVkFormat, glFormat and its capability
// rules); see docs/ARCHITECTURE.md, "How to add a format".
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

constexpr bool inEnumOrder() {
    for (size_t i = 0; i < kFormats.size(); ++i)
        if (kFormats[i].format != Format(i)) return false;
    return true;
}
static_assert(inEnumOrder(), "kFormats rows must follow the order of enum Format (it is indexed by it)");
}  // namespace

const FormatInfo& formatInfo(Format format) {
    const auto index = size_t(format);
    return index < kFormats.size() ? kFormats[index] : kFormats[0];
}

std::span<const FormatInfo> allFormats() { return std::span(kFormats).subspan(1); }

const char* toString(FormatKind kind) {
    switch (kind) {
        case FormatKind::UNorm: return "unorm";
        case FormatKind::Float: return "float";
        case FormatKind::UInt: return "uint";
        case FormatKind::Depth: return "depth";
    }
    return "unknown";
}

const char* toString(FormatCapability cap) {
    switch (cap) {
        case FormatCapability::Sampled: return "sampled";
        case FormatCapability::Filterable: return "filterable";
        case FormatCapability::CompareFilterable: return "compare-filterable";
        case FormatCapability::RenderTarget: return "render-target";
        case FormatCapability::Blendable: return "blendable";
        case FormatCapability::Storage: return "storage";
        case FormatCapability::Copyable: return "copyable";
        case FormatCapability::GenerateMips: return "generate-mips";
    }
    return "unknown";
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
