// The validation layer: every description and transfer argument is checked here, once, before
// any backend sees it (called by the non-virtual fronts of IDevice and ICommandList in
// device_front.cpp). One function per description kind; each failure throws rhi::Error with the
// same ErrorCode on every backend and a message that names the field and what to change:
//   InvalidDescription     a Desc field is absurd or contradicts another (or the device's limits)
//   InvalidUsage           a call's arguments are wrong (ranges, subresources, null data)
//   UnsupportedCapability  the device lacks a Capability or a format capability for this use
// Backends keep only what is theirs: handle ownership, command-list state, driver errors.
#pragma once

#include <string_view>

#include "janus/rhi/rhi.h"

namespace janus::rhi::detail {

void validateBuffer(const DeviceProperties& device, const BufferDesc& desc);
// Returns the description with mipLevels resolved (0 = the full chain).
TextureDesc validateTexture(const DeviceProperties& device, const TextureDesc& desc);
void validateSampler(const DeviceProperties& device, const SamplerDesc& desc);
void validateShader(const DeviceProperties& device, const ShaderDesc& desc);
void validateGraphicsPipeline(const DeviceProperties& device, const GraphicsPipelineDesc& desc);
void validateComputePipeline(const DeviceProperties& device, const ComputePipelineDesc& desc);
void validateBindingSet(const DeviceProperties& device, const BindingSetDesc& desc);
void validateTimerQuery(const DeviceProperties& device);
void validateRenderPass(const DeviceProperties& device, const RenderPassDesc& desc);
void validateViewport(const DeviceProperties& device, const Viewport& viewport);
void validateScissor(const ScissorRect& scissor);
// setVertexBuffer / setIndexBuffer: the buffer's usage, the offset inside it, the slot against
// Limits::maxVertexBuffers, the index type (both backends took any value but UInt16 as 32-bit).
void validateVertexBufferBind(const DeviceProperties& device, uint32_t slot, const BufferHandle& buffer, uint64_t offset);
void validateIndexBufferBind(const BufferHandle& buffer, IndexType type, uint64_t offset);

// Transfers; `call` names the call in messages ("writeBuffer()", "ICommandList::copyTexture()").
void validateWriteBuffer(const BufferHandle& buffer, const void* data, uint64_t size, uint64_t offset,
                         std::string_view call);
// Returns the size to read (0 = to the end, resolved).
uint64_t validateReadBuffer(const BufferHandle& buffer, uint64_t offset, uint64_t size);
void validateWriteTexture(const DeviceProperties& device, const TextureHandle& texture, TextureSubresource sub,
                          const void* data, uint64_t size);
void validateReadTexture(const DeviceProperties& device, const TextureHandle& texture, TextureSubresource sub);
void validateCopyBuffer(const BufferHandle& dst, uint64_t dstOffset, const BufferHandle& src, uint64_t srcOffset,
                        uint64_t size);
void validateCopyBufferToTexture(const DeviceProperties& device, const TextureHandle& dst, TextureSubresource dstSub,
                                 const BufferHandle& src, uint64_t srcOffset);
void validateCopyTextureToBuffer(const DeviceProperties& device, const BufferHandle& dst, uint64_t dstOffset,
                                 const TextureHandle& src, TextureSubresource srcSub);
void validateCopyTexture(const DeviceProperties& device, const TextureHandle& dst, TextureSubresource dstSub,
                         const TextureHandle& src, TextureSubresource srcSub);
void validateGenerateMips(const DeviceProperties& device, const TextureHandle& texture);

// Throws UnsupportedCapability unless the device can use `format` for `cap`; `what` says where.
void requireFormatCapability(const DeviceProperties& device, Format format, FormatCapability cap,
                             std::string_view what);

}  // namespace janus::rhi::detail
