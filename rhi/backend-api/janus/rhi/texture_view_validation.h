// Backend-neutral checks of array textures, texture views and sampled items against their shader
// (rhi/src/texture_view_validation.cpp).
// Every backend calls these, so the same mistake gets the same ErrorCode and message everywhere.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "janus/rhi/rhi.h"

namespace janus::rhi {

// A view with every count resolved (no kAllMips / kAllLayers). 3D textures: baseLayer 0 and
// layerCount = depth (views of a volume are always whole).
struct ResolvedTextureView {
    TextureDimension dimension = TextureDimension::Texture2D;
    uint32_t baseMip = 0;
    uint32_t mipCount = 1;
    uint32_t baseLayer = 0;
    uint32_t layerCount = 1;
    bool operator==(const ResolvedTextureView&) const = default;
};

// Checks TextureDesc::arrayLayers against the dimension, Limits::maxTextureArrayLayers and
// Capability::CubeArrays. Throws InvalidDescription or UnsupportedCapability.
void validateTextureLayers(const TextureDesc& desc, const Capabilities& caps, Backend backend);

// Checks the view of a SampledTexture / StorageImage item (its texture must be set) and returns
// it resolved. `where` names the item in messages ("binding 3"). Throws InvalidDescription when
// the view does not fit the texture, UnsupportedCapability for TextureViews / CubeArrays.
ResolvedTextureView validateTextureView(const BindingItem& item, const Capabilities& caps, Backend backend,
                                        std::string_view where);

// The same resolution without checks, for items validated when their set was created.
ResolvedTextureView resolveTextureView(const BindingItem& item);

// A sampled texture item against how the shader declares it: a shadow sampler (sampler2DShadow and
// kin, which compare) needs a sampler with SamplerDesc::compare, any other sampler one without.
// Drivers leave the mismatch undefined (NVIDIA's GL reports it, Mesa and lavapipe say nothing), so
// every backend checks it when it first pairs a set with a pipeline. `where()` names the binding
// and the shader's variable; it is called only for the message. Throws InvalidUsage.
[[noreturn]] void throwSamplerShaderMismatch(const BindingItem& item, bool shaderCompares, std::string_view where);
template <class Where>
void requireSamplerMatchesShader(const BindingItem& item, bool shaderCompares, Where&& where) {
    if (item.type != ResourceType::SampledTexture || !item.sampler || item.sampler->desc().compare.has_value() == shaderCompares)
        return;
    throwSamplerShaderMismatch(item, shaderCompares, where());
}

// A storage image item against the format qualifier its shader declares (`layout(rgba16f)
// image2D`; `spirvImageFormat` is SPIR-V's ImageFormat operand, 0 = none): they must name the
// same format. Drivers leave a mismatch undefined (Mesa converts to the texture's format, others
// reinterpret the bits), so every backend checks it when it first pairs a set with a pipeline.
// Throws InvalidUsage naming both formats.
[[noreturn]] void throwStorageFormatMismatch(const BindingItem& item, uint32_t spirvImageFormat, std::string_view where);
// The format a SPIR-V ImageFormat names, or Format::Unknown for none and for those no Format is.
Format formatOfImageQualifier(uint32_t spirvImageFormat);
template <class Where>
void requireStorageFormatMatchesShader(const BindingItem& item, uint32_t spirvImageFormat, Where&& where) {
    if (item.type != ResourceType::StorageImage || spirvImageFormat == 0 || !item.texture ||
        formatOfImageQualifier(spirvImageFormat) == item.texture->desc().format)
        return;
    throwStorageFormatMismatch(item, spirvImageFormat, where());
}

// True when `view` shows all of `desc` with its own dimension (what binding the texture itself gives).
bool isWholeTexture(const ResolvedTextureView& view, const TextureDesc& desc);

// One binding a draw or dispatch uses (an item its shaders read), with its set for messages.
struct UsedBinding {
    uint32_t set = 0;
    const BindingItem* item = nullptr;
};

// Throws InvalidUsage when a texture binding of `bindings` overlaps a subresource the same
// command writes: an attachment of `pass` (when given; attachments count as written) or a
// storage image of `bindings` (storage images count as written). `call` names the command.
void validateViewOverlaps(std::span<const UsedBinding> bindings, const RenderPassDesc* pass, std::string_view call);

}  // namespace janus::rhi
