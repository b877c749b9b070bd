// Texture formats and what they are made of. Shared by every backend and by users.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace janus::rhi {

enum class Format {
    Unknown,
    RGBA8_UNORM,
    RGBA8_SRGB,
    RGBA16_FLOAT,
    RGBA32_FLOAT,
    R11G11B10_FLOAT,
    R32_UINT,
    RGBA32_UINT,
    R32_FLOAT,
    D32_FLOAT,
};

enum class FormatKind { UNorm, Float, UInt, Depth };

struct FormatInfo {
    Format format;
    const char* name;         // "rgba8", "rgba8_srgb", ...
    uint32_t bytesPerPixel;
    uint32_t channels;
    FormatKind kind;
    bool srgb;
};

const FormatInfo& formatInfo(Format format);
inline const char* toString(Format format) { return formatInfo(format).name; }
std::optional<Format> parseFormat(std::string_view name);
inline bool isDepthFormat(Format f) { return formatInfo(f).kind == FormatKind::Depth; }

// Number of mip levels in a full chain for the largest of the given extents.
uint32_t fullMipCount(uint32_t width, uint32_t height, uint32_t depth = 1);
// Extent of `extent` at `mip` (never below 1).
inline uint32_t mipExtent(uint32_t extent, uint32_t mip) { uint32_t e = extent >> mip; return e ? e : 1; }

}  // namespace janus::rhi
