// The validation layer (see validation.h): sokol's _sg_validate_* / NVRHI's validation layer
// for Janus. Everything here is backend-independent; what it knows about the device comes from
// DeviceProperties (capabilities, limits and the per-format capability table).
#include "validation.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

#include "janus/rhi/texture_view_validation.h"
#include "shader_reflection.h"

namespace janus::rhi::detail {
namespace {

[[noreturn]] void invalid(const std::string& message) { throw Error(ErrorCode::InvalidDescription, message); }
[[noreturn]] void misuse(const std::string& message) { throw Error(ErrorCode::InvalidUsage, message); }

// "TextureDesc 'albedo'" or "TextureDesc" when unnamed.
std::string named(std::string_view kind, const std::string& debugName) {
    return debugName.empty() ? std::string(kind) : fmt::format("{} '{}'", kind, debugName);
}

std::string textureName(const ITexture& texture) {
    return texture.desc().debugName.empty() ? std::string("(unnamed)") : texture.desc().debugName;
}

void requireCapability(const DeviceProperties& device, Capability cap, std::string_view what) {
    if (!device.capabilities.has(cap))
        throw Error(ErrorCode::UnsupportedCapability,
                    fmt::format("{} needs capability '{}', which the {} backend does not have; use the fallback "
                                "path or another backend", what, toString(cap), toString(device.info.backend)));
}

// Layers (cube faces, array layers, cube-array layer-faces, 3D slices at that mip) of one mip
// level. The only place subresource layers are counted.
uint32_t layersAt(const TextureDesc& desc, uint32_t mip) {
    switch (desc.dimension) {
        case TextureDimension::Texture2D: return 1;
        case TextureDimension::TextureCube: return 6;
        case TextureDimension::Texture2DArray:
        case TextureDimension::TextureCubeArray: return desc.arrayLayers;
        case TextureDimension::Texture3D: return mipExtent(desc.depth, mip);
    }
    return 1;
}

bool isCubeLike(TextureDimension d) {
    return d == TextureDimension::TextureCube || d == TextureDimension::TextureCubeArray;
}

uint64_t subresourceBytes(const TextureDesc& desc, uint32_t mip) {
    return uint64_t(mipExtent(desc.width, mip)) * mipExtent(desc.height, mip) * formatInfo(desc.format).bytesPerPixel;
}

// InvalidUsage unless `sub` is one existing 2D image of `texture`.
void checkSubresource(const ITexture& texture, TextureSubresource sub, std::string_view what) {
    const TextureDesc& desc = texture.desc();
    if (sub.mipLevel >= desc.mipLevels)
        misuse(fmt::format("{}: mip level {} does not exist; texture '{}' has {} level(s)", what, sub.mipLevel,
                           textureName(texture), desc.mipLevels));
    const uint32_t layers = layersAt(desc, sub.mipLevel);
    if (sub.layer >= layers)
        misuse(fmt::format("{}: layer {} does not exist; the {} texture '{}' has {} layer(s)/slice(s) at mip {}", what,
                           sub.layer, toString(desc.dimension), textureName(texture), layers, sub.mipLevel));
}

// InvalidUsage unless [offset, offset + size) is a non-empty range inside `buffer`.
void checkRange(const IBuffer& buffer, uint64_t offset, uint64_t size, std::string_view what) {
    const uint64_t total = buffer.desc().size;
    if (size == 0 || offset > total || size > total - offset)
        misuse(fmt::format("{}: bytes [{}, {}) are not a non-empty range inside the {}-byte buffer '{}'", what, offset,
                           offset + size, total, buffer.desc().debugName));
}

template <class Handle>
void requireHandle(const Handle& handle, std::string_view what) {
    if (!handle) misuse(fmt::format("{} is null", what));
}

bool isLinear(const SamplerDesc& s) {
    return s.minFilter == Filter::Linear || s.magFilter == Filter::Linear || s.mipFilter == Filter::Linear;
}

bool sameBlend(const BlendAttachment& a, const BlendAttachment& b) {
    return a.enable == b.enable && a.writeMask == b.writeMask &&
           (!a.enable || (a.srcColor == b.srcColor && a.dstColor == b.dstColor && a.colorOp == b.colorOp &&
                          a.srcAlpha == b.srcAlpha && a.dstAlpha == b.dstAlpha && a.alphaOp == b.alphaOp));
}

// Values outside an enum (a cast from a file or a wire format gone wrong) are refused before any
// backend: their switches fell back to different defaults (CullMode(77) culled every triangle on
// GL and none on Vulkan; LoadOp(77) loaded on GL and was DONT_CARE on Vulkan).
// `where` names the checked thing in the message: text, or a callable making the text, so that a
// check made per call (a render pass per frame) formats nothing unless it fails.
template <class Where>
std::string subject(const Where& where) {
    if constexpr (std::is_invocable_v<const Where&>)
        return where();
    else
        return std::string(where);
}

template <class E, class Where>
void checkEnum(E value, E last, const Where& where, std::string_view field, std::string_view choices) {
    if (uint32_t(value) > uint32_t(last))
        invalid(fmt::format("{}: {} is {}, which is outside its enum; use one of {}", subject(where), field,
                            uint32_t(value), choices));
}

constexpr std::string_view kCompareOps = "Never, Less, Equal, LessOrEqual, Greater, NotEqual, GreaterOrEqual, Always";

bool isFloat32(Format f) { return formatInfo(f).kind == FormatKind::Float && formatInfo(f).bytesPerPixel / formatInfo(f).channels == 4; }

// InvalidUsage for a multisampled texture where only single-sampled ones go (copies, readback):
// its samples must be resolved first.
void requireSingleSampled(const ITexture& texture, std::string_view what) {
    if (texture.desc().sampleCount > 1)
        misuse(fmt::format("{}: texture '{}' is multisampled ({} samples); resolve it into a single-sampled texture "
                           "(Attachment::resolveTo) and use that", what, textureName(texture), texture.desc().sampleCount));
}

// UnsupportedCapability unless `format` allows `count` samples (FormatCapabilities::sampleCounts).
void requireSampleCount(const DeviceProperties& device, Format format, uint32_t count, std::string_view what) {
    const uint32_t counts = size_t(format) < device.formats.size() ? device.formats[size_t(format)].sampleCounts : 0;
    if (count && std::has_single_bit(count) && (counts & count)) return;
    throw Error(ErrorCode::UnsupportedCapability,
                fmt::format("{}: sampleCount {} is not supported for format {} on this {} device (it allows {}: "
                            "FormatCapabilities::sampleCounts, `janus info`)", what, count, toString(format),
                            toString(device.info.backend), FormatCapabilities::sampleCountText(counts)));
}

}  // namespace

void requireFormatCapability(const DeviceProperties& device, Format format, FormatCapability cap,
                             std::string_view what) {
    const size_t index = size_t(format);
    const bool has = index < device.formats.size() && device.formats[index].has(cap);
    if (has) return;
    // Name the device-wide capability too where one covers this use, so fallbacks can key on it.
    std::string hint;
    const FormatInfo& info = formatInfo(format);
    if (cap == FormatCapability::RenderTarget && info.kind == FormatKind::Float && !device.capabilities.floatRenderTargets)
        hint = fmt::format("; float formats need capability '{}'", toString(Capability::FloatRenderTargets));
    if (cap == FormatCapability::Blendable && isFloat32(format) && !device.capabilities.floatBlend)
        hint = fmt::format("; 32-bit float formats need capability '{}'", toString(Capability::FloatBlend));
    if (cap == FormatCapability::Storage && !device.capabilities.storageImages)
        hint = fmt::format("; storage images need capability '{}'", toString(Capability::StorageImages));
    throw Error(ErrorCode::UnsupportedCapability,
                fmt::format("{}: format {} is not '{}' on this {} device{}; use a format whose "
                            "IDevice::formatCapabilities() has it (`janus info` lists them)",
                            what, toString(format), toString(cap), toString(device.info.backend), hint));
}

// ---------------------------------------------------------------------------------------------
// Resources

void validateBuffer(const DeviceProperties& device, const BufferDesc& desc) {
    const std::string name = named("BufferDesc", desc.debugName);
    if (desc.size == 0) invalid(fmt::format("{}: size is 0; give it the number of bytes it must hold", name));
    constexpr auto kBufferUsages =
        uint32_t(BufferUsage::Vertex | BufferUsage::Index | BufferUsage::Uniform | BufferUsage::Storage);
    if (uint32_t(desc.usage) & ~kBufferUsages)
        invalid(fmt::format("{}: usage {:#x} has bits that are no BufferUsage ({:#x}); combine Vertex, Index, Uniform and "
                            "Storage", name, uint32_t(desc.usage), uint32_t(desc.usage) & ~kBufferUsages));
    const uint64_t most = device.capabilities.limits.maxBufferSize;
    if (most && desc.size > most)
        invalid(fmt::format("{}: size {} is above this device's largest buffer ({} bytes, Limits::maxBufferSize); "
                            "split it", name, desc.size, most));
    if (any(desc.usage, BufferUsage::Storage)) requireCapability(device, Capability::StorageBuffers, name + ": BufferUsage::Storage");
}

TextureDesc validateTexture(const DeviceProperties& device, const TextureDesc& desc) {
    const std::string name = fmt::format("{} ({} {}x{}x{}, {})", named("TextureDesc", desc.debugName),
                                         toString(desc.dimension), desc.width, desc.height, desc.depth,
                                         toString(desc.format));
    // Values outside the enums (a cast from a file or a wire format gone wrong): GL raised
    // GL_INVALID_ENUM for such a dimension and Vulkan made some image, no error either way.
    if (uint32_t(desc.dimension) > uint32_t(TextureDimension::TextureCubeArray))
        invalid(fmt::format("{}: dimension {} is not a TextureDimension", name, uint32_t(desc.dimension)));
    constexpr auto kTextureUsages = uint32_t(TextureUsage::Sampled | TextureUsage::RenderTarget | TextureUsage::Storage);
    if (uint32_t(desc.usage) & ~kTextureUsages)
        invalid(fmt::format("{}: usage {:#x} has bits that are no TextureUsage ({:#x}); combine Sampled, RenderTarget and "
                            "Storage", name, uint32_t(desc.usage), uint32_t(desc.usage) & ~kTextureUsages));
    if (desc.format == Format::Unknown || size_t(desc.format) >= device.formats.size())
        invalid(fmt::format("{}: format is Unknown; pick a concrete Format", name));
    if (desc.width == 0 || desc.height == 0 || desc.depth == 0)
        invalid(fmt::format("{}: width, height and depth must all be at least 1", name));
    const Limits& limits = device.capabilities.limits;
    // arrayLayers against the dimension, Limits::maxTextureArrayLayers and Capability::CubeArrays
    // (texture_view_validation.cpp); the extents per dimension below.
    validateTextureLayers(desc, device.capabilities, device.info.backend);
    switch (desc.dimension) {
        case TextureDimension::Texture2D:
        case TextureDimension::Texture2DArray:
            if (desc.depth != 1)
                invalid(fmt::format("{}: depth must be 1 for a 2D texture or 2D array (use Texture3D for volumes, "
                                    "arrayLayers for layers)", name));
            if (std::max(desc.width, desc.height) > limits.maxTextureSize2D)
                invalid(fmt::format("{}: width/height exceed Limits::maxTextureSize2D ({})", name, limits.maxTextureSize2D));
            break;
        case TextureDimension::TextureCube:
        case TextureDimension::TextureCubeArray:
            if (desc.width != desc.height) invalid(fmt::format("{}: a cube map needs width == height", name));
            if (desc.depth != 1)
                invalid(fmt::format("{}: depth must be 1 for a cube map or cube array (its faces are implied, a cube "
                                    "array's layer-faces are arrayLayers)", name));
            if (desc.width > limits.maxTextureSizeCube)
                invalid(fmt::format("{}: width exceeds Limits::maxTextureSizeCube ({})", name, limits.maxTextureSizeCube));
            break;
        case TextureDimension::Texture3D:
            if (std::max({desc.width, desc.height, desc.depth}) > limits.maxTextureSize3D)
                invalid(fmt::format("{}: an extent exceeds Limits::maxTextureSize3D ({})", name, limits.maxTextureSize3D));
            if (isDepthFormat(desc.format))
                invalid(fmt::format("{}: depth formats cannot be 3D textures; use Texture2D or a colour format", name));
            break;
    }
    TextureDesc resolved = desc;
    const uint32_t fullChain = fullMipCount(desc.width, desc.height,
                                            desc.dimension == TextureDimension::Texture3D ? desc.depth : 1);
    if (resolved.mipLevels == 0) resolved.mipLevels = fullChain;
    if (resolved.mipLevels > fullChain)
        invalid(fmt::format("{}: mipLevels is {} but the full chain has only {} levels; pass 0 for the full chain",
                            name, desc.mipLevels, fullChain));
    if (desc.usage == TextureUsage::None)
        invalid(fmt::format("{}: usage is None; set Sampled, RenderTarget and/or Storage", name));
    if (any(desc.usage, TextureUsage::Storage)) {
        requireCapability(device, Capability::StorageImages, name + ": TextureUsage::Storage");
        requireFormatCapability(device, desc.format, FormatCapability::Storage, name + ": TextureUsage::Storage");
    }
    if (any(desc.usage, TextureUsage::Sampled))
        requireFormatCapability(device, desc.format, FormatCapability::Sampled, name + ": TextureUsage::Sampled");
    if (any(desc.usage, TextureUsage::RenderTarget))
        requireFormatCapability(device, desc.format, FormatCapability::RenderTarget, name + ": TextureUsage::RenderTarget");
    if (desc.sampleCount != 1) {
        if (desc.sampleCount == 0 || !std::has_single_bit(desc.sampleCount))
            invalid(fmt::format("{}: sampleCount is {}; it must be 1 or a power of two the format allows", name,
                                desc.sampleCount));
        if (desc.dimension != TextureDimension::Texture2D || desc.arrayLayers != 1 || resolved.mipLevels != 1)
            invalid(fmt::format("{}: sampleCount is {} but the texture has {} layer(s) and {} mip level(s); a "
                                "multisampled texture is a Texture2D with one layer and mipLevels 1", name,
                                desc.sampleCount, textureLayerCount(desc), resolved.mipLevels));
        if (desc.usage != TextureUsage::RenderTarget)
            invalid(fmt::format("{}: sampleCount is {} with usage {:#x}; a multisampled texture's usage is "
                                "RenderTarget alone (shaders read the single-sampled texture it resolves into)",
                                name, desc.sampleCount, uint32_t(desc.usage)));
        requireSampleCount(device, desc.format, desc.sampleCount, name);
    }
    return resolved;
}

void validateSampler(const DeviceProperties& device, const SamplerDesc& desc) {
    constexpr std::string_view kFilters = "Nearest, Linear";
    constexpr std::string_view kAddressModes = "Repeat, MirroredRepeat, ClampToEdge";
    checkEnum(desc.minFilter, Filter::Linear, "SamplerDesc", "minFilter", kFilters);
    checkEnum(desc.magFilter, Filter::Linear, "SamplerDesc", "magFilter", kFilters);
    checkEnum(desc.mipFilter, Filter::Linear, "SamplerDesc", "mipFilter", kFilters);
    checkEnum(desc.addressU, AddressMode::ClampToEdge, "SamplerDesc", "addressU", kAddressModes);
    checkEnum(desc.addressV, AddressMode::ClampToEdge, "SamplerDesc", "addressV", kAddressModes);
    checkEnum(desc.addressW, AddressMode::ClampToEdge, "SamplerDesc", "addressW", kAddressModes);
    if (desc.compare) checkEnum(*desc.compare, CompareOp::Always, "SamplerDesc", "compare", kCompareOps);
    if (!(desc.minLod <= desc.maxLod))
        invalid(fmt::format("SamplerDesc: minLod {} is above maxLod {}; swap them", desc.minLod, desc.maxLod));
    if (!(desc.maxAnisotropy >= 1.0f))
        invalid(fmt::format("SamplerDesc: maxAnisotropy is {}; it must be at least 1 (1 = off)", desc.maxAnisotropy));
    const float most = device.capabilities.limits.maxSamplerAnisotropy;
    if (desc.maxAnisotropy > most)
        invalid(fmt::format("SamplerDesc: maxAnisotropy is {}, above this device's Limits::maxSamplerAnisotropy ({}); "
                            "use at most that", desc.maxAnisotropy, most));
}

void validateShader(const DeviceProperties& device, const ShaderDesc& desc) {
    const std::string name = named("ShaderDesc", desc.debugName);
    if (desc.stage != ShaderStage::Vertex && desc.stage != ShaderStage::Fragment && desc.stage != ShaderStage::Compute)
        invalid(fmt::format("{}: stage {} is not one ShaderStage; use Vertex, Fragment or Compute", name,
                            uint32_t(desc.stage)));
    if (desc.stage == ShaderStage::Compute) requireCapability(device, Capability::Compute, name + ": a compute shader");
    checkSpirvModule(desc);
    const ShaderReflection reflection = reflectShader(desc);
    for (const ReflectedResource& r : reflection.resources) {
        if (r.type == ResourceType::StorageBuffer)
            requireCapability(device, Capability::StorageBuffers, fmt::format("{}: storage buffer '{}'", name, r.name));
        if (r.type == ResourceType::StorageImage)
            requireCapability(device, Capability::StorageImages, fmt::format("{}: storage image '{}'", name, r.name));
        if (r.dimension == TextureDimension::TextureCubeArray)
            requireCapability(device, Capability::CubeArrays,
                              fmt::format("{}: cube-array {} '{}'", name,
                                          r.type == ResourceType::StorageImage ? "image" : "sampler", r.name));
    }
}

namespace {
// The resources of a pipeline's shaders merged by binding: numbers are unique across sets (the GL
// backend uses them as binding points), and two stages must declare a shared binding alike.
std::vector<ReflectedResource> checkPipelineBindings(const std::vector<const IShader*>& shaders, const std::string& name) {
    std::vector<ReflectedResource> merged;
    for (const IShader* shader : shaders) {
        for (const ReflectedResource& r : reflectShader(shader->desc()).resources) {
            auto existing = std::find_if(merged.begin(), merged.end(),
                                         [&](const ReflectedResource& m) { return m.binding == r.binding; });
            if (existing == merged.end()) {
                merged.push_back(r);
                continue;
            }
            if (existing->set != r.set)
                invalid(fmt::format("{}: binding {} is used in set {} ('{}') and set {} ('{}'); binding numbers must "
                                    "be unique across sets", name, r.binding, existing->set, existing->name, r.set, r.name));
            if (existing->type != r.type || existing->dimension != r.dimension)
                invalid(fmt::format("{}: set {} binding {} is declared differently in two stages ('{}' and '{}'); "
                                    "declare it alike", name, r.set, r.binding, existing->name, r.name));
        }
    }
    return merged;
}

// What a pipeline declares dynamic (DynamicUniformBuffer) must be a uniform block its shaders read.
void checkDynamicUniformBuffers(const std::vector<DynamicUniformBuffer>& declared,
                                const std::vector<ReflectedResource>& resources, const std::string& name) {
    if (declared.size() > kMaxDynamicUniformBuffersPerPipeline)
        invalid(fmt::format("{}: {} dynamic uniform buffers are declared; a pipeline may have at most {} "
                            "(kMaxDynamicUniformBuffersPerPipeline)", name, declared.size(),
                            kMaxDynamicUniformBuffersPerPipeline));
    for (size_t i = 0; i < declared.size(); ++i) {
        const DynamicUniformBuffer& d = declared[i];
        if (std::find(declared.begin(), declared.begin() + i, d) != declared.begin() + i)
            invalid(fmt::format("{}: dynamicUniformBuffers names set {} binding {} twice", name, d.set, d.binding));
        auto r = std::find_if(resources.begin(), resources.end(),
                              [&](const ReflectedResource& x) { return x.set == d.set && x.binding == d.binding; });
        if (r == resources.end())
            invalid(fmt::format("{}: dynamicUniformBuffers names set {} binding {}, which its shaders do not read; "
                                "declare only the uniform blocks they read", name, d.set, d.binding));
        if (r->type != ResourceType::UniformBuffer)
            invalid(fmt::format("{}: dynamicUniformBuffers names set {} binding {} ('{}'), which is not a uniform "
                                "block; only uniform buffers take dynamic offsets", name, d.set, d.binding, r->name));
    }
}

const IShader& shaderOf(const ShaderHandle& handle, ShaderStage stage, std::string_view field, const std::string& name) {
    if (!handle) invalid(fmt::format("{}: {} is null; give it a {} shader", name, field, toString(stage)));
    if (handle->desc().stage != stage)
        invalid(fmt::format("{}: {} is a {} shader ('{}'), not a {} shader", name, field,
                            toString(handle->desc().stage), handle->desc().debugName, toString(stage)));
    return *handle;
}
}  // namespace

void validateGraphicsPipeline(const DeviceProperties& device, const GraphicsPipelineDesc& desc) {
    const std::string name = named("GraphicsPipelineDesc", desc.debugName);
    const Capabilities& caps = device.capabilities;
    const Limits& limits = caps.limits;
    const IShader& vs = shaderOf(desc.vertexShader, ShaderStage::Vertex, "vertexShader", name);
    const IShader& fs = shaderOf(desc.fragmentShader, ShaderStage::Fragment, "fragmentShader", name);

    // Enums (blend states whose blending is off too: Vulkan requires valid values either way).
    checkEnum(desc.topology, PrimitiveTopology::PointList, name, "topology",
              "TriangleList, TriangleStrip, LineList, PointList");
    checkEnum(desc.raster.cullMode, CullMode::Back, name, "raster.cullMode", "None, Front, Back");
    checkEnum(desc.raster.frontFace, FrontFace::Clockwise, name, "raster.frontFace", "CounterClockwise, Clockwise");
    checkEnum(desc.depth.compare, CompareOp::Always, name, "depth.compare", kCompareOps);
    for (size_t i = 0; i < desc.blend.size(); ++i) {
        const BlendAttachment& b = desc.blend[i];
        constexpr std::string_view kFactors = "the BlendFactor values Zero .. OneMinusDstAlpha";
        constexpr std::string_view kOps = "Add, Subtract, ReverseSubtract, Min, Max";
        const std::string field = fmt::format("blend[{}].", i);
        checkEnum(b.srcColor, BlendFactor::OneMinusDstAlpha, name, field + "srcColor", kFactors);
        checkEnum(b.dstColor, BlendFactor::OneMinusDstAlpha, name, field + "dstColor", kFactors);
        checkEnum(b.colorOp, BlendOp::Max, name, field + "colorOp", kOps);
        checkEnum(b.srcAlpha, BlendFactor::OneMinusDstAlpha, name, field + "srcAlpha", kFactors);
        checkEnum(b.dstAlpha, BlendFactor::OneMinusDstAlpha, name, field + "dstAlpha", kFactors);
        checkEnum(b.alphaOp, BlendOp::Max, name, field + "alphaOp", kOps);
        if (b.writeMask & ~0xFu)
            invalid(fmt::format("{}: blend[{}].writeMask {:#x} has bits above the four RGBA bits (0xF); use 0xF for "
                                "all channels", name, i, b.writeMask));
    }
    for (const VertexAttribute& a : desc.vertexAttributes)
        checkEnum(a.format, VertexFormat::UInt1, name, fmt::format("the format of vertex attribute location {}", a.location),
                  "Float1, Float2, Float3, Float4, UByte4Norm, UInt1");

    // Attachments.
    if (desc.colorFormats.empty() && desc.depthFormat == Format::Unknown)
        invalid(fmt::format("{}: no colorFormats and no depthFormat; a pipeline must render into something", name));
    if (desc.colorFormats.size() > limits.maxColorAttachments)
        invalid(fmt::format("{}: {} colorFormats, above Limits::maxColorAttachments ({})", name,
                            desc.colorFormats.size(), limits.maxColorAttachments));
    if (desc.blend.size() > desc.colorFormats.size())
        invalid(fmt::format("{}: {} blend states for {} colorFormats; give one per colour format (addColorFormat)",
                            name, desc.blend.size(), desc.colorFormats.size()));
    for (size_t i = 0; i < desc.colorFormats.size(); ++i) {
        const Format format = desc.colorFormats[i];
        if (format == Format::Unknown || size_t(format) >= device.formats.size() || isDepthFormat(format))
            invalid(fmt::format("{}: colorFormats[{}] is {}, not a colour format; depth goes in depthFormat", name, i,
                                toString(format)));
        requireFormatCapability(device, format, FormatCapability::RenderTarget,
                                fmt::format("{}: colorFormats[{}]", name, i));
        const BlendAttachment blend = i < desc.blend.size() ? desc.blend[i] : BlendAttachment{};
        if (blend.enable)
            requireFormatCapability(device, format, FormatCapability::Blendable,
                                    fmt::format("{}: blend[{}] is enabled, so colorFormats[{}]", name, i, i));
        const BlendAttachment first = desc.blend.empty() ? BlendAttachment{} : desc.blend[0];
        if (i > 0 && !sameBlend(first, blend) && !caps.independentBlend)
            throw Error(ErrorCode::UnsupportedCapability,
                        fmt::format("{}: colour attachment {} blends (or masks) differently from attachment 0, which "
                                    "needs capability '{}', which the {} backend does not have; use one blend state",
                                    name, i, toString(Capability::IndependentBlend), toString(device.info.backend)));
    }
    if (desc.sampleCount == 0 || !std::has_single_bit(desc.sampleCount))
        invalid(fmt::format("{}: sampleCount is {}; it must be 1 or the render pass's (a power of two)", name,
                            desc.sampleCount));
    if (desc.sampleCount > 1) {
        for (Format format : desc.colorFormats) requireSampleCount(device, format, desc.sampleCount, name);
        if (desc.depthFormat != Format::Unknown) requireSampleCount(device, desc.depthFormat, desc.sampleCount, name);
    }
    if (desc.alphaToCoverage) {
        // With one sample GL ignores alpha to coverage and Vulkan turns alpha into a per-pixel
        // cut-off of its own choosing: the backends would draw differently.
        if (desc.sampleCount < 2)
            invalid(fmt::format("{}: alphaToCoverage needs a multisampled pipeline (sampleCount > 1), not sampleCount {}; "
                                "discard below a cut-off in the shader instead, or turn it off",
                                name, desc.sampleCount));
        // GL skips alpha to coverage without a colour buffer at draw buffer 0; Vulkan still applies it.
        if (desc.colorFormats.empty())
            invalid(fmt::format("{}: alphaToCoverage needs a colour attachment (colorFormats is empty): GL skips it in a "
                                "depth-only pass and Vulkan does not; discard in the shader there instead",
                                name));
        if (!reflectShader(fs.desc()).writesAlphaAtLocation0)
            invalid(fmt::format("{}: alphaToCoverage reads the alpha of fragment output location 0, which the fragment shader "
                                "'{}' does not write; declare a vec4 output at location 0",
                                name, fs.desc().debugName));
    }
    if (desc.depthFormat != Format::Unknown) {
        if (size_t(desc.depthFormat) >= device.formats.size() || !isDepthFormat(desc.depthFormat))
            invalid(fmt::format("{}: depthFormat {} is not a depth format", name, toString(desc.depthFormat)));
        requireFormatCapability(device, desc.depthFormat, FormatCapability::RenderTarget, name + ": depthFormat");
    } else if (desc.depth.testEnable || desc.depth.writeEnable) {
        invalid(fmt::format("{}: depth test/write is enabled but depthFormat is Unknown; set a depthFormat or "
                            "disable them", name));
    }

    // Vertex input.
    for (size_t i = 0; i < desc.vertexBuffers.size(); ++i) {
        const VertexBufferLayout& vb = desc.vertexBuffers[i];
        if (vb.slot >= limits.maxVertexBuffers)
            invalid(fmt::format("{}: vertex buffer slot {} is above Limits::maxVertexBuffers ({})", name, vb.slot,
                                limits.maxVertexBuffers));
        if (vb.stride == 0 || vb.stride > limits.maxVertexStride || vb.stride % 4 != 0)
            invalid(fmt::format("{}: vertex buffer slot {} has stride {}; it must be a multiple of 4 in 4..{} "
                                "(Limits::maxVertexStride)", name, vb.slot, vb.stride, limits.maxVertexStride));
        for (size_t j = 0; j < i; ++j)
            if (desc.vertexBuffers[j].slot == vb.slot)
                invalid(fmt::format("{}: vertex buffer slot {} has two VertexBufferLayouts; give each slot one", name,
                                    vb.slot));
    }
    for (size_t i = 0; i < desc.vertexAttributes.size(); ++i) {
        const VertexAttribute& a = desc.vertexAttributes[i];
        auto layout = std::find_if(desc.vertexBuffers.begin(), desc.vertexBuffers.end(),
                                   [&](const VertexBufferLayout& vb) { return vb.slot == a.bufferSlot; });
        if (layout == desc.vertexBuffers.end())
            invalid(fmt::format("{}: vertex attribute at location {} reads buffer slot {}, which has no "
                                "VertexBufferLayout; add one with addVertexBuffer", name, a.location, a.bufferSlot));
        if (a.location >= limits.maxVertexAttributes)
            invalid(fmt::format("{}: vertex attribute location {} is above Limits::maxVertexAttributes ({})", name,
                                a.location, limits.maxVertexAttributes));
        // Vulkan needs the attribute's address aligned to its component size; WebGPU's rule,
        // min(4, the format's size), covers that (every VertexFormat has 4 bytes or more).
        if (const uint32_t alignment = std::min(4u, vertexFormatSize(a.format)); a.offset % alignment != 0)
            invalid(fmt::format("{}: vertex attribute at location {} has offset {}; it must be a multiple of {}",
                                name, a.location, a.offset, alignment));
        if (uint64_t(a.offset) + vertexFormatSize(a.format) > layout->stride)
            invalid(fmt::format("{}: vertex attribute at location {} (offset {}, {} bytes) does not fit in stride {}",
                                name, a.location, a.offset, vertexFormatSize(a.format), layout->stride));
        for (size_t j = 0; j < i; ++j)
            if (desc.vertexAttributes[j].location == a.location)
                invalid(fmt::format("{}: two vertex attributes feed location {}; give each location one", name,
                                    a.location));
    }
    // Vulkan rejects a missing input; GL would feed (0, 0, 0, 1) and reinterpret a float as an
    // integer. Reject both everywhere.
    for (const ReflectedInput& input : reflectShader(vs.desc()).inputs) {
        auto attribute = std::find_if(desc.vertexAttributes.begin(), desc.vertexAttributes.end(),
                                      [&](const VertexAttribute& a) { return a.location == input.location; });
        if (attribute == desc.vertexAttributes.end())
            invalid(fmt::format("{}: the vertex shader '{}' reads location {}, but no vertex attribute feeds it; add "
                                "one with addVertexAttribute", name, vs.desc().debugName, input.location));
        const bool integerFormat = attribute->format == VertexFormat::UInt1;
        if (integerFormat != input.integer)
            invalid(fmt::format("{}: vertex attribute at location {} is {} but the shader reads it as {}; match them",
                                name, input.location, integerFormat ? "an integer format (UInt1)" : "a float format",
                                input.integer ? "an integer" : "a float"));
    }
    checkDynamicUniformBuffers(desc.dynamicUniformBuffers, checkPipelineBindings({&vs, &fs}, name), name);
}

void validateComputePipeline(const DeviceProperties& device, const ComputePipelineDesc& desc) {
    const std::string name = named("ComputePipelineDesc", desc.debugName);
    requireCapability(device, Capability::Compute, name + ": a compute pipeline");
    const IShader& cs = shaderOf(desc.computeShader, ShaderStage::Compute, "computeShader", name);
    checkDynamicUniformBuffers(desc.dynamicUniformBuffers, checkPipelineBindings({&cs}, name), name);
}

void validateBindingSet(const DeviceProperties& device, const BindingSetDesc& desc) {
    const Capabilities& caps = device.capabilities;
    uint32_t dynamicItems = 0;
    for (size_t i = 0; i < desc.items.size(); ++i) {
        const BindingItem& item = desc.items[i];
        const std::string where = fmt::format("BindingSetDesc item {} (binding {})", i, item.binding);
        if (item.dynamicOffset) {
            if (item.type != ResourceType::UniformBuffer)
                invalid(fmt::format("{}: dynamicOffset is set on a {} item; only uniform buffers take dynamic offsets",
                                    where, item.type == ResourceType::StorageBuffer    ? "storage buffer"
                                           : item.type == ResourceType::SampledTexture ? "sampled texture"
                                                                                       : "storage image"));
            if (item.range == 0)
                invalid(fmt::format("{}: a dynamic uniform buffer needs a range (the window each dynamic offset "
                                    "moves); range 0 means 'to the end of the buffer'", where));
            if (++dynamicItems > kMaxDynamicOffsetsPerSet)
                invalid(fmt::format("{}: more than {} items of the set have dynamic offsets "
                                    "(kMaxDynamicOffsetsPerSet)", where, kMaxDynamicOffsetsPerSet));
        }
        for (size_t j = 0; j < i; ++j)
            if (desc.items[j].binding == item.binding)
                invalid(fmt::format("{}: binding {} appears twice in the set; give each binding one item", where,
                                    item.binding));
        checkEnum(item.type, ResourceType::StorageImage, where, "type",
                  "UniformBuffer, StorageBuffer, SampledTexture, StorageImage");
        switch (item.type) {
            case ResourceType::UniformBuffer:
            case ResourceType::StorageBuffer: {
                const bool uniform = item.type == ResourceType::UniformBuffer;
                if (!uniform) requireCapability(device, Capability::StorageBuffers, where + ": a storage-buffer binding");
                if (!item.buffer) invalid(fmt::format("{}: buffer is null; give it a buffer", where));
                const BufferDesc& bd = item.buffer->desc();
                if (!any(bd.usage, uniform ? BufferUsage::Uniform : BufferUsage::Storage))
                    invalid(fmt::format("{}: buffer '{}' is bound as a {} buffer but lacks BufferUsage::{}", where,
                                        bd.debugName, uniform ? "uniform" : "storage", uniform ? "Uniform" : "Storage"));
                const uint64_t range = item.range ? item.range : (item.offset < bd.size ? bd.size - item.offset : 0);
                if (item.offset >= bd.size || range > bd.size - item.offset)
                    invalid(fmt::format("{}: offset {} + range {} is outside the {}-byte buffer '{}'", where,
                                        item.offset, item.range, bd.size, bd.debugName));
                const uint64_t alignment =
                    uniform ? caps.limits.uniformBufferOffsetAlignment : caps.limits.storageBufferOffsetAlignment;
                if (alignment && item.offset % alignment)
                    invalid(fmt::format("{}: offset {} is not a multiple of the device's {} buffer offset alignment "
                                        "({}, Limits)", where, item.offset, uniform ? "uniform" : "storage", alignment));
                const uint64_t most = uniform ? caps.limits.maxUniformBufferRange : caps.limits.maxStorageBufferRange;
                if (range > most)
                    invalid(fmt::format("{}: the bound range is {} bytes, above the device's max {} buffer range ({}); "
                                        "pass a smaller range", where, range, uniform ? "uniform" : "storage", most));
                break;
            }
            case ResourceType::SampledTexture: {
                if (!item.texture || !item.sampler)
                    invalid(fmt::format("{}: a sampled texture needs a texture and a sampler; one is null", where));
                const TextureDesc& td = item.texture->desc();
                if (!any(td.usage, TextureUsage::Sampled))
                    invalid(fmt::format("{}: texture '{}' lacks TextureUsage::Sampled", where, td.debugName));
                const SamplerDesc& sd = item.sampler->desc();
                if (sd.compare && !isDepthFormat(td.format))
                    invalid(fmt::format("{}: the sampler compares depth but texture '{}' is {}, not a depth format; "
                                        "use a sampler without compare", where, td.debugName, toString(td.format)));
                if (isLinear(sd))
                    requireFormatCapability(device, td.format,
                                            sd.compare ? FormatCapability::CompareFilterable : FormatCapability::Filterable,
                                            fmt::format("{}: a linear-filtering sampler over texture '{}' (use "
                                                        "Filter::Nearest for it)", where, td.debugName));
                validateTextureView(item, caps, device.info.backend, where);
                break;
            }
            case ResourceType::StorageImage: {
                requireCapability(device, Capability::StorageImages, where + ": a storage-image binding");
                if (!item.texture) invalid(fmt::format("{}: texture is null; give it a texture", where));
                const TextureDesc& td = item.texture->desc();
                if (!any(td.usage, TextureUsage::Storage))
                    invalid(fmt::format("{}: texture '{}' lacks TextureUsage::Storage", where, td.debugName));
                if (item.mipLevel >= td.mipLevels)
                    invalid(fmt::format("{}: mipLevel {} does not exist; texture '{}' has {}", where, item.mipLevel,
                                        td.debugName, td.mipLevels));
                validateTextureView(item, caps, device.info.backend, where);
                break;
            }
        }
    }
}

void validateTimerQuery(const DeviceProperties& device) {
    requireCapability(device, Capability::TimestampQueries, "createTimerQuery()");
}

void validateRenderPass(const DeviceProperties& device, const RenderPassDesc& desc) {
    const Capabilities& caps = device.capabilities;
    if (desc.colors.empty() && !desc.depth)
        invalid("RenderPassDesc: no colour and no depth attachment; add one with addColor or setDepth");
    if (desc.colors.size() > caps.limits.maxColorAttachments)
        invalid(fmt::format("RenderPassDesc: {} colour attachments, above Limits::maxColorAttachments ({})",
                            desc.colors.size(), caps.limits.maxColorAttachments));
    uint32_t width = 0, height = 0, samples = 0;
    // One 2D image of a texture written by the pass (an attachment, a resolve target): it exists,
    // and the device can render to its kind.
    // `field` names it in messages; `verb` says what the pass does to it ("" or "resolving into ").
    auto checkTargetSubresource = [&](const TextureDesc& td, TextureSubresource sub, const auto& where, std::string_view field,
                                      std::string_view verb) {
        if (sub.mipLevel >= td.mipLevels || sub.layer >= layersAt(td, sub.mipLevel))
            invalid(fmt::format("{}: {} (mip {}, layer {}) does not exist in the {} texture '{}' ({} mip "
                                "level(s), {} layer(s)/slice(s) at that mip)", where(), field, sub.mipLevel, sub.layer,
                                toString(td.dimension), td.debugName, td.mipLevels,
                                sub.mipLevel < td.mipLevels ? layersAt(td, sub.mipLevel) : 0));
        if (td.dimension == TextureDimension::Texture3D)
            requireCapability(device, Capability::RenderToVolumeSlice, fmt::format("{}: {}a 3D texture slice", where(), verb));
        if (isCubeLike(td.dimension) && sub.mipLevel > 0)
            requireCapability(device, Capability::RenderToCubeFaceMip, fmt::format("{}: {}a cube face at mip > 0", where(), verb));
    };
    // Passes are begun per frame: the attachment's name is made only for a message.
    auto check = [&](const Attachment& a, size_t colorIndex, bool depth) {
        auto where = [&] {
            return depth ? std::string("RenderPassDesc depth") : fmt::format("RenderPassDesc colors[{}]", colorIndex);
        };
        if (!a.texture) invalid(fmt::format("{}: texture is null; give it a texture", where()));
        checkEnum(a.loadOp, LoadOp::DontCare, where, "loadOp", "Load, Clear, DontCare");
        checkEnum(a.storeOp, StoreOp::DontCare, where, "storeOp", "Store, DontCare");
        const TextureDesc& td = a.texture->desc();
        if (!any(td.usage, TextureUsage::RenderTarget))
            invalid(fmt::format("{}: texture '{}' lacks TextureUsage::RenderTarget", where(), td.debugName));
        if (isDepthFormat(td.format) != depth)
            invalid(fmt::format("{}: texture '{}' has format {}, which is {}a depth format; {}", where(), td.debugName,
                                toString(td.format), depth ? "not " : "",
                                depth ? "pass a depth texture to setDepth" : "pass depth textures to setDepth"));
        const TextureSubresource sub = a.subresource;
        checkTargetSubresource(td, sub, where, "subresource", "");
        // Clear values every backend stores alike: Vulkan needs depth in [0, 1] (without
        // VK_EXT_depth_range_unrestricted), and a float outside an unsigned integer's range does
        // not convert to one (C++ leaves it undefined; the backends converted differently).
        if (a.loadOp == LoadOp::Clear && depth && !(a.clearDepth >= 0.0f && a.clearDepth <= 1.0f))
            invalid(fmt::format("{}: clearDepth is {}; it must be in [0, 1]", where(), a.clearDepth));
        if (a.loadOp == LoadOp::Clear && formatInfo(td.format).kind == FormatKind::UInt)
            for (float c : a.clearColor)
                if (!(c >= 0.0f && c < 4294967296.0f))
                    invalid(fmt::format("{}: clearColor ({}, {}, {}, {}) of the unsigned integer texture '{}' ({}) "
                                        "holds {}; each value must be in [0, 2^32)", where(), a.clearColor[0],
                                        a.clearColor[1], a.clearColor[2], a.clearColor[3], td.debugName,
                                        toString(td.format), c));
        const uint32_t w = mipExtent(td.width, sub.mipLevel), h = mipExtent(td.height, sub.mipLevel);
        if (width == 0) {
            width = w;
            height = h;
        } else if (w != width || h != height) {
            invalid(fmt::format("{}: texture '{}' is {}x{} at mip {} but the first attachment is {}x{}; all "
                                "attachments must have the same size", where(), td.debugName, w, h, sub.mipLevel, width,
                                height));
        }
        if (samples == 0) {
            samples = td.sampleCount;
        } else if (td.sampleCount != samples) {
            invalid(fmt::format("{}: texture '{}' has {} sample(s) but the first attachment has {}; all attachments "
                                "must have the same sampleCount", where(), td.debugName, td.sampleCount, samples));
        }
        if (!a.resolveTexture) return;
        if (depth)
            invalid(fmt::format("{}: a depth attachment cannot be resolved; resolve colour attachments only (a "
                                "multisampled depth texture is left as it is: StoreOp::DontCare)", where()));
        if (td.sampleCount == 1)
            invalid(fmt::format("{}: resolveTexture is set but texture '{}' is single-sampled; resolve only "
                                "multisampled attachments (TextureDesc::sampleCount > 1)", where(), td.debugName));
        const TextureDesc& rd = a.resolveTexture->desc();
        const TextureSubresource rs = a.resolveSubresource;
        if (rd.sampleCount != 1)
            invalid(fmt::format("{}: resolveTexture '{}' is multisampled ({} samples); resolve into a single-sampled "
                                "texture", where(), rd.debugName, rd.sampleCount));
        if (!any(rd.usage, TextureUsage::RenderTarget))
            invalid(fmt::format("{}: resolveTexture '{}' lacks TextureUsage::RenderTarget", where(), rd.debugName));
        if (rd.format != td.format)
            invalid(fmt::format("{}: resolveTexture '{}' is {} but the attachment is {}; the formats must be the same",
                                where(), rd.debugName, toString(rd.format), toString(td.format)));
        checkTargetSubresource(rd, rs, where, "resolveSubresource", "resolving into ");
        if (mipExtent(rd.width, rs.mipLevel) != w || mipExtent(rd.height, rs.mipLevel) != h)
            invalid(fmt::format("{}: resolveTexture '{}' is {}x{} at mip {} but the attachment is {}x{}; they must be "
                                "the same size", where(), rd.debugName, mipExtent(rd.width, rs.mipLevel),
                                mipExtent(rd.height, rs.mipLevel), rs.mipLevel, w, h));
    };
    for (size_t i = 0; i < desc.colors.size(); ++i) {
        check(desc.colors[i], i, false);
        // One subresource written through two attachments: which write wins is undefined
        // (Vulkan forbids it; GL draws both in an unspecified order).
        for (size_t j = 0; j < i; ++j)
            if (desc.colors[j].texture == desc.colors[i].texture &&
                desc.colors[j].subresource.mipLevel == desc.colors[i].subresource.mipLevel &&
                desc.colors[j].subresource.layer == desc.colors[i].subresource.layer)
                invalid(fmt::format("RenderPassDesc colors[{}]: texture '{}' (mip {}, layer {}) is colors[{}] too; "
                                    "render to each subresource through one attachment",
                                    i, desc.colors[i].texture->desc().debugName, desc.colors[i].subresource.mipLevel,
                                    desc.colors[i].subresource.layer, j));
    }
    if (desc.depth) check(*desc.depth, 0, true);
    // Two resolves into one subresource: which one lands is undefined.
    for (size_t i = 0; i < desc.colors.size(); ++i)
        for (size_t j = 0; j < i && desc.colors[i].resolveTexture; ++j)
            if (desc.colors[j].resolveTexture == desc.colors[i].resolveTexture &&
                desc.colors[j].resolveSubresource.mipLevel == desc.colors[i].resolveSubresource.mipLevel &&
                desc.colors[j].resolveSubresource.layer == desc.colors[i].resolveSubresource.layer)
                invalid(fmt::format("RenderPassDesc colors[{}]: resolves into texture '{}' (mip {}, layer {}) as "
                                    "colors[{}] does; resolve each attachment into its own subresource", i,
                                    desc.colors[i].resolveTexture->desc().debugName,
                                    desc.colors[i].resolveSubresource.mipLevel, desc.colors[i].resolveSubresource.layer, j));
}

void validateViewport(const DeviceProperties& device, const Viewport& v) {
    const Limits& limits = device.capabilities.limits;
    const auto most = float(limits.maxViewportSize);
    if (!(v.width > 0 && v.width <= most && v.height > 0 && v.height <= most))
        misuse(fmt::format("setViewport(): the viewport is {}x{}; width and height must be in (0, {}] "
                           "(Limits::maxViewportSize)", v.width, v.height, limits.maxViewportSize));
    const float lo = limits.viewportBoundsRange[0], hi = limits.viewportBoundsRange[1];
    if (!(v.x >= lo && v.y >= lo && double(v.x) + v.width <= hi && double(v.y) + v.height <= hi))
        misuse(fmt::format("setViewport(): the viewport ({}, {}) + {}x{} leaves this device's bounds range [{}, {}] "
                           "(Limits::viewportBoundsRange); move or shrink it", v.x, v.y, v.width, v.height, lo, hi));
    // GL's glViewport and ES take integers (glViewportIndexedf is GL 4.1+, not ES): a fraction
    // Vulkan keeps would be dropped there, and the backends' images would differ without a word.
    if (v.x != std::floor(v.x) || v.y != std::floor(v.y) || v.width != std::floor(v.width) || v.height != std::floor(v.height))
        misuse(fmt::format("setViewport(): the viewport ({}, {}) + {}x{} is not in whole pixels; round it (GL and GL ES "
                           "take whole pixels only)", v.x, v.y, v.width, v.height));
    if (!(v.minDepth >= 0 && v.minDepth <= 1 && v.maxDepth >= 0 && v.maxDepth <= 1))
        misuse(fmt::format("setViewport(): minDepth {} / maxDepth {} must be in [0, 1]", v.minDepth, v.maxDepth));
}

void validateScissor(const ScissorRect& s) {
    constexpr int64_t most = INT32_MAX;
    if (s.x < 0 || s.y < 0)
        misuse(fmt::format("setScissor(): offset ({}, {}) is negative; scissor offsets must be >= 0", s.x, s.y));
    if (int64_t(s.x) + s.width > most || int64_t(s.y) + s.height > most)
        misuse(fmt::format("setScissor(): ({}, {}) + {}x{} reaches past {} (INT32_MAX); clamp the rectangle to the "
                           "render target", s.x, s.y, s.width, s.height, most));
}

void validateVertexBufferBind(const DeviceProperties& device, uint32_t slot, const BufferHandle& buffer, uint64_t offset) {
    if (!buffer) misuse("setVertexBuffer(): the buffer is null");
    const BufferDesc& desc = buffer->desc();
    if (!any(desc.usage, BufferUsage::Vertex))
        misuse(fmt::format("setVertexBuffer(): buffer '{}' lacks BufferUsage::Vertex", desc.debugName));
    if (offset >= desc.size)
        misuse(fmt::format("setVertexBuffer(): offset {} is past the end of buffer '{}' ({} bytes)", offset, desc.debugName,
                           desc.size));
    // Vulkan needs each attribute's address aligned to its component size (undefined otherwise);
    // as in WebGPU, offsets, strides and float attribute offsets are multiples of 4.
    if (offset % 4 != 0)
        misuse(fmt::format("setVertexBuffer(): offset {} is not a multiple of 4; align vertex data to 4 bytes", offset));
    if (const uint32_t slots = device.capabilities.limits.maxVertexBuffers; slot >= slots)
        misuse(fmt::format("setVertexBuffer(): slot {} is above the device's {} slots (Limits::maxVertexBuffers)", slot, slots));
}

void validateIndexBufferBind(const BufferHandle& buffer, IndexType type, uint64_t offset) {
    if (type != IndexType::UInt16 && type != IndexType::UInt32)
        misuse(fmt::format("setIndexBuffer(): index type {} is outside IndexType; use IndexType::UInt16 or IndexType::UInt32",
                           uint32_t(type)));
    if (!buffer) misuse("setIndexBuffer(): the buffer is null");
    const BufferDesc& desc = buffer->desc();
    if (!any(desc.usage, BufferUsage::Index))
        misuse(fmt::format("setIndexBuffer(): buffer '{}' lacks BufferUsage::Index", desc.debugName));
    const uint64_t indexSize = type == IndexType::UInt16 ? 2 : 4;
    if (offset % indexSize != 0 || offset >= desc.size)
        misuse(fmt::format("setIndexBuffer(): offset {} must be a multiple of {} inside the buffer ({} bytes)", offset,
                           indexSize, desc.size));
}

// ---------------------------------------------------------------------------------------------
// Transfers

void validateWriteBuffer(const BufferHandle& buffer, const void* data, uint64_t size, uint64_t offset,
                         std::string_view call) {
    requireHandle(buffer, fmt::format("{}: the buffer", call));
    checkRange(*buffer, offset, size, call);
    if (!data) misuse(fmt::format("{}: data is null", call));
}

uint64_t validateReadBuffer(const BufferHandle& buffer, uint64_t offset, uint64_t size) {
    requireHandle(buffer, "readBuffer(): the buffer");
    if (size == 0) {
        if (offset >= buffer->desc().size)
            misuse(fmt::format("readBuffer(): offset {} is not inside the {}-byte buffer '{}'", offset,
                               buffer->desc().size, buffer->desc().debugName));
        size = buffer->desc().size - offset;
    }
    checkRange(*buffer, offset, size, "readBuffer()");
    return size;
}

void validateWriteTexture(const DeviceProperties& device, const TextureHandle& texture, TextureSubresource sub,
                          const void* data, uint64_t size) {
    requireHandle(texture, "writeTexture(): the texture");
    checkSubresource(*texture, sub, "writeTexture()");
    requireSingleSampled(*texture, "writeTexture()");
    requireFormatCapability(device, texture->desc().format, FormatCapability::Copyable, "writeTexture()");
    const uint64_t expected = subresourceBytes(texture->desc(), sub.mipLevel);
    if (size != expected)
        misuse(fmt::format("writeTexture(): size is {} bytes but mip {} of the {} texture '{}' holds {} ({}x{}, rows "
                           "tightly packed)", size, sub.mipLevel, toString(texture->desc().format), textureName(*texture),
                           expected, mipExtent(texture->desc().width, sub.mipLevel),
                           mipExtent(texture->desc().height, sub.mipLevel)));
    if (!data) misuse("writeTexture(): data is null");
    // Depth values outside [0, 1] were kept by Vulkan (which may not store them without
    // VK_EXT_depth_range_unrestricted) and clamped by GL: refuse them, as the clear depth.
    if (texture->desc().format == Format::D32_FLOAT) {
        const auto* bytes = static_cast<const std::byte*>(data);
        for (uint64_t i = 0; i < size / 4; ++i) {
            float depth;
            std::memcpy(&depth, bytes + 4 * i, 4);
            if (!(depth >= 0.0f && depth <= 1.0f))
                misuse(fmt::format("writeTexture(): texel {} of the d32f texture '{}' holds depth {}; depths must be in [0, 1]",
                                   i, textureName(*texture), depth));
        }
    }
}

void validateReadTexture(const DeviceProperties& device, const TextureHandle& texture, TextureSubresource sub) {
    requireHandle(texture, "readTexture(): the texture");
    checkSubresource(*texture, sub, "readTexture()");
    requireSingleSampled(*texture, "readTexture()");
    requireFormatCapability(device, texture->desc().format, FormatCapability::Copyable, "readTexture()");
}

void validateCopyBuffer(const BufferHandle& dst, uint64_t dstOffset, const BufferHandle& src, uint64_t srcOffset,
                        uint64_t size) {
    requireHandle(dst, "copyBuffer(): the destination");
    requireHandle(src, "copyBuffer(): the source");
    checkRange(*dst, dstOffset, size, "copyBuffer() destination");
    checkRange(*src, srcOffset, size, "copyBuffer() source");
    if (dst == src && srcOffset < dstOffset + size && dstOffset < srcOffset + size)
        misuse("copyBuffer(): source and destination ranges overlap in the same buffer; copy through another buffer");
}

namespace {
void checkBufferImageCopy(const DeviceProperties& device, const BufferHandle& buffer, uint64_t offset,
                          const TextureHandle& texture, TextureSubresource sub, std::string_view call,
                          std::string_view bufferRole) {
    requireHandle(texture, fmt::format("{}: the texture", call));
    requireHandle(buffer, fmt::format("{}: the buffer", call));
    checkSubresource(*texture, sub, call);
    requireSingleSampled(*texture, call);
    requireFormatCapability(device, texture->desc().format, FormatCapability::Copyable, call);
    checkRange(*buffer, offset, subresourceBytes(texture->desc(), sub.mipLevel), fmt::format("{} {}", call, bufferRole));
    const uint32_t texel = formatInfo(texture->desc().format).bytesPerPixel;
    if (offset % texel)
        misuse(fmt::format("{}: the buffer offset {} must be a multiple of the texel size {} of {}", call, offset, texel,
                           toString(texture->desc().format)));
}
}  // namespace

void validateCopyBufferToTexture(const DeviceProperties& device, const TextureHandle& dst, TextureSubresource dstSub,
                                 const BufferHandle& src, uint64_t srcOffset) {
    checkBufferImageCopy(device, src, srcOffset, dst, dstSub, "copyBufferToTexture()", "source");
}

void validateCopyTextureToBuffer(const DeviceProperties& device, const BufferHandle& dst, uint64_t dstOffset,
                                 const TextureHandle& src, TextureSubresource srcSub) {
    checkBufferImageCopy(device, dst, dstOffset, src, srcSub, "copyTextureToBuffer()", "destination");
}

void validateCopyTexture(const DeviceProperties& device, const TextureHandle& dst, TextureSubresource dstSub,
                         const TextureHandle& src, TextureSubresource srcSub) {
    requireHandle(dst, "copyTexture(): the destination");
    requireHandle(src, "copyTexture(): the source");
    checkSubresource(*dst, dstSub, "copyTexture() destination");
    checkSubresource(*src, srcSub, "copyTexture() source");
    requireSingleSampled(*dst, "copyTexture() destination");
    requireSingleSampled(*src, "copyTexture() source");
    const Format dstFormat = dst->desc().format, srcFormat = src->desc().format;
    if (dstFormat != srcFormat)
        misuse(fmt::format("copyTexture(): cannot copy {} into {}; the formats must be the same",
                           toString(srcFormat), toString(dstFormat)));
    requireFormatCapability(device, srcFormat, FormatCapability::Copyable, "copyTexture()");
    const uint32_t sw = mipExtent(src->desc().width, srcSub.mipLevel), sh = mipExtent(src->desc().height, srcSub.mipLevel);
    const uint32_t dw = mipExtent(dst->desc().width, dstSub.mipLevel), dh = mipExtent(dst->desc().height, dstSub.mipLevel);
    if (sw != dw || sh != dh)
        misuse(fmt::format("copyTexture(): the source subresource is {}x{} but the destination is {}x{}; sizes must "
                           "match", sw, sh, dw, dh));
    if (dst == src && dstSub.mipLevel == srcSub.mipLevel && dstSub.layer == srcSub.layer)
        misuse("copyTexture(): source and destination are the same subresource");
}

void validateGenerateMips(const DeviceProperties& device, const TextureHandle& texture) {
    requireHandle(texture, "generateMips(): the texture");
    requireSingleSampled(*texture, "generateMips()");
    requireFormatCapability(device, texture->desc().format, FormatCapability::GenerateMips,
                            fmt::format("generateMips() of texture '{}' (write each mip level yourself instead)",
                                        textureName(*texture)));
}

}  // namespace janus::rhi::detail
