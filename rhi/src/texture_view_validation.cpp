// Backend-neutral checks of array textures and texture views (see texture_view_validation.h).
#include "janus/rhi/texture_view_validation.h"

#include <fmt/format.h>
#include <spirv_cross/spirv.hpp>

#include <algorithm>
#include <string>

namespace janus::rhi {
namespace {

std::string textureName(const TextureDesc& desc) {
    return desc.debugName.empty() ? std::string("(unnamed)") : desc.debugName;
}

[[noreturn]] void unsupported(Capability cap, Backend backend, std::string_view what) {
    throw Error(ErrorCode::UnsupportedCapability,
                fmt::format("{} needs capability '{}', which the {} backend does not have; use the fallback path or "
                            "another backend",
                            what, toString(cap), toString(backend)));
}

bool isCubeLike(TextureDimension d) {
    return d == TextureDimension::TextureCube || d == TextureDimension::TextureCubeArray;
}

// Which view dimensions a texture of dimension `texture` may be seen as.
bool viewDimensionFits(TextureDimension texture, TextureDimension view) {
    switch (texture) {
        case TextureDimension::Texture3D: return view == TextureDimension::Texture3D;
        case TextureDimension::Texture2D:
        case TextureDimension::Texture2DArray:
            return view == TextureDimension::Texture2D || view == TextureDimension::Texture2DArray;
        case TextureDimension::TextureCube:
        case TextureDimension::TextureCubeArray: return view != TextureDimension::Texture3D;
    }
    return false;
}

std::string range(uint32_t base, uint32_t count) {
    return count == 1 ? fmt::format("{}", base) : fmt::format("{}..{}", base, base + count - 1);
}

std::string describe(const ResolvedTextureView& v) {
    return fmt::format("mip {} layer {}", range(v.baseMip, v.mipCount), range(v.baseLayer, v.layerCount));
}

bool overlaps(uint32_t baseA, uint32_t countA, uint32_t baseB, uint32_t countB) {
    return uint64_t(baseA) < uint64_t(baseB) + countB && uint64_t(baseB) < uint64_t(baseA) + countA;
}

}  // namespace

void validateTextureLayers(const TextureDesc& desc, const Capabilities& caps, Backend backend) {
    auto fail = [&](const std::string& problem) {
        throw Error(ErrorCode::InvalidDescription,
                    fmt::format("TextureDesc of '{}' ({} {}x{}, {} layer(s)): {}", textureName(desc),
                                toString(desc.dimension), desc.width, desc.height, desc.arrayLayers, problem));
    };
    switch (desc.dimension) {
        case TextureDimension::Texture2D:
        case TextureDimension::Texture3D:
        case TextureDimension::TextureCube:
            if (desc.arrayLayers != 1)
                fail(fmt::format("arrayLayers must be 1 for a {} texture (a cube's 6 faces are implied); use "
                                 "Texture2DArray or TextureCubeArray for arrays",
                                 toString(desc.dimension)));
            return;
        case TextureDimension::Texture2DArray:
            if (desc.arrayLayers == 0) fail("arrayLayers must be at least 1");
            if (desc.depth != 1) fail("depth must be 1 for a 2D array (its layers are arrayLayers)");
            break;
        case TextureDimension::TextureCubeArray:
            if (!caps.cubeArrays)
                unsupported(Capability::CubeArrays, backend, fmt::format("texture '{}' (a cube array)", textureName(desc)));
            if (desc.arrayLayers == 0 || desc.arrayLayers % 6 != 0)
                fail("a cube array's arrayLayers counts layer-faces: 6 x the number of cubes (a multiple of 6, >= 6)");
            if (desc.width != desc.height) fail("a cube array needs width == height");
            if (desc.depth != 1) fail("depth must be 1 for a cube array (its layer-faces are arrayLayers)");
            break;
    }
    if (desc.arrayLayers > caps.limits.maxTextureArrayLayers)
        fail(fmt::format("arrayLayers exceeds maxTextureArrayLayers ({})", caps.limits.maxTextureArrayLayers));
}

ResolvedTextureView resolveTextureView(const BindingItem& item) {
    const TextureDesc& desc = item.texture->desc();
    ResolvedTextureView v;
    v.dimension = item.viewDimension.value_or(desc.dimension);
    if (item.type == ResourceType::StorageImage) {
        v.baseMip = item.mipLevel;
        v.mipCount = 1;
    } else {
        v.baseMip = item.view.baseMip;
        v.mipCount = item.view.mipCount == kAllMips ? desc.mipLevels - std::min(v.baseMip, desc.mipLevels)
                                                    : item.view.mipCount;
    }
    const uint32_t layers = textureLayerCount(desc);
    if (desc.dimension == TextureDimension::Texture3D) {
        v.baseLayer = 0;
        v.layerCount = layers;
    } else {
        v.baseLayer = item.view.baseLayer;
        v.layerCount = item.view.layerCount == kAllLayers ? layers - std::min(v.baseLayer, layers) : item.view.layerCount;
    }
    return v;
}

bool isWholeTexture(const ResolvedTextureView& v, const TextureDesc& desc) {
    return v.dimension == desc.dimension && v.baseMip == 0 && v.mipCount == desc.mipLevels && v.baseLayer == 0 &&
           v.layerCount == textureLayerCount(desc);
}

ResolvedTextureView validateTextureView(const BindingItem& item, const Capabilities& caps, Backend backend,
                                        std::string_view where) {
    const TextureDesc& desc = item.texture->desc();
    const bool storage = item.type == ResourceType::StorageImage;
    auto fail = [&](const std::string& problem) {
        throw Error(ErrorCode::InvalidDescription,
                    fmt::format("{}: the view of {} texture '{}' ({} mip(s), {} layer(s)): {}", where,
                                toString(desc.dimension), textureName(desc), desc.mipLevels, textureLayerCount(desc),
                                problem));
    };
    const TextureViewRange& r = item.view;
    if (storage) {
        if ((r.baseMip != 0 || r.mipCount != kAllMips) && !(r.baseMip == item.mipLevel && r.mipCount == 1))
            fail("a storage image binds one mip level, BindingItem::mipLevel (storageImage(b, texture, mip)); leave "
                 "the view's mip range at its default");
        if (item.mipLevel >= desc.mipLevels)
            fail(fmt::format("mip level {} does not exist; pick a level below {}", item.mipLevel, desc.mipLevels));
    } else {
        if (r.baseMip >= desc.mipLevels)
            fail(fmt::format("baseMip {} does not exist; pick a level below {}", r.baseMip, desc.mipLevels));
        if (r.mipCount != kAllMips && (r.mipCount == 0 || uint64_t(r.baseMip) + r.mipCount > desc.mipLevels))
            fail(fmt::format("mips {} + count {} run past the last level {}; pass a count of 1..{} (or kAllMips)",
                             r.baseMip, r.mipCount, desc.mipLevels - 1, desc.mipLevels - r.baseMip));
    }
    const uint32_t layers = textureLayerCount(desc);
    if (desc.dimension == TextureDimension::Texture3D) {
        if (r.baseLayer != 0 || r.layerCount != kAllLayers)
            fail("3D textures are viewed whole; leave the view's layer range at its default");
    } else {
        if (r.baseLayer >= layers)
            fail(fmt::format("baseLayer {} does not exist; pick a layer below {}", r.baseLayer, layers));
        if (r.layerCount != kAllLayers && (r.layerCount == 0 || uint64_t(r.baseLayer) + r.layerCount > layers))
            fail(fmt::format("layers {} + count {} run past the last layer {}; pass a count of 1..{} (or kAllLayers)",
                             r.baseLayer, r.layerCount, layers - 1, layers - r.baseLayer));
    }
    const ResolvedTextureView v = resolveTextureView(item);
    if (!viewDimensionFits(desc.dimension, v.dimension))
        fail(fmt::format("it cannot be viewed as {}; a {} texture can be viewed as {}", toString(v.dimension),
                         toString(desc.dimension),
                         desc.dimension == TextureDimension::Texture3D ? "3d only"
                         : isCubeLike(desc.dimension)                  ? "2d, 2d-array, cube or cube-array"
                                                                       : "2d or 2d-array"));
    switch (v.dimension) {
        case TextureDimension::Texture2D:
            if (v.layerCount != 1)
                fail(fmt::format("a 2d view shows one layer but the range has {}; setLayers(layer, 1) or view it "
                                 "as 2d-array",
                                 v.layerCount));
            break;
        case TextureDimension::TextureCube:
            if (v.layerCount != 6)
                fail(fmt::format("a cube view shows 6 layers (faces) but the range has {}; setLayers(6 * cube, 6), or "
                                 "view one face as 2d",
                                 v.layerCount));
            break;
        case TextureDimension::TextureCubeArray:
            if (v.layerCount % 6 != 0 || v.baseLayer % 6 != 0)
                fail(fmt::format("a cube-array view starts at a whole cube and shows whole cubes (layers {} + {} are "
                                 "not multiples of 6); setLayers(6 * firstCube, 6 * cubes)",
                                 v.baseLayer, v.layerCount));
            if (!caps.cubeArrays) unsupported(Capability::CubeArrays, backend, fmt::format("{}: a cube-array view", where));
            break;
        case TextureDimension::Texture2DArray:
        case TextureDimension::Texture3D: break;
    }
    const bool allLayers = v.baseLayer == 0 && v.layerCount == layers;
    if (storage) {
        if (!(allLayers && v.dimension == desc.dimension) && !(v.layerCount == 1 && v.dimension == TextureDimension::Texture2D))
            fail(fmt::format("a storage image binds all layers as {} or one layer as 2d (setLayers(layer, "
                             "1).setViewDimension(TextureDimension::Texture2D)), not {} of layer {}",
                             toString(desc.dimension), toString(v.dimension), range(v.baseLayer, v.layerCount)));
    } else if (!caps.textureViews && (!allLayers || v.dimension != desc.dimension)) {
        unsupported(Capability::TextureViews, backend,
                    fmt::format("{}: viewing layer {} of {} texture '{}' as {} (only mip ranges of the whole texture "
                                "work without it)",
                                where, range(v.baseLayer, v.layerCount), toString(desc.dimension), textureName(desc),
                                toString(v.dimension)));
    }
    return v;
}

void validateViewOverlaps(std::span<const UsedBinding> bindings, const RenderPassDesc* pass, std::string_view call) {
    bool anyStorage = false;
    for (const UsedBinding& b : bindings) anyStorage = anyStorage || b.item->type == ResourceType::StorageImage;
    const bool anyAttachment = pass && (!pass->colors.empty() || pass->depth);
    if (!anyStorage && !anyAttachment) return;

    auto isTexture = [](const BindingItem& item) {
        return item.texture &&
               (item.type == ResourceType::SampledTexture || item.type == ResourceType::StorageImage);
    };
    auto verb = [](const BindingItem& item) { return item.type == ResourceType::StorageImage ? "writes" : "samples"; };
    for (size_t i = 0; i < bindings.size(); ++i) {
        const BindingItem& item = *bindings[i].item;
        if (!isTexture(item)) continue;
        // The common case (per draw): a sampled texture that is no attachment; nothing to resolve.
        bool attached = false;
        if (anyAttachment) {
            for (const Attachment& a : pass->colors)
                attached = attached || a.texture.get() == item.texture.get() || a.resolveTexture.get() == item.texture.get();
            attached = attached || (pass->depth && pass->depth->texture.get() == item.texture.get());
        }
        if (!attached && item.type != ResourceType::StorageImage) continue;
        const ResolvedTextureView v = resolveTextureView(item);
        const TextureDesc& desc = item.texture->desc();
        const bool volume = desc.dimension == TextureDimension::Texture3D;
        if (attached) {
            auto check = [&](const ITexture* texture, TextureSubresource sub, const std::string& which) {
                if (texture != item.texture.get()) return;
                const uint32_t mip = sub.mipLevel, layer = sub.layer;
                if (!overlaps(v.baseMip, v.mipCount, mip, 1) || (!volume && !overlaps(v.baseLayer, v.layerCount, layer, 1)))
                    return;
                throw Error(ErrorCode::InvalidUsage,
                            fmt::format("{}: set {} binding {} {} {} of texture '{}', which {} of the current render "
                                        "pass writes (mip {} layer {}); bind a view that excludes it "
                                        "(BindingItem::setMips / setLayers) or render into another texture",
                                        call, bindings[i].set, item.binding, verb(item), describe(v), textureName(desc),
                                        which, mip, layer));
            };
            for (size_t c = 0; c < pass->colors.size(); ++c) {
                const Attachment& a = pass->colors[c];
                check(a.texture.get(), a.subresource, fmt::format("colour attachment {}", c));
                check(a.resolveTexture.get(), a.resolveSubresource, fmt::format("colour attachment {}'s resolve", c));
            }
            if (pass->depth) check(pass->depth->texture.get(), pass->depth->subresource, "the depth attachment");
        }
        if (item.type != ResourceType::StorageImage) continue;
        for (size_t j = 0; j < bindings.size(); ++j) {
            const BindingItem& other = *bindings[j].item;
            if (j == i || !isTexture(other) || other.texture.get() != item.texture.get()) continue;
            const ResolvedTextureView o = resolveTextureView(other);
            if (!overlaps(v.baseMip, v.mipCount, o.baseMip, o.mipCount) ||
                (!volume && !overlaps(v.baseLayer, v.layerCount, o.baseLayer, o.layerCount)))
                continue;
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("{}: set {} binding {} writes {} of texture '{}' as a storage image while set {} "
                                    "binding {} {} {} of it in the same command; bind views of disjoint mips/layers "
                                    "(BindingItem::setMips / setLayers, storageImage(b, texture, mip))",
                                    call, bindings[i].set, item.binding, describe(v), textureName(desc),
                                    bindings[j].set, other.binding,
                                    other.type == ResourceType::StorageImage ? "also writes" : "samples", describe(o)));
        }
    }
}

void throwSamplerShaderMismatch(const BindingItem& item, bool shaderCompares, std::string_view where) {
    const std::string texture = item.texture ? fmt::format("texture '{}'", item.texture->desc().debugName) : "its texture";
    if (shaderCompares)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("{}: the shader declares a shadow sampler (it compares depth), but the binding reads {} "
                                "through a sampler without compare; give that sampler SamplerDesc::setCompare",
                                where, texture));
    throw Error(ErrorCode::InvalidUsage,
                fmt::format("{}: the sampler for {} compares depth (SamplerDesc::compare), but the shader declares a "
                            "plain sampler, not a shadow sampler; use a sampler without compare or declare "
                            "sampler2DShadow",
                            where, texture));
}

namespace {
// The GLSL name of a format qualifier, for messages.
const char* qualifierName(uint32_t format) {
    switch (spv::ImageFormat(format)) {
        case spv::ImageFormatRgba32f: return "rgba32f";
        case spv::ImageFormatRgba16f: return "rgba16f";
        case spv::ImageFormatR32f: return "r32f";
        case spv::ImageFormatRgba8: return "rgba8";
        case spv::ImageFormatRgba8Snorm: return "rgba8_snorm";
        case spv::ImageFormatRg32f: return "rg32f";
        case spv::ImageFormatRg16f: return "rg16f";
        case spv::ImageFormatR11fG11fB10f: return "r11f_g11f_b10f";
        case spv::ImageFormatR16f: return "r16f";
        case spv::ImageFormatRgba16: return "rgba16";
        case spv::ImageFormatRgb10A2: return "rgb10_a2";
        case spv::ImageFormatRg16: return "rg16";
        case spv::ImageFormatRg8: return "rg8";
        case spv::ImageFormatR16: return "r16";
        case spv::ImageFormatR8: return "r8";
        case spv::ImageFormatRgba32i: return "rgba32i";
        case spv::ImageFormatRgba16i: return "rgba16i";
        case spv::ImageFormatRgba8i: return "rgba8i";
        case spv::ImageFormatR32i: return "r32i";
        case spv::ImageFormatRgba32ui: return "rgba32ui";
        case spv::ImageFormatRgba16ui: return "rgba16ui";
        case spv::ImageFormatRgba8ui: return "rgba8ui";
        case spv::ImageFormatR32ui: return "r32ui";
        default: return "another format";
    }
}
}  // namespace

Format formatOfImageQualifier(uint32_t spirvImageFormat) {
    switch (spv::ImageFormat(spirvImageFormat)) {
        case spv::ImageFormatRgba8: return Format::RGBA8_UNORM;
        case spv::ImageFormatRgba16f: return Format::RGBA16_FLOAT;
        case spv::ImageFormatRgba32f: return Format::RGBA32_FLOAT;
        case spv::ImageFormatR11fG11fB10f: return Format::R11G11B10_FLOAT;
        case spv::ImageFormatR32ui: return Format::R32_UINT;
        case spv::ImageFormatRgba32ui: return Format::RGBA32_UINT;
        case spv::ImageFormatR32f: return Format::R32_FLOAT;
        default: return Format::Unknown;
    }
}

void throwStorageFormatMismatch(const BindingItem& item, uint32_t spirvImageFormat, std::string_view where) {
    const TextureDesc& texture = item.texture->desc();
    // The qualifier that declares the texture's format (the same words, but for R11G11B10).
    const char* wanted = texture.format == Format::R11G11B10_FLOAT ? "r11f_g11f_b10f" : toString(texture.format);
    const Format declared = formatOfImageQualifier(spirvImageFormat);
    const std::string other = declared == Format::Unknown ? std::string() : fmt::format("make the texture {} or ", toString(declared));
    throw Error(ErrorCode::InvalidUsage,
                fmt::format("{}: the shader declares the storage image layout({}), but the binding's texture '{}' is "
                            "{}; {}declare layout({}) (drivers leave a mismatch undefined)",
                            where, qualifierName(spirvImageFormat), texture.debugName, toString(texture.format), other,
                            wanted));
}

}  // namespace janus::rhi
