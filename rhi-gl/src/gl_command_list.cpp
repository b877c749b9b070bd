// Command lists record closures (validated as they are recorded, so errors point at the call
// that caused them) and replay them on execute(). Each closure holds the handles it uses, which
// keeps those resources alive until the list is reset or destroyed.
#include <fmt/format.h>

#include <algorithm>

#include "gl_device.h"

namespace janus::rhi::gl {

namespace {
template <typename T, typename Handle>
std::shared_ptr<T> cast(Device& device, const Handle& handle, const char* what, const char* kind) {
    auto result = std::dynamic_pointer_cast<T>(handle);
    if (!result)
        throw Error(ErrorCode::InvalidUsage, fmt::format("{}: the {} is null or comes from another backend", what, kind));
    if constexpr (requires { result->owner(); }) {
        // GL names mean nothing in another context.
        if (result->owner() != &device.context())
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("{}: the {} was created by another device; use resources of this device", what, kind));
    }
    return result;
}

GLenum primitiveMode(PrimitiveTopology topology) {
    switch (topology) {
        case PrimitiveTopology::TriangleList: return GL_TRIANGLES;
        case PrimitiveTopology::TriangleStrip: return GL_TRIANGLE_STRIP;
        case PrimitiveTopology::LineList: return GL_LINES;
        case PrimitiveTopology::PointList: return GL_POINTS;
    }
    return GL_TRIANGLES;
}
}  // namespace

// ---------------------------------------------------------------------------------------------
// Recording

void CommandList::requireRecording(const char* what) const {
    if (!m_recording)
        throw Error(ErrorCode::InvalidUsage, fmt::format("{} was called outside begin()/end() of the command list", what));
}

void CommandList::requireOutsideRenderPass(const char* what) const {
    requireRecording(what);
    if (m_inRenderPass)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("{} is not allowed inside a render pass; call endRenderPass() first", what));
}

void CommandList::requireInsideRenderPass(const char* what) const {
    requireRecording(what);
    if (!m_inRenderPass)
        throw Error(ErrorCode::InvalidUsage, fmt::format("{} needs an active render pass; call beginRenderPass() first", what));
}

void CommandList::begin() {
    m_commands.clear();
    m_recording = true;
    m_recorded = false;
    m_inRenderPass = false;
    m_pipeline.reset();
    m_indexBufferSet = false;
    m_vertexSlots.clear();
    m_bindingSets.clear();
    m_passColorFormats.clear();
    m_passDepthFormat = Format::Unknown;
    m_debugGroupDepth = 0;
}

void CommandList::requireCompatiblePipeline(const char* what) const {
    const GraphicsPipelineDesc& desc = m_pipeline->graphics();
    auto list = [](const std::vector<Format>& formats) {
        std::string text;
        for (Format f : formats) text += fmt::format("{}{}", text.empty() ? "" : ", ", toString(f));
        return "[" + text + "]";
    };
    if (desc.colorFormats != m_passColorFormats)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("{}: the pipeline's colour formats {} do not match the render pass attachments {}; "
                                "create the pipeline with the pass's formats",
                                what, list(desc.colorFormats), list(m_passColorFormats)));
    if (desc.depthFormat != Format::Unknown && desc.depthFormat != m_passDepthFormat)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("{}: the pipeline's depth format {} does not match the render pass depth attachment ({})",
                                what, toString(desc.depthFormat),
                                m_passDepthFormat == Format::Unknown ? "none" : toString(m_passDepthFormat)));
}

std::vector<UsedBinding> CommandList::requireBindings(const char* what) const {
    // GL would silently read whatever is bound at a unit; Vulkan's validation would flag the
    // same mistake, so catch it here with the binding named.
    std::vector<UsedBinding> textures;
    for (const ShaderBinding& binding : m_pipeline->bindings()) {
        const BindingItem* found = nullptr;
        if (auto set = m_bindingSets.find(binding.set); set != m_bindingSets.end()) {
            for (const BindingItem& item : set->second->desc().items)
                if (item.binding == binding.binding) found = &item;
        }
        if (!found)
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("{}: the pipeline's shaders use set {} binding {} ({}), but the binding set "
                                    "given to setBindingSet({}, ...) has no item for it (or none was set)",
                                    what, binding.set, binding.binding, binding.glName, binding.set));
        if (found->type != binding.type)
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("{}: binding {} is a different resource type in the binding set than in the "
                                    "shader ({})",
                                    what, binding.binding, binding.glName));
        if (!found->texture) continue;
        const TextureDimension viewed = found->viewDimension.value_or(found->texture->desc().dimension);
        if (binding.dimension && viewed != *binding.dimension)
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("{}: binding {} views {} texture '{}' as {} but the shader declares a {} one; match "
                                    "the shader's type or set BindingItem::viewDimension",
                                    what, binding.binding, toString(found->texture->desc().dimension),
                                    found->texture->desc().debugName, toString(viewed), toString(*binding.dimension)));
        textures.push_back({binding.set, found});
    }
    validateViewOverlaps(textures, m_inRenderPass ? &m_passDesc : nullptr, what);
    if (m_device.isES()) {
        // Mip ranges are texture state on ES (BASE/MAX_LEVEL): one range per texture per draw.
        for (size_t i = 0; i < textures.size(); ++i)
            for (size_t j = 0; j < i; ++j) {
                const BindingItem& a = *textures[i].item;
                const BindingItem& b = *textures[j].item;
                if (a.texture != b.texture || a.type != ResourceType::SampledTexture ||
                    b.type != ResourceType::SampledTexture)
                    continue;
                const ResolvedTextureView va = resolveTextureView(a), vb = resolveTextureView(b);
                if (va.baseMip != vb.baseMip || va.mipCount != vb.mipCount)
                    throw Error(ErrorCode::UnsupportedCapability,
                                fmt::format("{}: bindings {} and {} sample texture '{}' through different mip ranges "
                                            "in one draw, which needs capability '{}' (OpenGL ES emulates mip ranges "
                                            "with texture state: one range per texture per draw); the gles backend "
                                            "does not have it",
                                            what, b.binding, a.binding, a.texture->desc().debugName,
                                            toString(Capability::TextureViews)));
            }
    }
    return textures;
}

void CommandList::recordMipRanges(const std::vector<UsedBinding>& textures) {
    if (!m_device.isES()) return;   // desktop GL binds texture views instead
    std::vector<Device::MipRange> ranges;
    for (const UsedBinding& used : textures) {
        if (used.item->type != ResourceType::SampledTexture) continue;
        const ResolvedTextureView view = resolveTextureView(*used.item);
        // The binding set's replayed closure keeps the texture alive.
        ranges.push_back({static_cast<const Texture*>(used.item->texture.get()), used.item->binding, view.baseMip,
                          view.mipCount});
    }
    if (!ranges.empty()) record([ranges = std::move(ranges)](Device& device) { device.applyMipRanges(ranges); });
}

void CommandList::requireVertexBuffers(const char* what) const {
    for (const VertexAttribute& attribute : m_pipeline->graphics().vertexAttributes) {
        if (std::find(m_vertexSlots.begin(), m_vertexSlots.end(), attribute.bufferSlot) == m_vertexSlots.end())
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("{}: the pipeline reads vertex buffer slot {}, but no buffer was set there; call "
                                    "setVertexBuffer({}, ...) first",
                                    what, attribute.bufferSlot, attribute.bufferSlot));
    }
}

void CommandList::end() {
    requireRecording("end()");
    if (m_inRenderPass) throw Error(ErrorCode::InvalidUsage, "end() was called inside a render pass; call endRenderPass() first");
    if (m_debugGroupDepth != 0)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("end() was called with {} debug group(s) still open; pop them first", m_debugGroupDepth));
    m_recording = false;
    m_recorded = true;
}

void CommandList::replay() {
    if (m_recording || !m_recorded)
        throw Error(ErrorCode::InvalidUsage, "execute() needs a command list that was recorded with begin() ... end()");
    for (auto& command : m_commands) command(m_device);
}

// `desc` is validated (rhi/src/validation.cpp); the attachments must still be this device's.
void CommandList::beginRenderPassImpl(const RenderPassDesc& desc) {
    requireOutsideRenderPass("beginRenderPass");
    for (const Attachment& a : desc.colors) cast<Texture>(m_device, a.texture, "beginRenderPass", "attachment texture");
    if (desc.depth) cast<Texture>(m_device, desc.depth->texture, "beginRenderPass", "attachment texture");
    m_inRenderPass = true;
    m_passDesc = desc;
    m_passColorFormats.clear();
    for (const Attachment& a : desc.colors) m_passColorFormats.push_back(a.texture->desc().format);
    m_passDepthFormat = desc.depth ? desc.depth->texture->desc().format : Format::Unknown;
    record([desc](Device& device) { device.beginRenderPass(desc); });
}

void CommandList::endRenderPass() {
    requireInsideRenderPass("endRenderPass");
    m_inRenderPass = false;
    m_passDesc = {};
}

void CommandList::setViewport(const Viewport& viewport) {
    requireInsideRenderPass("setViewport");
    if (!(viewport.width > 0 && viewport.height > 0))
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("setViewport: width {} and height {} must be > 0", viewport.width, viewport.height));
    record([viewport](Device& device) {
        const GLFunctions& gl = device.gl();
        // GL's window origin is row 0 as well, so y needs no flip.
        gl.glViewport(GLint(viewport.x), GLint(viewport.y), GLsizei(viewport.width), GLsizei(viewport.height));
        gl.glDepthRangef(viewport.minDepth, viewport.maxDepth);
    });
}

void CommandList::setScissor(const ScissorRect& scissor) {
    requireInsideRenderPass("setScissor");
    if (scissor.x < 0 || scissor.y < 0)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("setScissor: offset ({}, {}) is negative; scissor offsets must be >= 0", scissor.x, scissor.y));
    record([scissor](Device& device) {
        device.gl().glScissor(scissor.x, scissor.y, GLsizei(scissor.width), GLsizei(scissor.height));
    });
}

void CommandList::setPipeline(const PipelineHandle& handle) {
    requireRecording("setPipeline");
    auto pipeline = cast<Pipeline>(m_device, handle, "setPipeline", "pipeline");
    if (pipeline->isCompute() && m_inRenderPass)
        throw Error(ErrorCode::InvalidUsage, "setPipeline: a compute pipeline cannot be set inside a render pass");
    m_pipeline = pipeline;
    record([pipeline](Device& device) { device.bindPipeline(*pipeline); });
}

void CommandList::setBindingSetImpl(uint32_t set, const BindingSetHandle& handle) {
    requireRecording("setBindingSet");
    auto bindings = cast<BindingSet>(m_device, handle, "setBindingSet", "binding set");
    m_bindingSets[set] = bindings;
    record([bindings](Device& device) { device.bindBindingSet(bindings->desc()); });
}

void CommandList::setVertexBuffer(uint32_t slot, const BufferHandle& handle, uint64_t offset) {
    requireRecording("setVertexBuffer");
    auto buffer = cast<Buffer>(m_device, handle, "setVertexBuffer", "buffer");
    if (!any(buffer->desc().usage, BufferUsage::Vertex))
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("setVertexBuffer: buffer '{}' lacks BufferUsage::Vertex", buffer->desc().debugName));
    if (offset >= buffer->desc().size)
        throw Error(ErrorCode::InvalidUsage, fmt::format("setVertexBuffer: offset {} is past the end of buffer '{}' ({} bytes)",
                                                         offset, buffer->desc().debugName, buffer->desc().size));
    if (std::find(m_vertexSlots.begin(), m_vertexSlots.end(), slot) == m_vertexSlots.end()) m_vertexSlots.push_back(slot);
    record([buffer, slot, offset](Device& device) { device.setVertexBuffer(slot, buffer->name(), offset); });
}

void CommandList::setIndexBuffer(const BufferHandle& handle, IndexType type, uint64_t offset) {
    requireRecording("setIndexBuffer");
    auto buffer = cast<Buffer>(m_device, handle, "setIndexBuffer", "buffer");
    if (!any(buffer->desc().usage, BufferUsage::Index))
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("setIndexBuffer: buffer '{}' lacks BufferUsage::Index", buffer->desc().debugName));
    const uint64_t indexSize = type == IndexType::UInt16 ? 2 : 4;
    if (offset % indexSize != 0 || offset >= buffer->desc().size)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("setIndexBuffer: offset {} must be a multiple of {} inside the buffer ({} bytes)",
                                offset, indexSize, buffer->desc().size));
    m_indexBufferSet = true;
    record([buffer, type, offset](Device& device) { device.setIndexBuffer(buffer->name(), type, offset); });
}

void CommandList::draw(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex, uint32_t firstInstance) {
    requireInsideRenderPass("draw");
    if (!m_pipeline || m_pipeline->isCompute())
        throw Error(ErrorCode::InvalidUsage, "draw: no graphics pipeline is set; call setPipeline() first");
    requireVertexBuffers("draw");
    requireCompatiblePipeline("draw");
    recordMipRanges(requireBindings("draw"));
    record([=](Device& device) { device.draw(vertexCount, instanceCount, firstVertex, firstInstance); });
}

void CommandList::drawIndexed(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex, int32_t vertexOffset,
                                uint32_t firstInstance) {
    requireInsideRenderPass("drawIndexed");
    if (!m_pipeline || m_pipeline->isCompute())
        throw Error(ErrorCode::InvalidUsage, "drawIndexed: no graphics pipeline is set; call setPipeline() first");
    requireVertexBuffers("drawIndexed");
    requireCompatiblePipeline("drawIndexed");
    recordMipRanges(requireBindings("drawIndexed"));
    if (!m_indexBufferSet)
        throw Error(ErrorCode::InvalidUsage, "drawIndexed: no index buffer is set; call setIndexBuffer() first");
    record([=](Device& device) { device.drawIndexed(indexCount, instanceCount, firstIndex, vertexOffset, firstInstance); });
}

void CommandList::dispatchImpl(uint32_t groupsX, uint32_t groupsY, uint32_t groupsZ) {   // Compute; counts in limits
    requireOutsideRenderPass("dispatch");
    if (!m_pipeline || !m_pipeline->isCompute())
        throw Error(ErrorCode::InvalidUsage, "dispatch: no compute pipeline is set; call setPipeline() first");
    requireBindings("dispatch");
    record([=](Device& device) { device.dispatch(groupsX, groupsY, groupsZ); });
}

// Transfers: arguments are validated (rhi/src/validation.cpp); ranges and subresources exist.
void CommandList::writeBufferImpl(const BufferHandle& handle, const void* data, uint64_t size, uint64_t dstOffset) {
    requireOutsideRenderPass("writeBuffer");
    auto buffer = cast<Buffer>(m_device, handle, "writeBuffer", "buffer");
    // The data is copied now: the caller's memory need not outlive the call.
    auto bytes = std::make_shared<std::vector<std::byte>>(static_cast<const std::byte*>(data),
                                                          static_cast<const std::byte*>(data) + size);
    record([buffer, bytes, dstOffset](Device& device) {
        device.bufferSubData(*buffer, bytes->data(), bytes->size(), dstOffset);
    });
}

void CommandList::copyBufferImpl(const BufferHandle& dstHandle, uint64_t dstOffset, const BufferHandle& srcHandle,
                                 uint64_t srcOffset, uint64_t size) {
    requireOutsideRenderPass("copyBuffer");
    auto dst = cast<Buffer>(m_device, dstHandle, "copyBuffer", "destination buffer");
    auto src = cast<Buffer>(m_device, srcHandle, "copyBuffer", "source buffer");
    record([=](Device& device) {
        const GLFunctions& gl = device.gl();
        gl.glBindBuffer(GL_COPY_READ_BUFFER, src->name());
        gl.glBindBuffer(GL_COPY_WRITE_BUFFER, dst->name());
        gl.glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, GLintptr(srcOffset), GLintptr(dstOffset),
                               GLsizeiptr(size));
    });
}

void CommandList::copyBufferToTextureImpl(const TextureHandle& dstHandle, TextureSubresource dstSub,
                                          const BufferHandle& srcHandle, uint64_t srcOffset) {
    requireOutsideRenderPass("copyBufferToTexture");
    auto dst = cast<Texture>(m_device, dstHandle, "copyBufferToTexture", "texture");
    auto src = cast<Buffer>(m_device, srcHandle, "copyBufferToTexture", "buffer");
    record([=](Device& device) {
        // Unpacking from a bound pixel buffer: the "pointer" is an offset into it.
        device.gl().glBindBuffer(GL_PIXEL_UNPACK_BUFFER, src->name());
        device.uploadTexture(*dst, dstSub, reinterpret_cast<const void*>(uintptr_t(srcOffset)));
        device.gl().glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    });
}

void CommandList::copyTextureToBufferImpl(const BufferHandle& dstHandle, uint64_t dstOffset,
                                          const TextureHandle& srcHandle, TextureSubresource srcSub) {
    requireOutsideRenderPass("copyTextureToBuffer");
    auto dst = cast<Buffer>(m_device, dstHandle, "copyTextureToBuffer", "buffer");
    auto src = cast<Texture>(m_device, srcHandle, "copyTextureToBuffer", "texture");
    record([=](Device& device) {
        // Through the CPU: ES 3.0 can read some formats only in a wider form that needs repacking.
        const std::vector<std::byte> pixels = device.downloadTexture(*src, srcSub);
        device.bufferSubData(*dst, pixels.data(), pixels.size(), dstOffset);
    });
}

void CommandList::copyTextureImpl(const TextureHandle& dstHandle, TextureSubresource dstSub,
                                  const TextureHandle& srcHandle, TextureSubresource srcSub) {
    requireOutsideRenderPass("copyTexture");
    auto dst = cast<Texture>(m_device, dstHandle, "copyTexture", "destination texture");
    auto src = cast<Texture>(m_device, srcHandle, "copyTexture", "source texture");
    record([=](Device& device) { device.copyTextureImage(*dst, dstSub, *src, srcSub); });
}

// The format's GenerateMips capability (colour-renderable and filterable) is validated.
void CommandList::generateMipsImpl(const TextureHandle& handle) {
    requireOutsideRenderPass("generateMips");
    auto texture = cast<Texture>(m_device, handle, "generateMips", "texture");
    record([texture](Device& device) {
        const GLFunctions& gl = device.gl();
        gl.glActiveTexture(GL_TEXTURE0 + kScratchTextureUnit);
        gl.glBindTexture(texture->target(), texture->name());
        // glGenerateMipmap starts at GL_TEXTURE_BASE_LEVEL: undo a mip-range view's (GLES).
        if (device.isES()) texture->applyMipRange(0, texture->desc().mipLevels);
        gl.glGenerateMipmap(texture->target());
    });
}

void CommandList::beginTimer(const TimerQueryHandle& handle) {
    requireRecording("beginTimer");
    auto timer = cast<TimerQuery>(m_device, handle, "beginTimer", "timer");
    record([timer](Device& device) {
        device.timestamp(timer->beginQuery());
        timer->begun = true;
        timer->ended = false;
    });
}

void CommandList::endTimer(const TimerQueryHandle& handle) {
    requireRecording("endTimer");
    auto timer = cast<TimerQuery>(m_device, handle, "endTimer", "timer");
    record([timer](Device& device) {
        device.timestamp(timer->endQuery());
        timer->ended = true;
    });
}

void CommandList::pushDebugGroup(std::string_view name) {
    requireRecording("pushDebugGroup");
    ++m_debugGroupDepth;
    record([label = std::string(name)](Device& device) {
        if (device.gl().glPushDebugGroup)
            device.gl().glPushDebugGroup(GL_DEBUG_SOURCE_APPLICATION, 0, GLsizei(label.size()), label.c_str());
    });
}

void CommandList::popDebugGroup() {
    requireRecording("popDebugGroup");
    if (m_debugGroupDepth == 0) throw Error(ErrorCode::InvalidUsage, "popDebugGroup: no debug group is open");
    --m_debugGroupDepth;
    record([](Device& device) {
        if (device.gl().glPopDebugGroup) device.gl().glPopDebugGroup();
    });
}

// ---------------------------------------------------------------------------------------------
// Replay (Device)

namespace {
bool sameVertexLayout(const GraphicsPipelineDesc& a, const GraphicsPipelineDesc& b) {
    auto sameAttribute = [](const VertexAttribute& x, const VertexAttribute& y) {
        return x.location == y.location && x.format == y.format && x.bufferSlot == y.bufferSlot && x.offset == y.offset;
    };
    auto sameBuffer = [](const VertexBufferLayout& x, const VertexBufferLayout& y) {
        return x.slot == y.slot && x.stride == y.stride && x.perInstance == y.perInstance;
    };
    return std::equal(a.vertexAttributes.begin(), a.vertexAttributes.end(), b.vertexAttributes.begin(),
                      b.vertexAttributes.end(), sameAttribute) &&
           std::equal(a.vertexBuffers.begin(), a.vertexBuffers.end(), b.vertexBuffers.begin(), b.vertexBuffers.end(),
                      sameBuffer);
}
}  // namespace

void Device::beginRenderPass(const RenderPassDesc& desc) {
    const GLFunctions& f = gl();
    FramebufferKey key;
    std::vector<const Texture*> colors;
    const Texture* depth = nullptr;
    for (const Attachment& a : desc.colors) {
        auto* texture = static_cast<const Texture*>(a.texture.get());
        colors.push_back(texture);
        key.colors.push_back({texture->name(), a.subresource.mipLevel, a.subresource.layer});
    }
    if (desc.depth) {
        depth = static_cast<const Texture*>(desc.depth->texture.get());
        key.depth = {depth->name(), desc.depth->subresource.mipLevel, desc.depth->subresource.layer};
    }
    const GLuint fbo = m_context->framebuffer(key, colors, depth);
    f.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);

    const Texture* any = colors.empty() ? depth : colors[0];
    const uint32_t mip = colors.empty() ? desc.depth->subresource.mipLevel : desc.colors[0].subresource.mipLevel;
    m_renderWidth = any->width(mip);
    m_renderHeight = any->height(mip);
    f.glViewport(0, 0, GLsizei(m_renderWidth), GLsizei(m_renderHeight));
    f.glScissor(0, 0, GLsizei(m_renderWidth), GLsizei(m_renderHeight));
    f.glDepthRangef(0.0f, 1.0f);

    // Clears obey the write masks, which the previous pipeline may have narrowed.
    f.glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    f.glDepthMask(GL_TRUE);
    for (size_t i = 0; i < desc.colors.size(); ++i) {
        const Attachment& a = desc.colors[i];
        if (a.loadOp != LoadOp::Clear) continue;
        if (formatInfo(colors[i]->desc().format).kind == FormatKind::UInt) {
            const GLuint value[4] = {GLuint(a.clearColor[0]), GLuint(a.clearColor[1]), GLuint(a.clearColor[2]),
                                     GLuint(a.clearColor[3])};
            f.glClearBufferuiv(GL_COLOR, GLint(i), value);
        } else {
            f.glClearBufferfv(GL_COLOR, GLint(i), a.clearColor.data());
        }
    }
    if (desc.depth && desc.depth->loadOp == LoadOp::Clear) f.glClearBufferfv(GL_DEPTH, 0, &desc.depth->clearDepth);
    if (m_pipeline) m_pipeline->applyState();
}

void Device::bindPipeline(const Pipeline& pipeline) {
    // Attribute pointers depend on the vertex layout only, which many pipelines share.
    if (!m_pipeline || !sameVertexLayout(m_pipeline->graphics(), pipeline.graphics())) m_vertexStateDirty = true;
    m_pipeline = &pipeline;
    pipeline.applyState();
}

void Device::bindBindingSet(const BindingSetDesc& desc) {
    const GLFunctions& f = gl();
    for (const BindingItem& item : desc.items) {
        switch (item.type) {
            case ResourceType::UniformBuffer:
            case ResourceType::StorageBuffer: {
                auto* buffer = static_cast<const Buffer*>(item.buffer.get());
                const uint64_t range = item.range ? item.range : buffer->desc().size - item.offset;
                f.glBindBufferRange(item.type == ResourceType::UniformBuffer ? GL_UNIFORM_BUFFER : GL_SHADER_STORAGE_BUFFER,
                                    item.binding, buffer->name(), GLintptr(item.offset), GLsizeiptr(range));
                break;
            }
            case ResourceType::SampledTexture: {
                auto* texture = static_cast<const Texture*>(item.texture.get());
                auto* sampler = static_cast<const Sampler*>(item.sampler.get());
                const ResolvedTextureView view = resolveTextureView(item);
                f.glActiveTexture(GL_TEXTURE0 + item.binding);
                if (isES()) {
                    // No texture views: the whole texture, showing the view's mips (and all of
                    // them when the binding has no range, so no earlier range leaks into it).
                    f.glBindTexture(texture->target(), texture->name());
                    texture->applyMipRange(view.baseMip, view.mipCount);
                } else {
                    const auto [name, target] = texture->viewFor(view);
                    f.glBindTexture(target, name);
                }
                f.glBindSampler(item.binding, sampler->name());
                break;
            }
            case ResourceType::StorageImage: {
                auto* texture = static_cast<const Texture*>(item.texture.get());
                const ResolvedTextureView view = resolveTextureView(item);
                // All layers (layered, so a compute shader can write every slice of a 3D texture,
                // face of a cube, layer of an array), or one layer as a 2D image.
                const bool oneLayer = view.dimension == TextureDimension::Texture2D &&
                                      texture->desc().dimension != TextureDimension::Texture2D;
                f.glBindImageTexture(item.binding, texture->name(), GLint(item.mipLevel), oneLayer ? GL_FALSE : GL_TRUE,
                                     oneLayer ? GLint(view.baseLayer) : 0, GL_READ_WRITE,
                                     texture->format().internalFormat);
                break;
            }
        }
    }
}

void Device::applyMipRanges(const std::vector<MipRange>& ranges) {
    for (const MipRange& r : ranges) {
        if (r.texture->hasMipRange(r.baseMip, r.mipCount)) continue;
        gl().glActiveTexture(GL_TEXTURE0 + r.unit);   // where the binding set bound it
        r.texture->applyMipRange(r.baseMip, r.mipCount);
    }
}

void Device::setVertexBuffer(uint32_t slot, GLuint buffer, uint64_t offset) {
    VertexBinding& binding = m_vertexBuffers[slot];
    if (binding.buffer == buffer && binding.offset == offset) return;
    binding = {buffer, offset};
    m_vertexStateDirty = true;
}

void Device::setIndexBuffer(GLuint buffer, IndexType type, uint64_t offset) {
    m_indexBuffer = buffer;
    m_indexType = type;
    m_indexOffset = offset;
}

void Device::bindVertexAttributes(int64_t baseVertexOffset, uint32_t baseInstanceOffset) {
    if (!m_vertexStateDirty && baseVertexOffset == m_vertexStateBase && baseInstanceOffset == m_vertexStateInstanceBase)
        return;
    m_vertexStateDirty = false;
    m_vertexStateBase = baseVertexOffset;
    m_vertexStateInstanceBase = baseInstanceOffset;
    const GLFunctions& f = gl();
    const GraphicsPipelineDesc& desc = m_pipeline->graphics();
    uint32_t wanted = 0;
    for (const VertexAttribute& attribute : desc.vertexAttributes) {
        const VertexBufferLayout& layout = *std::find_if(desc.vertexBuffers.begin(), desc.vertexBuffers.end(),
                                                         [&](const VertexBufferLayout& l) { return l.slot == attribute.bufferSlot; });
        const auto binding = m_vertexBuffers.find(attribute.bufferSlot);   // present: checked at record time
        const int64_t stepOffset = (layout.perInstance ? int64_t(baseInstanceOffset) : baseVertexOffset) * int64_t(layout.stride);
        const auto pointer = reinterpret_cast<const void*>(
            uintptr_t(int64_t(binding->second.offset) + int64_t(attribute.offset) + stepOffset));
        f.glBindBuffer(GL_ARRAY_BUFFER, binding->second.buffer);
        const GLuint location = attribute.location;
        const auto stride = GLsizei(layout.stride);
        switch (attribute.format) {
            case VertexFormat::Float1: f.glVertexAttribPointer(location, 1, GL_FLOAT, GL_FALSE, stride, pointer); break;
            case VertexFormat::Float2: f.glVertexAttribPointer(location, 2, GL_FLOAT, GL_FALSE, stride, pointer); break;
            case VertexFormat::Float3: f.glVertexAttribPointer(location, 3, GL_FLOAT, GL_FALSE, stride, pointer); break;
            case VertexFormat::Float4: f.glVertexAttribPointer(location, 4, GL_FLOAT, GL_FALSE, stride, pointer); break;
            case VertexFormat::UByte4Norm:
                f.glVertexAttribPointer(location, 4, GL_UNSIGNED_BYTE, GL_TRUE, stride, pointer);
                break;
            case VertexFormat::UInt1: f.glVertexAttribIPointer(location, 1, GL_UNSIGNED_INT, stride, pointer); break;
        }
        // Strides are >= 1 (validated): GL would read 0 as "tightly packed".
        f.glVertexAttribDivisor(location, layout.perInstance ? 1 : 0);
        wanted |= 1u << location;
    }
    for (GLuint location = 0; location < 16; ++location) {
        const uint32_t bit = 1u << location;
        if ((wanted & bit) && !(m_enabledAttributes & bit)) f.glEnableVertexAttribArray(location);
        if (!(wanted & bit) && (m_enabledAttributes & bit)) f.glDisableVertexAttribArray(location);
    }
    m_enabledAttributes = wanted;
}

void Device::setBaseInstance(uint32_t firstInstance) {
    // SPIRV-Cross emulates gl_InstanceIndex as gl_InstanceID + this uniform (0 after linking).
    const GLint location = m_pipeline->baseInstanceLocation();
    if (location < 0 || GLint(firstInstance) == m_pipeline->baseInstanceValue) return;
    gl().glUniform1i(location, GLint(firstInstance));
    m_pipeline->baseInstanceValue = GLint(firstInstance);
}

void Device::draw(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex, uint32_t firstInstance) {
    const GLFunctions& f = gl();
    const GLenum mode = primitiveMode(m_pipeline->graphics().topology);
    setBaseInstance(firstInstance);
    if (firstInstance != 0 && !isES()) {
        bindVertexAttributes(0, 0);
        f.glDrawArraysInstancedBaseInstance(mode, GLint(firstVertex), GLsizei(vertexCount), GLsizei(instanceCount),
                                            firstInstance);
        return;
    }
    // ES 3.0 has no base instance: the per-instance attribute pointers start at firstInstance
    // instead (gl_InstanceIndex gets it from the base-instance uniform above).
    bindVertexAttributes(0, isES() ? firstInstance : 0);
    f.glDrawArraysInstanced(mode, GLint(firstVertex), GLsizei(vertexCount), GLsizei(instanceCount));
}

void Device::drawIndexed(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex, int32_t vertexOffset,
                           uint32_t firstInstance) {
    const GLFunctions& f = gl();
    const GLenum mode = primitiveMode(m_pipeline->graphics().topology);
    const GLenum type = m_indexType == IndexType::UInt16 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
    const uint64_t indexSize = m_indexType == IndexType::UInt16 ? 2 : 4;
    const auto indices = reinterpret_cast<const void*>(uintptr_t(m_indexOffset + uint64_t(firstIndex) * indexSize));
    setBaseInstance(firstInstance);
    if (m_boundIndexBuffer != m_indexBuffer) {
        f.glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_indexBuffer);
        m_boundIndexBuffer = m_indexBuffer;
    }
    if (!isES()) {
        bindVertexAttributes(0, 0);
        f.glDrawElementsInstancedBaseVertexBaseInstance(mode, GLsizei(indexCount), type, indices, GLsizei(instanceCount),
                                                        vertexOffset, firstInstance);
        return;
    }
    // ES 3.0 has no base vertex or base instance: shift the attribute pointers instead.
    bindVertexAttributes(vertexOffset, firstInstance);
    f.glDrawElementsInstanced(mode, GLsizei(indexCount), type, indices, GLsizei(instanceCount));
}

void Device::dispatch(uint32_t x, uint32_t y, uint32_t z) {
    const GLFunctions& f = gl();
    f.glDispatchCompute(x, y, z);
    // Conservative: whatever reads the results next (draws, copies, mapping) sees them.
    f.glMemoryBarrier(GL_ALL_BARRIER_BITS);
}

}  // namespace janus::rhi::gl
