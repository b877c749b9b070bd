// The non-virtual fronts of IDevice and ICommandList: validate (validation.cpp), then hand the
// call to the backend's protected ...Impl. Backends cannot skip validation because users can
// only reach them through these. The per-draw calls are not here: they go to the backend directly.
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>

#include "janus/rhi/derivative_lint.h"
#include "janus/rhi/index_value_validation.h"
#include "janus/rhi/rhi.h"
#include "validation.h"

namespace janus::rhi {

// ---------------------------------------------------------------------------------------------
// IDevice

void IDevice::setProperties(DeviceProperties properties) {
    properties.formats.resize(allFormats().size() + 1);   // + Unknown, which can do nothing
    properties.formats[size_t(Format::Unknown)] = {};
    m_properties = std::make_shared<const DeviceProperties>(std::move(properties));
}

FormatCapabilities IDevice::formatCapabilities(Format format) const {
    const auto index = size_t(format);
    return index < m_properties->formats.size() ? m_properties->formats[index] : FormatCapabilities{};
}

BufferHandle IDevice::createBuffer(const BufferDesc& desc) {
    detail::validateBuffer(*m_properties, desc);
    BufferHandle buffer = createBufferImpl(desc);
    if (m_properties->validation && any(desc.usage, BufferUsage::Index))
        buffer->m_hostIndexContents = std::make_shared<detail::HostIndexContents>(desc.size);   // zeros, as the buffer
    return buffer;
}

TextureHandle IDevice::createTexture(const TextureDesc& desc) {
    return createTextureImpl(detail::validateTexture(*m_properties, desc));
}

SamplerHandle IDevice::createSampler(const SamplerDesc& desc) {
    detail::validateSampler(*m_properties, desc);
    return createSamplerImpl(desc);
}

ShaderHandle IDevice::createShader(const ShaderDesc& desc) {
    detail::validateShader(*m_properties, desc);
    ShaderHandle shader = createShaderImpl(desc);
    // Undefined behaviour that Mesa happens to forgive and NVIDIA's GL driver did not (issue 10):
    // said once, here, the same on every backend. A warning, not a refusal: the check is
    // conservative, and the shader may be fine where the condition cannot differ within a quad.
    if (m_properties->validation && desc.stage == ShaderStage::Fragment) {
        for (const std::string& finding : derivativeHazards(desc.spirv)) {
            const DebugMessage message{MessageSeverity::Warning,
                                       fmt::format("createShader: fragment shader{}: {}",
                                                   desc.debugName.empty() ? "" : " '" + desc.debugName + "'", finding)};
            try {
                collectFrontMessage(message);
            } catch (const std::exception& e) {
                std::fprintf(stderr, "janus: the debug message callback threw (%s); the message was still collected\n", e.what());
            } catch (...) {
                std::fprintf(stderr, "janus: the debug message callback threw; the message was still collected\n");
            }
        }
    }
    return shader;
}

PipelineHandle IDevice::createGraphicsPipeline(const GraphicsPipelineDesc& desc) {
    detail::validateGraphicsPipeline(*m_properties, desc);
    return createGraphicsPipelineImpl(desc);
}

PipelineHandle IDevice::createComputePipeline(const ComputePipelineDesc& desc) {
    detail::validateComputePipeline(*m_properties, desc);
    return createComputePipelineImpl(desc);
}

BindingSetHandle IDevice::createBindingSet(const BindingSetDesc& desc) {
    detail::validateBindingSet(*m_properties, desc);
    BindingSetHandle set = createBindingSetImpl(desc);
    set->m_keepMark.dynamicOffsetCount =
        uint32_t(std::count_if(desc.items.begin(), desc.items.end(), [](const BindingItem& i) { return i.dynamicOffset; }));
    for (const BindingItem& item : desc.items)
        if (item.type == ResourceType::StorageBuffer && item.buffer && item.buffer->m_hostIndexContents)
            item.buffer->m_hostIndexContents->markShaderWritable();
    return set;
}

TimerQueryHandle IDevice::createTimerQuery() {
    detail::validateTimerQuery(*m_properties);
    return createTimerQueryImpl();
}

CommandListHandle IDevice::createCommandList() {
    CommandListHandle list = createCommandListImpl();
    list->m_properties = m_properties;
    const uint32_t alignment = m_properties->capabilities.limits.uniformBufferOffsetAlignment;
    list->m_dynamicOffsetMask = alignment != 0 && (alignment & (alignment - 1)) == 0 ? alignment - 1 : ~0u;
    if (m_properties->validation) list->m_indexValueLog = std::make_shared<detail::IndexValueLog>();
    return list;
}

void IDevice::execute(const CommandListHandle& commandList) {
    const detail::IndexValueLog* indexValues = commandList ? commandList->m_indexValueLog.get() : nullptr;
    if (indexValues) indexValues->check();
    executeImpl(commandList);
    if (indexValues) indexValues->applyWrites();
}

void IDevice::writeBuffer(const BufferHandle& buffer, const void* data, uint64_t size, uint64_t offset) {
    detail::validateWriteBuffer(buffer, data, size, offset, "writeBuffer()");
    writeBufferImpl(buffer, data, size, offset);
    if (buffer->m_hostIndexContents)
        buffer->m_hostIndexContents->hostWrite(offset, {static_cast<const std::byte*>(data), size_t(size)});
}

std::vector<std::byte> IDevice::readBuffer(const BufferHandle& buffer, uint64_t offset, uint64_t size) {
    return readBufferImpl(buffer, offset, detail::validateReadBuffer(buffer, offset, size));
}

void IDevice::writeTexture(const TextureHandle& texture, TextureSubresource sub, const void* data, uint64_t size) {
    detail::validateWriteTexture(*m_properties, texture, sub, data, size);
    writeTextureImpl(texture, sub, data, size);
}

std::vector<std::byte> IDevice::readTexture(const TextureHandle& texture, TextureSubresource sub) {
    detail::validateReadTexture(*m_properties, texture, sub);
    return readTextureImpl(texture, sub);
}

// ---------------------------------------------------------------------------------------------
// ICommandList

void ICommandList::throwInvalidSetBinding(uint32_t set, const IBindingSet* bindings) const {
    if (set >= kMaxBindingSets)
        throw Error(ErrorCode::InvalidUsage, fmt::format("setBindingSet(): set {} does not exist; sets 0..{} are "
                                                         "available", set, kMaxBindingSets - 1));
    if (!bindings) throw Error(ErrorCode::InvalidUsage, "setBindingSet(): the binding set is null");
    const uint32_t count = bindings->m_keepMark.dynamicOffsetCount;
    throw Error(ErrorCode::InvalidUsage,
                fmt::format("setBindingSet(): the binding set has {} dynamic uniform buffer{} (BindingItem::"
                            "dynamicOffset) but no offsets were given; pass {}: setBindingSet({}, set, offsets)",
                            count, count == 1 ? "" : "s", count == 1 ? "its offset" : "one offset each, in binding order",
                            set));
}

// setBindingSet's second form when its inline checks did not all pass: which one failed (or an
// offset that only a division checks, for an alignment that is not a power of two), or no offsets
// for a set without dynamic items, which is the first form.
void ICommandList::setBindingSetChecked(uint32_t set, const BindingSetHandle& bindings,
                                        std::span<const uint32_t> dynamicOffsets) {
    if (set >= kMaxBindingSets || !bindings) throwInvalidSetBinding(set, bindings.get());
    const uint32_t count = bindings->m_keepMark.dynamicOffsetCount;
    if (dynamicOffsets.size() != count)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("setBindingSet(): {} dynamic offset{} given, but the binding set has {} dynamic uniform "
                                "buffer{} (BindingItem::dynamicOffset); give one offset per such item, in binding order",
                                dynamicOffsets.size(), dynamicOffsets.size() == 1 ? "" : "s", count,
                                count == 1 ? "" : "s"));
    if (count == 0) return setBindingSetImpl(set, bindings);
    const uint32_t alignment = m_properties->capabilities.limits.uniformBufferOffsetAlignment;
    for (size_t i = 0; i < count; ++i)
        if (alignment > 1 && dynamicOffsets[i] % alignment)
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("setBindingSet(): dynamic offset {} ({}) is not a multiple of the device's uniform "
                                    "buffer offset alignment ({}, Limits::uniformBufferOffsetAlignment)",
                                    i, dynamicOffsets[i], alignment));
    setBindingSetImpl(set, bindings, dynamicOffsets);
}

void ICommandList::throwInvalidDispatch(uint32_t groupsX, uint32_t groupsY, uint32_t groupsZ) const {
    const Capabilities& caps = m_properties->capabilities;
    if (!caps.compute)
        throw Error(ErrorCode::UnsupportedCapability,
                    fmt::format("dispatch() needs capability '{}', which the {} backend does not have; use the "
                                "fallback path or another backend",
                                toString(Capability::Compute), toString(m_properties->info.backend)));
    const uint32_t groups[3] = {groupsX, groupsY, groupsZ};
    for (int i = 0; i < 3; ++i)
        if (groups[i] > caps.limits.maxComputeWorkGroupCount[i])
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("dispatch(): {} groups in dimension {} is above Limits::maxComputeWorkGroupCount "
                                    "({}); split the dispatch", groups[i], "xyz"[i],
                                    caps.limits.maxComputeWorkGroupCount[i]));
    throw Error(ErrorCode::InvalidUsage, "dispatch(): invalid group count");
}

void ICommandList::begin() {
    if (m_indexValueLog) m_indexValueLog->clear();
    beginImpl();
}

void ICommandList::beginRenderPass(const RenderPassDesc& desc) {
    detail::validateRenderPass(*m_properties, desc);
    beginRenderPassImpl(desc);
}

void ICommandList::setViewport(const Viewport& viewport) {
    detail::validateViewport(*m_properties, viewport);
    setViewportImpl(viewport);
}

void ICommandList::setVertexBuffer(uint32_t slot, const BufferHandle& buffer, uint64_t offset) {
    detail::validateVertexBufferBind(*m_properties, slot, buffer, offset);
    setVertexBufferImpl(slot, buffer, offset);
}

void ICommandList::setIndexBuffer(const BufferHandle& buffer, IndexType type, uint64_t offset) {
    detail::validateIndexBufferBind(buffer, type, offset);
    setIndexBufferImpl(buffer, type, offset);
}

void ICommandList::setScissor(const ScissorRect& scissor) {
    detail::validateScissor(scissor);
    setScissorImpl(scissor);
}

void ICommandList::writeBuffer(const BufferHandle& dst, const void* data, uint64_t size, uint64_t dstOffset) {
    detail::validateWriteBuffer(dst, data, size, dstOffset, "ICommandList::writeBuffer()");
    writeBufferImpl(dst, data, size, dstOffset);
    if (m_indexValueLog) m_indexValueLog->noteWrite(*dst, dstOffset, data, size);
}

void ICommandList::copyBuffer(const BufferHandle& dst, uint64_t dstOffset, const BufferHandle& src, uint64_t srcOffset,
                              uint64_t size) {
    detail::validateCopyBuffer(dst, dstOffset, src, srcOffset, size);
    copyBufferImpl(dst, dstOffset, src, srcOffset, size);
    if (m_indexValueLog) m_indexValueLog->noteUnknownWrite(*dst);
}

void ICommandList::copyBufferToTexture(const TextureHandle& dst, TextureSubresource dstSub, const BufferHandle& src,
                                       uint64_t srcOffset) {
    detail::validateCopyBufferToTexture(*m_properties, dst, dstSub, src, srcOffset);
    copyBufferToTextureImpl(dst, dstSub, src, srcOffset);
}

void ICommandList::copyTextureToBuffer(const BufferHandle& dst, uint64_t dstOffset, const TextureHandle& src,
                                       TextureSubresource srcSub) {
    detail::validateCopyTextureToBuffer(*m_properties, dst, dstOffset, src, srcSub);
    copyTextureToBufferImpl(dst, dstOffset, src, srcSub);
    if (m_indexValueLog) m_indexValueLog->noteUnknownWrite(*dst);
}

void ICommandList::copyTexture(const TextureHandle& dst, TextureSubresource dstSub, const TextureHandle& src,
                               TextureSubresource srcSub) {
    detail::validateCopyTexture(*m_properties, dst, dstSub, src, srcSub);
    copyTextureImpl(dst, dstSub, src, srcSub);
}

void ICommandList::generateMips(const TextureHandle& texture) {
    detail::validateGenerateMips(*m_properties, texture);
    generateMipsImpl(texture);
}

}  // namespace janus::rhi
