// Texture formats and what they are made of. Shared by every backend and by users.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
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
const char* toString(FormatKind kind);   // "unorm", "float", "uint", "depth"

// What a format is made of: the same on every device (rhi/src/format.cpp, one row per format).
struct FormatInfo {
    Format format;
    const char* name;         // "rgba8", "rgba8_srgb", ...
    uint32_t bytesPerPixel;
    uint32_t channels;
    FormatKind kind;          // how shaders read it: normalised, float, unsigned integer, depth
    bool srgb;                // stored sRGB-encoded, decoded when sampled, encoded when rendered to
    bool stencil = false;     // has a stencil aspect (none of today's formats)
};

const FormatInfo& formatInfo(Format format);
inline const char* toString(Format format) { return formatInfo(format).name; }
std::optional<Format> parseFormat(std::string_view name);
inline bool isDepthFormat(Format f) { return formatInfo(f).kind == FormatKind::Depth; }
// Every format except Unknown, in enum order: what format tables and tests iterate over.
std::span<const FormatInfo> allFormats();

// What one device can do with a format; IDevice::formatCapabilities(format) reports it, queried
// from the driver when the device starts. The validation layer checks every use of a format
// against it and throws UnsupportedCapability naming the format and the use.
enum class FormatCapability : uint32_t {
    Sampled = 1u << 0,            // TextureUsage::Sampled: read in shaders (texelFetch, nearest filtering)
    Filterable = 1u << 1,         // linear filtering (min/mag/mip) by a sampler without comparison
    CompareFilterable = 1u << 2,  // depth formats: linear filtering of depth comparisons (2x2 PCF)
    RenderTarget = 1u << 3,       // TextureUsage::RenderTarget; a pipeline colour / depth format
    Blendable = 1u << 4,          // blending enabled on a colour attachment of this format
    Storage = 1u << 5,            // TextureUsage::Storage: image load/store
    Copyable = 1u << 6,           // writeTexture, readTexture and the copy commands
    GenerateMips = 1u << 7,       // ICommandList::generateMips
};
const char* toString(FormatCapability cap);   // "sampled", "filterable", "render-target", ...
inline constexpr std::array kAllFormatCapabilities = {
    FormatCapability::Sampled,   FormatCapability::Filterable, FormatCapability::CompareFilterable,
    FormatCapability::RenderTarget, FormatCapability::Blendable, FormatCapability::Storage,
    FormatCapability::Copyable,  FormatCapability::GenerateMips,
};

struct FormatCapabilities {
    uint32_t bits = 0;
    // The sample counts a render target of this format can have (TextureDesc::sampleCount): bit
    // n set = 2^n samples allowed; 1 (single-sampled only) where multisampling is not possible
    // (not a render target, integer formats: their resolve is not an average) and 0 only in the
    // table's Unknown row.
    uint32_t sampleCounts = 1;

    bool has(FormatCapability cap) const { return (bits & uint32_t(cap)) != 0; }
    FormatCapabilities& set(FormatCapability cap, bool on = true) {
        bits = on ? bits | uint32_t(cap) : bits & ~uint32_t(cap);
        return *this;
    }
    bool supportsSampleCount(uint32_t count) const { return count && std::has_single_bit(count) && (sampleCounts & count); }
    // The counts of `sampleCounts` (or of any such mask) joined by `separator`: "1, 4"; "none" for 0.
    static std::string sampleCountText(uint32_t counts, std::string_view separator = ", ");
    bool operator==(const FormatCapabilities&) const = default;
};

// Number of mip levels in a full chain for the largest of the given extents.
uint32_t fullMipCount(uint32_t width, uint32_t height, uint32_t depth = 1);
// Extent of `extent` at `mip` (never below 1).
inline uint32_t mipExtent(uint32_t extent, uint32_t mip) { uint32_t e = extent >> mip; return e ? e : 1; }

}  // namespace janus::rhi
