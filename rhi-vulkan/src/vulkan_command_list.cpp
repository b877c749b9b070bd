// Command lists: recording with state checks, barriers from hazard tracking, submission with a fence.
#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstring>

#include "vulkan_backend.h"
#include "janus/rhi/index_value_validation.h"

namespace janus::rhi::vulkan {
namespace {

std::string formatList(const std::vector<Format>& colors, Format depth) {
    std::string text = "[";
    for (size_t i = 0; i < colors.size(); ++i) text += (i ? ", " : "") + std::string(toString(colors[i]));
    return text + "] depth " + (depth == Format::Unknown ? std::string("none") : toString(depth));
}

ResourceAccess bufferAccess(const Buffer& buffer, uint64_t offset, uint64_t size, VkPipelineStageFlags stages,
                            VkAccessFlags access, bool write) {
    return {&buffer, {offset, offset + size}, stages, access, write};
}

ResourceAccess textureAccess(const Texture& texture, KeyRange range, VkPipelineStageFlags stages,
                             VkAccessFlags access, bool write) {
    return {&texture, range, stages, access, write};
}

ResourceAccess transferRead(const Buffer& buffer, uint64_t offset, uint64_t size) {
    return bufferAccess(buffer, offset, size, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT, false);
}
ResourceAccess transferWrite(const Buffer& buffer, uint64_t offset, uint64_t size) {
    return bufferAccess(buffer, offset, size, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, true);
}
ResourceAccess transferRead(const Texture& texture, KeyRange range) {
    return textureAccess(texture, range, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT, false);
}
ResourceAccess transferWrite(const Texture& texture, KeyRange range) {
    return textureAccess(texture, range, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, true);
}

KeyRange keysOf(TextureSubresource sub) { return subresourceKeys(sub.mipLevel, sub.layer); }

}  // namespace

void CommandList::access(std::initializer_list<ResourceAccess> accesses) {
    m_hazards.access(m_commands, std::span(accesses.begin(), accesses.size()));
}

CommandList::CommandList(ContextPtr context)
    : m_context(std::move(context)), m_poolCallbacks(m_context->commandMemory ? m_commandMemory.callbacks() : nullptr) {
    VkDevice device = m_context->device;
    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.queueFamilyIndex = m_context->queueFamily;
    check(vkCreateCommandPool(device, &poolInfo, m_poolCallbacks, &m_pool), ErrorCode::OutOfMemory,
          "vkCreateCommandPool");
    VkCommandBufferAllocateInfo allocInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    allocInfo.commandPool = m_pool;
    allocInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    allocInfo.commandBufferCount = 2;
    VkCommandBuffer buffers[2] = {};
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkResult result = vkAllocateCommandBuffers(device, &allocInfo, buffers);
    if (result == VK_SUCCESS) result = vkCreateFence(device, &fenceInfo, nullptr, &m_fence);
    if (result != VK_SUCCESS) {
        vkDestroyCommandPool(device, m_pool, m_poolCallbacks);
        check(result, ErrorCode::OutOfMemory, "creating a command list");
    }
    m_prologue = buffers[0];
    m_commands = buffers[1];
}

CommandList::~CommandList() {
    if (m_pending) vkWaitForFences(m_context->device, 1, &m_fence, VK_TRUE, UINT64_MAX);
    vkDestroyFence(m_context->device, m_fence, nullptr);
    vkDestroyCommandPool(m_context->device, m_pool, m_poolCallbacks);
}

void CommandList::waitUntilDone() {
    if (!m_pending) return;
    if (m_submission <= m_context->finishedSubmissions.load(std::memory_order_acquire)) {
        m_pending = false;   // a waitIdle() since saw it finish: the fence has signalled
        return;
    }
    check(vkWaitForFences(m_context->device, 1, &m_fence, VK_TRUE, UINT64_MAX), ErrorCode::DeviceLost,
          "vkWaitForFences");
    m_pending = false;
}

void CommandList::throwNotRecording(std::string_view call) const {
    throw Error(ErrorCode::InvalidUsage, fmt::format("{}: the command list is not recording; call begin() first", call));
}

void CommandList::requireInsideRenderPass(std::string_view call) const {
    requireRecording(call);
    if (!inRenderPass())
        throw Error(ErrorCode::InvalidUsage, fmt::format("{}: needs a render pass (the next one would reset it); call "
                                                         "beginRenderPass() first", call));
}

void CommandList::throwNotRecordingOrInPass(std::string_view call) const {
    requireRecording(call);
    throw Error(ErrorCode::InvalidUsage,
                fmt::format("{}: not allowed inside a render pass; call endRenderPass() first", call));
}

void CommandList::beginImpl() {
    waitUntilDone();
    m_staging.clear();
    m_timers.clear();
    check(vkResetCommandPool(m_context->device, m_pool, 0), ErrorCode::DeviceLost, "vkResetCommandPool");
    VkCommandBufferBeginInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    check(vkBeginCommandBuffer(m_commands, &info), ErrorCode::DeviceLost, "vkBeginCommandBuffer");
    m_state = State::Recording;
    m_drawCalls = {m_context->cmdBindDescriptorSets, m_context->cmdDraw, m_context->cmdDrawIndexed};
    m_keepAlive.beginRecording();
    m_hazards.reset();
    m_drawNeeds = kNeedsEverything;
    m_graphicsPipeline = nullptr;
    m_computePipeline = nullptr;
    m_bindingSets = {};
    m_graphicsSetUses = {};
    m_computeSetUses = {};
    m_dirtyGraphicsSets = m_dirtyComputeSets = 0;
    m_vertexBindings.clear();
    m_indexBuffer = nullptr;
    m_passReads.resource = nullptr;
    m_debugGroupDepth = 0;
}

void CommandList::end() {
    requireOutsideRenderPass("end()");
    if (m_debugGroupDepth != 0)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("end(): {} debug group(s) are still open; call popDebugGroup()", m_debugGroupDepth));
    // Later device-level reads map memory on the host; make this list's writes visible to it.
    hostBarrier(m_commands);
    m_keepAlive.releaseUnused();
    check(vkEndCommandBuffer(m_commands), ErrorCode::DeviceLost, "vkEndCommandBuffer");

    // A list without timers submits its commands alone: an empty prologue would still cost a
    // command buffer's begin, end and submission every frame (docs/BENCHMARKS.md, session 24).
    if (!m_timers.empty()) {
        VkCommandBufferBeginInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        check(vkBeginCommandBuffer(m_prologue, &info), ErrorCode::DeviceLost, "vkBeginCommandBuffer");
        for (const TimerUse& use : m_timers) vkCmdResetQueryPool(m_prologue, use.timer->pool, 0, 2);
        check(vkEndCommandBuffer(m_prologue), ErrorCode::DeviceLost, "vkEndCommandBuffer");
    }
    m_state = State::Executable;
}

void CommandList::submit() {
    if (m_state != State::Executable)
        throw Error(ErrorCode::InvalidUsage,
                    m_state == State::Recording ? "execute(): the command list is still recording; call end() first"
                                                : "execute(): the command list is empty; call begin() and end() first");
    waitUntilDone();   // executing the same list again: its previous run must have finished
    std::lock_guard lock(m_context->queueMutex);
    check(vkResetFences(m_context->device, 1, &m_fence), ErrorCode::DeviceLost, "vkResetFences");
    const VkCommandBuffer buffers[] = {m_prologue, m_commands};
    const bool prologue = !m_timers.empty();   // end() recorded it
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = prologue ? 2 : 1;
    submit.pCommandBuffers = prologue ? buffers : buffers + 1;
    check(vkQueueSubmit(m_context->queue, 1, &submit, m_fence), ErrorCode::DeviceLost, "vkQueueSubmit");
    m_pending = true;
    m_submission = ++m_context->lastSubmission;
    for (TimerUse& use : m_timers) use.timer->submitted = use.began && use.ended;
}

// `desc` is validated (rhi/src/validation.cpp): attachments exist, are render targets of the
// right kind and have one size.
void CommandList::beginRenderPassImpl(const RenderPassDesc& desc) {
    requireOutsideRenderPass("beginRenderPass()");

    // The pass's scratch lives in the list, so that a frame's passes allocate nothing once the
    // list has seen as many attachments.
    std::optional<VkExtent2D> extent;
    std::vector<ResourceAccess>& attachmentAccesses = m_passScratch.accesses;
    std::vector<VkRenderingAttachmentInfo>& colors = m_passScratch.colors;
    attachmentAccesses.clear();
    colors.clear();
    m_layerResolves.clear();
    m_passColorFormats.clear();
    auto attach = [&](const Attachment& a, bool depth, size_t colorIndex) {
        auto* texture = native<Texture>(
            a.texture,
            [&] { return depth ? std::string("depth attachment") : fmt::format("colour attachment {}", colorIndex); },
            m_context.get());
        const TextureDesc& tdesc = texture->desc();
        const VkExtent3D e = texture->extent(a.subresource.mipLevel);
        extent = VkExtent2D{e.width, e.height};
        m_keepAlive.keep(a.texture, texture->keepMark);
        // Load and store ops read and write the attachment; counting it as written covers both.
        attachmentAccesses.push_back(
            depth ? textureAccess(*texture, keysOf(a.subresource),
                                  VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT,
                                  VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                                      VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                                  true)
                  : textureAccess(*texture, keysOf(a.subresource),
                                  VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                                  VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, true));

        VkRenderingAttachmentInfo info{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        info.imageView = texture->attachmentView(a.subresource);
        info.imageLayout = VK_IMAGE_LAYOUT_GENERAL;
        info.loadOp = a.loadOp == LoadOp::Load    ? VK_ATTACHMENT_LOAD_OP_LOAD
                      : a.loadOp == LoadOp::Clear ? VK_ATTACHMENT_LOAD_OP_CLEAR
                                                  : VK_ATTACHMENT_LOAD_OP_DONT_CARE;
        info.storeOp = a.storeOp == StoreOp::Store ? VK_ATTACHMENT_STORE_OP_STORE : VK_ATTACHMENT_STORE_OP_DONT_CARE;
        if (depth) {
            info.clearValue.depthStencil = {a.clearDepth, 0};
        } else if (formatInfo(tdesc.format).kind == FormatKind::UInt) {
            for (int i = 0; i < 4; ++i) info.clearValue.color.uint32[i] = uint32_t(std::max(0.0f, a.clearColor[i]));
        } else {
            for (int i = 0; i < 4; ++i) info.clearValue.color.float32[i] = a.clearColor[i];
        }
        if (a.resolveTexture) {
            // Validated: a colour attachment of the same non-integer format and size. The resolve
            // writes the whole subresource at the end of the pass, in the colour output stage.
            auto* target = native<Texture>(a.resolveTexture, [&] { return fmt::format("colour attachment {}'s resolve", colorIndex); },
                                           m_context.get());
            m_keepAlive.keep(a.resolveTexture, target->keepMark);
            if (a.resolveSubresource.layer != 0) {
                // After the pass, from the stored samples (m_layerResolves).
                m_layerResolves.push_back({texture, target, a.resolveSubresource});
                info.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
                return info;
            }
            attachmentAccesses.push_back(textureAccess(*target, keysOf(a.resolveSubresource),
                                                       VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                                                       VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                                                       true));
            info.resolveMode = VK_RESOLVE_MODE_AVERAGE_BIT;
            info.resolveImageView = target->attachmentView(a.resolveSubresource);
            info.resolveImageLayout = VK_IMAGE_LAYOUT_GENERAL;
        }
        return info;
    };

    for (size_t i = 0; i < desc.colors.size(); ++i) {
        colors.push_back(attach(desc.colors[i], false, i));
        m_passColorFormats.push_back(desc.colors[i].texture->desc().format);
    }
    VkRenderingAttachmentInfo depthInfo{};
    if (desc.depth) depthInfo = attach(*desc.depth, true, 0);

    // No barrier is possible between the draws of a pass, and what they will read is not known
    // yet: anything written since the last barrier is made visible now (one barrier per pass at
    // most), as is a read of an attachment (write after read).
    bool hazard = m_hazards.hasWrites();
    for (const ResourceAccess& a : attachmentAccesses) hazard = hazard || m_hazards.conflicts(a);
    if (hazard) m_hazards.barrier(m_commands);
    for (const ResourceAccess& a : attachmentAccesses) m_hazards.record(a);

    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, *extent};
    info.layerCount = 1;
    info.colorAttachmentCount = uint32_t(colors.size());
    info.pColorAttachments = colors.data();
    info.pDepthAttachment = desc.depth ? &depthInfo : nullptr;
    m_context->cmdBeginRendering(m_commands, &info);

    m_drawNeeds = kNeedsEverything & ~kNeedsRenderPass;
    m_passDesc.colors = desc.colors;   // into the capacity endRenderPass kept
    m_passDesc.depth = desc.depth;
    m_passTrackedSets = 0;
    m_passDepthFormat = desc.depth ? desc.depth->texture->desc().format : Format::Unknown;
    m_passSampleCount = (desc.depth ? desc.depth->texture : desc.colors[0].texture)->desc().sampleCount;
    setViewportImpl({0, 0, float(extent->width), float(extent->height), 0, 1});
    setScissorImpl({0, 0, extent->width, extent->height});
}

void CommandList::endRenderPass() {
    requireRecording("endRenderPass()");
    if (!inRenderPass()) throw Error(ErrorCode::InvalidUsage, "endRenderPass(): no render pass is open");
    flushPassReads();
    m_context->cmdEndRendering(m_commands);
    m_drawNeeds |= kNeedsRenderPass;
    for (const LayerResolve& resolve : m_layerResolves) {
        access({transferRead(*resolve.from, keysOf(TextureSubresource{})), transferWrite(*resolve.to, keysOf(resolve.sub))});
        VkImageResolve region{};
        region.srcSubresource = resolve.from->copyLayers({});
        region.dstSubresource = resolve.to->copyLayers(resolve.sub);
        region.dstOffset = resolve.to->copyOffset(resolve.sub);
        region.extent = resolve.from->copyExtent({});
        vkCmdResolveImage(m_commands, resolve.from->image, VK_IMAGE_LAYOUT_GENERAL, resolve.to->image, VK_IMAGE_LAYOUT_GENERAL, 1,
                          &region);
    }
    m_layerResolves.clear();
    m_passDesc.colors.clear();   // keeps its capacity for the next pass
    m_passDesc.depth.reset();
}

// Values validated by the front (rhi/src/validation.cpp).
void CommandList::setViewportImpl(const Viewport& v) {
    requireInsideRenderPass("setViewport()");
    // Positive height: row 0 is at the top and NDC y = -1 maps to it (no flip, see rhi.h).
    VkViewport viewport{v.x, v.y, v.width, v.height, v.minDepth, v.maxDepth};
    vkCmdSetViewport(m_commands, 0, 1, &viewport);
}

void CommandList::setScissorImpl(const ScissorRect& s) {
    requireInsideRenderPass("setScissor()");
    VkRect2D rect{{s.x, s.y}, {s.width, s.height}};
    vkCmdSetScissor(m_commands, 0, 1, &rect);
}

void CommandList::setPipeline(const PipelineHandle& handle) {
    requireRecording("setPipeline()");
    auto* pipeline = native<Pipeline>(handle, "setPipeline(): the pipeline", m_context.get());
    if (pipeline == m_computePipeline || pipeline == m_graphicsPipeline) return;   // already bound
    m_keepAlive.keep(handle, pipeline->keepMark);
    if (pipeline->isCompute()) {
        m_computePipeline = pipeline;
        m_dirtyComputeSets = ~0u;
        m_context->cmdBindPipeline(m_commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline->pipeline);
    } else {
        m_graphicsPipeline = pipeline;
        m_dirtyGraphicsSets = ~0u;
        m_passTrackedSets = 0;   // another pipeline may use the sets differently
        m_drawNeeds |= kNeedsStateCheck | kNeedsVertexTracking | kNeedsSets;
        m_context->cmdBindPipeline(m_commands, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline->pipeline);
    }
}

// The common case calls nothing before its last step (bindInPass's vkCmdBindDescriptorSets, after
// which nothing is left to do), so it keeps no registers across a call. Anything else (not
// recording, or a set the list does not hold yet: of another backend or device, or new) takes the
// checked path. A set the list holds passed that path's checks (its type, and the device that
// made it is this list's) when the list first held it, so not even its type is checked again.
void CommandList::setBindingSetImpl(uint32_t set, const BindingSetHandle& bindings) {   // set < kMaxBindingSets
    IBindingSet& object = *bindings;   // not null: the front end checked
    if (m_state != State::Recording || !m_keepAlive.keepIfHeld(keepMarkOf(object))) [[unlikely]]
        return setBindingSetChecked(set, bindings);
    auto* bindingSet = static_cast<BindingSet*>(&object);
    if (m_bindingSets[set] == bindingSet) return;   // already bound
    bindHeldSet(set, *bindingSet);
}

// A set with dynamic uniform buffers. The common case, the set already bound and tracked at `set`
// and moved to other offsets between draws of a pass, binds it again at once with the offsets (the
// tracking saw every window), so the draw after it stays on its straight-line path: the per-draw
// cost of one set for a whole pass; likewise between dispatches. Anything else leaves the bind to the next draw or dispatch's
// general path (the straight-line ones pass no offsets, so a dynamic set never takes them).
void CommandList::setBindingSetImpl(uint32_t set, const BindingSetHandle& bindings,
                                    std::span<const uint32_t> dynamicOffsets) {   // count and alignment checked
    IBindingSet& object = *bindings;   // not null: the front end checked
    if (m_state != State::Recording || !m_keepAlive.keepIfHeld(keepMarkOf(object))) [[unlikely]]
        return setDynamicSetChecked(set, bindings, dynamicOffsets);
    auto* bindingSet = static_cast<BindingSet*>(&object);   // held: its type was checked then
    takeDynamicOffsets(*bindingSet, bindingSet->dynamicWindows(), dynamicOffsets, m_dynamicOffsets[set]);
    const uint32_t bit = 1u << set;
    // Bound and tracked for this pipeline (no draw need left), so m_graphicsSetUses[set] is this
    // set's use for the pipeline's layout.
    if (m_bindingSets[set] == bindingSet && (m_drawNeeds & ~kNeedsIndexTracking) == 0 &&
        (m_graphicsPipeline->usedSets & bit) && !(m_dirtyGraphicsSets & bit)) [[likely]] {
        const BindingSet::LayoutUse& use = *m_graphicsSetUses[set];
        m_dirtyComputeSets |= bit;
        if (!use.offsetsAsGiven) [[unlikely]]
            return bindDynamicUse(VK_PIPELINE_BIND_POINT_GRAPHICS, m_graphicsPipeline->layout, set, use);
        return m_context->cmdBindDescriptorSets(m_commands, VK_PIPELINE_BIND_POINT_GRAPHICS, m_graphicsPipeline->layout,
                                                set, 1, &use.set, use.dynamicCount, m_dynamicOffsets[set].data());
    }
    // The same between dispatches: bound for the compute pipeline, which reads it (not dirty, so
    // m_computeSetUses[set] is this set's use for its layout); draws bind it at their next one.
    if (m_bindingSets[set] == bindingSet && m_computePipeline && (m_computePipeline->usedSets & bit) &&
        !(m_dirtyComputeSets & bit)) {
        m_dirtyGraphicsSets |= bit;
        m_drawNeeds |= kNeedsSets | kNeedsDynamicBind;
        return bindDynamicUse(VK_PIPELINE_BIND_POINT_COMPUTE, m_computePipeline->layout, set, *m_computeSetUses[set]);
    }
    bindDynamicSet(set, bindings, *bindingSet);
}

void CommandList::setDynamicSetChecked(uint32_t set, const BindingSetHandle& bindings,
                                       std::span<const uint32_t> dynamicOffsets) {
    requireRecording("setBindingSet()");
    auto* bindingSet = native<BindingSet>(bindings, "setBindingSet(): the binding set", m_context.get());
    takeDynamicOffsets(*bindingSet, bindingSet->dynamicWindows(), dynamicOffsets, m_dynamicOffsets[set]);
    bindDynamicSet(set, bindings, *bindingSet);
}

// vkCmdBindDescriptorSets of `use` at `set`, with the offsets of the set's dynamic bindings the
// layout has (a pipeline may read some of them).
void CommandList::bindDynamicUse(VkPipelineBindPoint bindPoint, VkPipelineLayout layout, uint32_t set,
                                 const BindingSet::LayoutUse& use) {
    std::array<uint32_t, kMaxDynamicOffsetsPerSet> offsets;
    for (uint32_t i = 0; i < use.dynamicCount; ++i) offsets[i] = m_dynamicOffsets[set][use.dynamicOffsetIndex[i]];
    m_context->cmdBindDescriptorSets(m_commands, bindPoint, layout, set, 1, &use.set, use.dynamicCount, offsets.data());
}

// The dynamic set at its new offsets, left for the next draw or dispatch to bind (its general path).
void CommandList::bindDynamicSet(uint32_t set, const BindingSetHandle& bindings, BindingSet& bindingSet) {
    if (m_bindingSets[set] == &bindingSet) {
        m_dirtyGraphicsSets |= 1u << set;
        m_dirtyComputeSets |= 1u << set;
        m_drawNeeds |= kNeedsSets | kNeedsDynamicBind;
        return;
    }
    m_keepAlive.keep(bindings, keepMarkOf(bindingSet));
    bindHeldSet(set, bindingSet);   // bindInPass declines it: a dynamic use has no onlyRead
    m_drawNeeds |= kNeedsDynamicBind;
}

void CommandList::setBindingSetChecked(uint32_t set, const BindingSetHandle& bindings) {
    requireRecording("setBindingSet()");
    bindSet(set, bindings, native<BindingSet>(bindings, "setBindingSet(): the binding set", m_context.get()));
}

void CommandList::bindSet(uint32_t set, const BindingSetHandle& bindings, BindingSet* bindingSet) {
    if (m_bindingSets[set] == bindingSet) return;   // already bound
    m_keepAlive.keep(bindings, keepMarkOf(*bindingSet));
    bindHeldSet(set, *bindingSet);
}

// `bindingSet` at `set`, now that the list holds it.
[[gnu::always_inline]] inline void CommandList::bindHeldSet(uint32_t set, BindingSet& bindingSet) {
    m_bindingSets[set] = &bindingSet;
    m_dirtyComputeSets |= 1u << set;
    if (bindInPass(set, bindingSet)) return;
    bindingSet.prefetchFirstUse();
    m_dirtyGraphicsSets |= 1u << set;
    m_passTrackedSets &= ~(1u << set);
    m_drawNeeds |= kNeedsSets;
}

// The set a pass changes per draw (a uniform slice per draw), bound now rather than at the draw,
// so that the draw after it is only its range check and the vkCmdDraw (drawStateBound): in a
// render pass whose draw state was checked, with a graphics pipeline whose only set this is, when
// the set has a descriptor set for that pipeline's layout already (findUse), no texture, and one
// access, a read of the resource the pass's draws read so far. That read joins the pass's hull,
// as trackDrawBindings would at the draw; if no draw follows, the hull is only wider, which can
// add a barrier but never miss one. Anything else is left to the draw, which binds and tracks what is dirty.
[[gnu::always_inline]] inline bool CommandList::bindInPass(uint32_t set, const BindingSet& bindingSet) {
    // One test for both: the state check passes only with a graphics pipeline set.
    if (m_drawNeeds & (kNeedsRenderPass | kNeedsStateCheck)) return false;
    const Pipeline* pipeline = m_graphicsPipeline;
    if (pipeline->usedSets != 1u << set) return false;
    const DescriptorSetLayoutInfo& layout = *pipeline->sets[set];
    const BindingSet::LayoutUse* use = bindingSet.findUse(layout.layout);
    if (!use || !joinPassReads(*use, layout)) return false;
    m_passTrackedSets |= 1u << set;
    m_graphicsSetUses[set] = use;
    m_dirtyGraphicsSets &= ~(1u << set);
    m_drawNeeds &= ~kNeedsSets;   // the pipeline's one set is this one, now bound and tracked
    m_drawCalls.bindDescriptorSets(m_commands, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline->layout, set, 1, &use->set, 0,
                                   nullptr);
    return true;
}

void CommandList::throwNoBindingSet(const Pipeline& pipeline, uint32_t set) const {
    const ReflectedBinding& first = pipeline.sets[set]->bindings[0];
    throw Error(ErrorCode::InvalidUsage,
                fmt::format("pipeline '{}' reads set {} (binding {} '{}') but no binding set is bound to set {}; call "
                            "setBindingSet({}, ...)", pipeline.debugName, set, first.binding, first.name, set, set));
}

// Inline, as are prepareDraw and trackDrawBindings below: they run on every draw or dispatch, and
// calls between them cost as much as the work they do.
[[gnu::always_inline]] inline void CommandList::bindDescriptorSets(
    Pipeline& pipeline, VkPipelineBindPoint bindPoint, uint32_t& dirtyMask,
    std::array<const BindingSet::LayoutUse*, Pipeline::kMaxSets>& uses) {
    for (uint32_t toBind = dirtyMask & pipeline.usedSets; toBind; toBind &= toBind - 1) {
        const uint32_t s = uint32_t(std::countr_zero(toBind));
        if (!m_bindingSets[s]) [[unlikely]] throwNoBindingSet(pipeline, s);
        const BindingSet::LayoutUse& use = m_bindingSets[s]->useWith(*pipeline.sets[s], s, pipeline.debugName);
        uses[s] = &use;
        if (use.dynamicCount) [[unlikely]]
            bindDynamicUse(bindPoint, pipeline.layout, s, use);
        else
            m_context->cmdBindDescriptorSets(m_commands, bindPoint, pipeline.layout, s, 1, &use.set, 0, nullptr);
    }
    dirtyMask = 0;   // only now: a failed bind above is reported again on the next draw
}

// Usage, offset and slot validated by the front (rhi/src/validation.cpp).
void CommandList::setVertexBufferImpl(uint32_t slot, const BufferHandle& handle, uint64_t offset) {
    requireRecording("setVertexBuffer()");
    auto* buffer = native<Buffer>(handle, "setVertexBuffer(): the buffer", m_context.get());
    if (m_vertexBindings.size() <= slot) m_vertexBindings.resize(slot + 1);
    VertexBinding& binding = m_vertexBindings[slot];
    if (binding.buffer == buffer && binding.offset == offset) return;   // already bound
    m_keepAlive.keep(handle, buffer->keepMark);
    m_context->cmdBindVertexBuffers(m_commands, slot, 1, &buffer->buffer, &offset);
    binding = {buffer, offset};
    m_drawNeeds |= kNeedsStateCheck | kNeedsVertexTracking;
}

// Type, usage and offset validated by the front (rhi/src/validation.cpp).
void CommandList::setIndexBufferImpl(const BufferHandle& handle, IndexType type, uint64_t offset) {
    requireRecording("setIndexBuffer()");
    auto* buffer = native<Buffer>(handle, "setIndexBuffer(): the buffer", m_context.get());
    const VkIndexType indexType = type == IndexType::UInt16 ? VK_INDEX_TYPE_UINT16 : VK_INDEX_TYPE_UINT32;
    if (m_indexBuffer == buffer && m_indexOffset == offset && m_indexType == indexType) return;   // already bound
    m_keepAlive.keep(handle, buffer->keepMark);
    m_context->cmdBindIndexBuffer(m_commands, buffer->buffer, offset, indexType);
    m_indexBuffer = buffer;
    m_indexOffset = offset;
    m_indexType = indexType;
    m_indexLimit = indexCountLimit(*buffer, offset, type);
    m_drawNeeds |= kNeedsIndexTracking;
}

void CommandList::checkDrawState(std::string_view call) {
    if (!m_graphicsPipeline)
        throw Error(ErrorCode::InvalidUsage, fmt::format("{}: no graphics pipeline is set; call setPipeline()", call));
    const GraphicsPipelineDesc& desc = m_graphicsPipeline->graphicsDesc;
    if (desc.colorFormats != m_passColorFormats || desc.depthFormat != m_passDepthFormat)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("{}: pipeline '{}' renders to {} but the render pass has {}", call,
                                m_graphicsPipeline->debugName, formatList(desc.colorFormats, desc.depthFormat),
                                formatList(m_passColorFormats, m_passDepthFormat)));
    if (desc.sampleCount != m_passSampleCount)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("{}: pipeline '{}' renders with {} sample(s) but the render pass's attachments have {}; "
                                "set GraphicsPipelineDesc::sampleCount to the attachments' TextureDesc::sampleCount",
                                call, m_graphicsPipeline->debugName, desc.sampleCount, m_passSampleCount));
    for (const VertexBufferLayout& layout : desc.vertexBuffers)
        if (layout.slot >= m_vertexBindings.size() || !m_vertexBindings[layout.slot].buffer)
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("{}: pipeline '{}' reads vertex buffer slot {}, but none is bound; call "
                                    "setVertexBuffer({}, ...)", call, m_graphicsPipeline->debugName, layout.slot,
                                    layout.slot));
    m_drawLimits = drawRangeLimits(desc, [this](uint32_t slot) { return boundVertexBuffer(slot); });
    m_drawNeeds &= ~kNeedsStateCheck;
}

[[gnu::always_inline]] inline void CommandList::checkViewOverlaps(
    const Pipeline& pipeline, const std::array<const BindingSet::LayoutUse*, Pipeline::kMaxSets>& uses, bool inPass,
    std::string_view call) {
    bool textures = false;   // most sets have none: nothing to check
    for (uint32_t sets = pipeline.usedSets; sets; sets &= sets - 1)
        textures = textures || uses[std::countr_zero(sets)]->hasTextureItems;
    if (textures) [[unlikely]] checkTextureViewOverlaps(pipeline, uses, inPass, call);
}

void CommandList::checkTextureViewOverlaps(const Pipeline& pipeline,
                                           const std::array<const BindingSet::LayoutUse*, Pipeline::kMaxSets>& uses,
                                           bool inPass, std::string_view call) {
    m_usedTextures.clear();
    for (uint32_t sets = pipeline.usedSets; sets; sets &= sets - 1) {
        const uint32_t s = uint32_t(std::countr_zero(sets));
        for (const BindingItem* item : uses[s]->textureItems) m_usedTextures.push_back({s, item});
    }
    validateViewOverlaps(m_usedTextures, inPass ? &m_passDesc : nullptr, call);
}

void CommandList::throwDrawOutsidePass(std::string_view call) const {
    requireRecording(call);
    throw Error(ErrorCode::InvalidUsage, fmt::format("{}: draws need a render pass; call beginRenderPass() first", call));
}

// Draws cannot be preceded by barriers (beginRenderPass made earlier writes visible), so what
// they access is only tracked, for the commands after the pass; each binding once per pass.
[[gnu::always_inline]] inline void CommandList::prepareDraw(std::string_view call) {
    if (m_state != State::Recording || !inRenderPass()) [[unlikely]] throwDrawOutsidePass(call);
    if (m_drawNeeds & kNeedsStateCheck) [[unlikely]] checkDrawState(call);
    Pipeline& pipeline = *m_graphicsPipeline;
    if (m_dirtyGraphicsSets & pipeline.usedSets)
        bindDescriptorSets(pipeline, VK_PIPELINE_BIND_POINT_GRAPHICS, m_dirtyGraphicsSets, m_graphicsSetUses);
    if (const uint32_t untracked = pipeline.usedSets & ~m_passTrackedSets) trackDrawBindings(pipeline, untracked, call);
    m_drawNeeds &= ~(kNeedsSets | kNeedsDynamicBind);
    if (m_drawNeeds & kNeedsVertexTracking) [[unlikely]] trackVertexBuffers(pipeline);
}

[[gnu::always_inline]] inline void CommandList::trackDrawBindings(const Pipeline& pipeline, uint32_t untracked,
                                                                  std::string_view call) {
    // Once per pass and set change, like the tracking: no view may overlap an attachment.
    checkViewOverlaps(pipeline, m_graphicsSetUses, true, call);
    for (uint32_t sets = untracked; sets; sets &= sets - 1)
        for (const ResourceAccess& a : m_graphicsSetUses[std::countr_zero(sets)]->accesses) {
            if (a.write) {
                m_hazards.record(a);
            } else if (a.resource == m_passReads.resource) {
                widenPassReads(a.range, a.stages);
            } else {
                flushPassReads();
                m_passReads = a;
            }
        }
    m_passTrackedSets |= untracked;
}

// Many draws read slices of one buffer (a uniform slice per draw): the hull of what they read
// reaches the tracker once, at the end of the pass. Wider than the slices, it can only add a
// barrier, never miss one. Branches rather than min and max: per-draw slices are mostly allocated
// in draw order, so a read rarely moves the hull's begin and at most its end (one store, not two).
[[gnu::always_inline]] inline void CommandList::widenPassReads(const KeyRange& range, VkPipelineStageFlags stages) {
    if (range.begin < m_passReads.range.begin) [[unlikely]] m_passReads.range.begin = range.begin;
    if (range.end > m_passReads.range.end) m_passReads.range.end = range.end;
    m_passReads.stages |= stages;
}

// The straight-line paths' tracking of one set (`use`, for `layout`): when it has no texture (so
// no view-overlap check) and its one access reads the resource the pass reads already, that read
// joins the pass's hull; anything else returns false and changes nothing.
[[gnu::always_inline]] inline bool CommandList::joinPassReads(const BindingSet::LayoutUse& use,
                                                              const DescriptorSetLayoutInfo& layout) {
    const BindingSet::OnlyRead& read = use.onlyRead;
    if (!read.resource || read.resource != m_passReads.resource) return false;
    widenPassReads(read.range, layout.onlyBindingStages);
    return true;
}

void CommandList::flushPassReads() {
    if (m_passReads.resource) m_hazards.record(m_passReads);
    m_passReads.resource = nullptr;
}

void CommandList::trackVertexBuffers(const Pipeline& pipeline) {
    for (const VertexBufferLayout& layout : pipeline.graphicsDesc.vertexBuffers) {
        const VertexBinding& binding = m_vertexBindings[layout.slot];
        m_hazards.record(bufferAccess(*binding.buffer, binding.offset, binding.buffer->desc().size - binding.offset,
                                      VK_PIPELINE_STAGE_VERTEX_INPUT_BIT, VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT, false));
    }
    m_drawNeeds &= ~kNeedsVertexTracking;
}

// The common draw, straight-line: the draw state was checked and at most one of the pipeline's
// sets changed since the last draw of the pass (the others are bound and tracked), and that one
// has no textures and one read access, of the resource the pass's draws read so far (a uniform
// slice per draw). Any other case, and every error, is prepareDraw's. Skipping the view-overlap
// check is exact: the changed set adds no texture, so the textures in use are those checked
// when the other sets were tracked in this pass.
[[gnu::always_inline]] inline bool CommandList::prepareDrawFast() {
    // kNeedsSets is what this path may do; kNeedsIndexTracking is drawIndexed's.
    if (m_drawNeeds & ~(kNeedsSets | kNeedsIndexTracking)) [[unlikely]] return false;
    const Pipeline& pipeline = *m_graphicsPipeline;
    const uint32_t changed = m_dirtyGraphicsSets & pipeline.usedSets;
    const uint32_t untracked = pipeline.usedSets & ~m_passTrackedSets;
    if ((changed & (changed - 1)) != 0 || (untracked & ~changed) != 0) [[unlikely]] return false;
    if (!changed) {   // then nothing is untracked either
        m_drawNeeds &= ~kNeedsSets;
        return true;
    }
    const uint32_t s = uint32_t(std::countr_zero(changed));
    const BindingSet* bindingSet = m_bindingSets[s];
    const BindingSet::LayoutUse* use = bindingSet ? bindingSet->findUse(pipeline.sets[s]->layout) : nullptr;
    if (!use) [[unlikely]] return false;
    if (untracked) {   // the changed set; nothing is modified before the checks pass
        if (!joinPassReads(*use, *pipeline.sets[s])) [[unlikely]] return false;
        m_passTrackedSets |= untracked;
    }
    m_graphicsSetUses[s] = use;
    m_dirtyGraphicsSets = 0;   // as bindDescriptorSets: every set the pipeline uses is bound
    m_drawNeeds &= ~kNeedsSets;
    // Last, so that only `this` is needed after this call into the driver.
    m_context->cmdBindDescriptorSets(m_commands, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.layout, s, 1, &use->set, 0,
                                     nullptr);
    return true;
}

void CommandList::prepareDrawGeneral(std::string_view call) { prepareDraw(call); }

void CommandList::throwDrawOutOfRange(std::string_view call, bool indexed) const {
    const DrawArguments& a = m_drawArguments;
    rhi::throwDrawOutOfRange({call, a.first, a.count, a.firstInstance, a.instances}, m_graphicsPipeline->graphicsDesc,
                             [this](uint32_t slot) { return boundVertexBuffer(slot); }, indexed ? m_indexBuffer : nullptr, m_indexOffset,
                             m_indexType == VK_INDEX_TYPE_UINT16 ? IndexType::UInt16 : IndexType::UInt32);
}

[[gnu::always_inline]] inline bool CommandList::drawStateBound() const {
    return (m_drawNeeds & ~kNeedsIndexTracking) == 0;
}

// The same for drawIndexed, the index buffer bound and tracked too, and no index values to note
// (validation off).
[[gnu::always_inline]] inline bool CommandList::indexedDrawStateBound() const {
    return m_drawNeeds == 0 && !indexValueLog();
}

// A draw whose sets are bound and tracked (setBindingSet bound the per-draw set: bindInPass) calls
// nothing before the vkCmdDraw, so its arguments stay in registers; any other goes through
// drawPrepared.
void CommandList::draw(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex, uint32_t firstInstance) {
    if (!drawStateBound() || m_drawLimits.exceeded(firstVertex, vertexCount, firstInstance, instanceCount)) [[unlikely]]
        return drawPrepared(vertexCount, instanceCount, firstVertex, firstInstance);
    m_drawCalls.draw(m_commands, vertexCount, instanceCount, firstVertex, firstInstance);
}

void CommandList::drawPrepared(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex,
                               uint32_t firstInstance) {
    // The arguments wait in the list while the bind calls into the driver: held in registers
    // across that call they cost four saved registers on every draw.
    m_drawArguments = {vertexCount, instanceCount, firstVertex, firstInstance};
    if (!prepareDrawFast()) [[unlikely]] prepareDrawGeneral("draw()");
    const DrawArguments& a = m_drawArguments;
    if (m_drawLimits.exceeded(a.first, a.count, a.firstInstance, a.instances)) [[unlikely]]
        throwDrawOutOfRange("draw()", false);
    m_context->cmdDraw(m_commands, a.count, a.instances, a.first, a.firstInstance);
}

// As draw(): with everything bound and tracked (the index buffer too) and no index values to
// note, the range check and the vkCmdDrawIndexed.
void CommandList::drawIndexed(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex, int32_t vertexOffset,
                              uint32_t firstInstance) {
    if (!indexedDrawStateBound() ||
        indexedDrawExceeds(m_drawLimits, m_indexLimit, firstIndex, indexCount, firstInstance, instanceCount)) [[unlikely]]
        return drawIndexedPrepared(indexCount, instanceCount, firstIndex, vertexOffset, firstInstance);
    m_drawCalls.drawIndexed(m_commands, indexCount, instanceCount, firstIndex, vertexOffset, firstInstance);
}

void CommandList::drawIndexedPrepared(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex,
                                      int32_t vertexOffset, uint32_t firstInstance) {
    m_drawArguments = {indexCount, instanceCount, firstIndex, firstInstance, vertexOffset};   // as in draw()
    if (!prepareDrawFast()) [[unlikely]] prepareDrawGeneral("drawIndexed()");
    if (!m_indexBuffer)
        throw Error(ErrorCode::InvalidUsage, "drawIndexed(): no index buffer is bound; call setIndexBuffer()");
    if (m_drawNeeds & kNeedsIndexTracking) {
        m_hazards.record(bufferAccess(*m_indexBuffer, m_indexOffset, m_indexBuffer->desc().size - m_indexOffset,
                                      VK_PIPELINE_STAGE_VERTEX_INPUT_BIT, VK_ACCESS_INDEX_READ_BIT, false));
        m_drawNeeds &= ~kNeedsIndexTracking;
    }
    const DrawArguments& a = m_drawArguments;
    if (indexedDrawExceeds(m_drawLimits, m_indexLimit, a.first, a.count, a.firstInstance, a.instances)) [[unlikely]]
        throwDrawOutOfRange("drawIndexed()", true);
    if (indexValueLog()) [[unlikely]] noteIndexedDraw();
    m_context->cmdDrawIndexed(m_commands, a.count, a.instances, a.first, a.vertexOffset, a.firstInstance);
}

void CommandList::noteIndexedDraw() {
    const DrawArguments& a = m_drawArguments;
    indexValueLog()->noteIndexedDraw(*m_indexBuffer, m_indexOffset,
                                     m_indexType == VK_INDEX_TYPE_UINT16 ? IndexType::UInt16 : IndexType::UInt32, a.first,
                                     a.count, a.vertexOffset,
                                     vertexLimit(m_graphicsPipeline->graphicsDesc,
                                                 [this](uint32_t slot) { return boundVertexBuffer(slot); }));
}

void CommandList::prepareDispatchGeneral() {
    requireOutsideRenderPass("dispatch()");
    if (!m_computePipeline)
        throw Error(ErrorCode::InvalidUsage, "dispatch(): no compute pipeline is set; call setPipeline()");
    Pipeline& pipeline = *m_computePipeline;
    const uint32_t changedSets = m_dirtyComputeSets & pipeline.usedSets;
    bindDescriptorSets(pipeline, VK_PIPELINE_BIND_POINT_COMPUTE, m_dirtyComputeSets, m_computeSetUses);
    if (changedSets) {
        try {
            checkViewOverlaps(pipeline, m_computeSetUses, false, "dispatch()");
        } catch (...) {
            m_dirtyComputeSets |= changedSets;   // checked again by the next dispatch
            throw;
        }
    }
    const uint32_t sets = pipeline.usedSets;
    if (sets && (sets & (sets - 1)) == 0) {   // one set
        m_hazards.access(m_commands, m_computeSetUses[std::countr_zero(sets)]->accesses);
    } else if (sets) {
        // Check every access before tracking any: a dispatch may read one range of a buffer and
        // write another (through two sets) without a hazard against itself.
        bool hazard = false;
        for (uint32_t left = sets; left && !hazard; left &= left - 1)
            for (const ResourceAccess& a : m_computeSetUses[std::countr_zero(left)]->accesses)
                hazard = hazard || m_hazards.conflicts(a);
        if (hazard) m_hazards.barrier(m_commands);
        for (uint32_t left = sets; left; left &= left - 1)
            for (const ResourceAccess& a : m_computeSetUses[std::countr_zero(left)]->accesses) m_hazards.record(a);
    }
}

// The common dispatch, straight-line: one set, its binding set's last layout is the pipeline's
// and, if it changed, it has no textures to check; one access to track. Everything else, and
// every error, is prepareDispatchGeneral's.
[[gnu::always_inline]] inline bool CommandList::prepareDispatchFast() {
    if (m_state != State::Recording || inRenderPass() || !m_computePipeline) [[unlikely]] return false;
    const Pipeline& pipeline = *m_computePipeline;
    const uint32_t sets = pipeline.usedSets;
    if (sets == 0 || (sets & (sets - 1)) != 0) [[unlikely]] return false;
    const uint32_t s = uint32_t(std::countr_zero(sets));
    if (m_dirtyComputeSets & sets) {
        const BindingSet* bindingSet = m_bindingSets[s];
        const BindingSet::LayoutUse* use = bindingSet ? bindingSet->findUse(pipeline.sets[s]->layout) : nullptr;
        if (!use || !use->plainBind) [[unlikely]] return false;
        m_computeSetUses[s] = use;
        m_dirtyComputeSets = 0;   // as bindDescriptorSets: every set the pipeline uses is bound
        m_context->cmdBindDescriptorSets(m_commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.layout, s, 1, &use->set,
                                         0, nullptr);
    }
    const std::span<const ResourceAccess> accesses = m_computeSetUses[s]->accesses;
    // Several accesses: the general path tracks them; it finds the set bound (its dirty bit is
    // clear), so it does not bind it again.
    if (accesses.size() != 1) [[unlikely]] return false;
    m_hazards.accessOne(m_commands, accesses[0]);
    return true;
}

void CommandList::dispatchImpl(uint32_t groupsX, uint32_t groupsY, uint32_t groupsZ) {   // counts within limits
    m_dispatchGroups = {groupsX, groupsY, groupsZ};   // across the calls, as draw()'s arguments
    if (!prepareDispatchFast()) [[unlikely]] prepareDispatchGeneral();
    const std::array<uint32_t, 3>& g = m_dispatchGroups;
    m_context->cmdDispatch(m_commands, g[0], g[1], g[2]);
}

// Transfers: arguments are validated (rhi/src/validation.cpp); ranges and subresources exist.
void CommandList::writeBufferImpl(const BufferHandle& dst, const void* data, uint64_t size, uint64_t dstOffset) {
    requireOutsideRenderPass("writeBuffer()");
    auto* buffer = native<Buffer>(dst, "writeBuffer(): the buffer", m_context.get());
    auto staging = std::make_shared<StagingBuffer>(m_context, size);
    std::memcpy(staging->mapped, data, size);
    m_keepAlive.keep(dst, buffer->keepMark);
    // The staging buffer was written by the host before submission: no device hazard.
    access({transferWrite(*buffer, dstOffset, size)});
    VkBufferCopy region{0, dstOffset, size};
    vkCmdCopyBuffer(m_commands, staging->buffer, buffer->buffer, 1, &region);
    m_staging.push_back(std::move(staging));
}

void CommandList::copyBufferImpl(const BufferHandle& dst, uint64_t dstOffset, const BufferHandle& src,
                                 uint64_t srcOffset, uint64_t size) {
    requireOutsideRenderPass("copyBuffer()");
    auto* to = native<Buffer>(dst, "copyBuffer(): the destination", m_context.get());
    auto* from = native<Buffer>(src, "copyBuffer(): the source", m_context.get());
    m_keepAlive.keep(dst, to->keepMark);
    m_keepAlive.keep(src, from->keepMark);
    access({transferRead(*from, srcOffset, size), transferWrite(*to, dstOffset, size)});
    VkBufferCopy region{srcOffset, dstOffset, size};
    vkCmdCopyBuffer(m_commands, from->buffer, to->buffer, 1, &region);
}

void CommandList::copyBufferToTextureImpl(const TextureHandle& dst, TextureSubresource dstSub, const BufferHandle& src,
                                          uint64_t srcOffset) {
    requireOutsideRenderPass("copyBufferToTexture()");
    auto* texture = native<Texture>(dst, "copyBufferToTexture(): the texture", m_context.get());
    auto* buffer = native<Buffer>(src, "copyBufferToTexture(): the buffer", m_context.get());
    m_keepAlive.keep(dst, texture->keepMark);
    m_keepAlive.keep(src, buffer->keepMark);
    access({transferRead(*buffer, srcOffset, texture->subresourceSize(dstSub.mipLevel)),
            transferWrite(*texture, keysOf(dstSub))});
    VkBufferImageCopy region{};
    region.bufferOffset = srcOffset;
    region.imageSubresource = texture->copyLayers(dstSub);
    region.imageOffset = texture->copyOffset(dstSub);
    region.imageExtent = texture->copyExtent(dstSub);
    vkCmdCopyBufferToImage(m_commands, buffer->buffer, texture->image, VK_IMAGE_LAYOUT_GENERAL, 1, &region);
}

void CommandList::copyTextureToBufferImpl(const BufferHandle& dst, uint64_t dstOffset, const TextureHandle& src,
                                          TextureSubresource srcSub) {
    requireOutsideRenderPass("copyTextureToBuffer()");
    auto* buffer = native<Buffer>(dst, "copyTextureToBuffer(): the buffer", m_context.get());
    auto* texture = native<Texture>(src, "copyTextureToBuffer(): the texture", m_context.get());
    m_keepAlive.keep(dst, buffer->keepMark);
    m_keepAlive.keep(src, texture->keepMark);
    access({transferRead(*texture, keysOf(srcSub)),
            transferWrite(*buffer, dstOffset, texture->subresourceSize(srcSub.mipLevel))});
    VkBufferImageCopy region{};
    region.bufferOffset = dstOffset;
    region.imageSubresource = texture->copyLayers(srcSub);
    region.imageOffset = texture->copyOffset(srcSub);
    region.imageExtent = texture->copyExtent(srcSub);
    vkCmdCopyImageToBuffer(m_commands, texture->image, VK_IMAGE_LAYOUT_GENERAL, buffer->buffer, 1, &region);
}

void CommandList::copyTextureImpl(const TextureHandle& dst, TextureSubresource dstSub, const TextureHandle& src,
                                  TextureSubresource srcSub) {
    requireOutsideRenderPass("copyTexture()");
    auto* to = native<Texture>(dst, "copyTexture(): the destination", m_context.get());
    auto* from = native<Texture>(src, "copyTexture(): the source", m_context.get());
    const VkExtent3D srcExtent = from->copyExtent(srcSub);
    m_keepAlive.keep(dst, to->keepMark);
    m_keepAlive.keep(src, from->keepMark);
    access({transferRead(*from, keysOf(srcSub)), transferWrite(*to, keysOf(dstSub))});
    VkImageCopy region{};
    region.srcSubresource = from->copyLayers(srcSub);
    region.srcOffset = from->copyOffset(srcSub);
    region.dstSubresource = to->copyLayers(dstSub);
    region.dstOffset = to->copyOffset(dstSub);
    region.extent = srcExtent;
    vkCmdCopyImage(m_commands, from->image, VK_IMAGE_LAYOUT_GENERAL, to->image, VK_IMAGE_LAYOUT_GENERAL, 1, &region);
}

// The format's GenerateMips capability (blit source/destination, linear filter) is validated.
void CommandList::generateMipsImpl(const TextureHandle& handle) {
    requireOutsideRenderPass("generateMips()");
    auto* texture = native<Texture>(handle, "generateMips(): the texture", m_context.get());
    const TextureDesc& desc = texture->desc();
    m_keepAlive.keep(handle, texture->keepMark);
    for (uint32_t level = 1; level < desc.mipLevels; ++level) {
        const VkExtent3D from = texture->extent(level - 1), to = texture->extent(level);
        VkImageBlit blit{};
        blit.srcSubresource = {texture->aspect, level - 1, 0, texture->arrayLayers()};
        blit.srcOffsets[1] = {int32_t(from.width), int32_t(from.height), int32_t(from.depth)};
        blit.dstSubresource = {texture->aspect, level, 0, texture->arrayLayers()};
        blit.dstOffsets[1] = {int32_t(to.width), int32_t(to.height), int32_t(to.depth)};
        // Each level reads the one written just before: a barrier per level.
        access({transferRead(*texture, mipKeys(level - 1)), transferWrite(*texture, mipKeys(level))});
        vkCmdBlitImage(m_commands, texture->image, VK_IMAGE_LAYOUT_GENERAL, texture->image, VK_IMAGE_LAYOUT_GENERAL, 1,
                       &blit, VK_FILTER_LINEAR);
    }
}

CommandList::TimerUse& CommandList::timerUse(const TimerQueryHandle& handle) {
    auto* timer = native<TimerQuery>(handle, "the timer", m_context.get());
    for (TimerUse& use : m_timers)
        if (use.timer.get() == timer) return use;
    m_timers.push_back({std::shared_ptr<TimerQuery>(handle, timer)});
    return m_timers.back();
}

void CommandList::beginTimer(const TimerQueryHandle& timer) {
    requireRecording("beginTimer()");
    TimerUse& use = timerUse(timer);
    if (use.began)
        throw Error(ErrorCode::InvalidUsage,
                    "beginTimer(): this timer was already begun in this command list; use one timer per measurement");
    use.began = true;
    vkCmdWriteTimestamp(m_commands, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, use.timer->pool, 0);
}

void CommandList::endTimer(const TimerQueryHandle& timer) {
    requireRecording("endTimer()");
    TimerUse& use = timerUse(timer);
    if (!use.began || use.ended)
        throw Error(ErrorCode::InvalidUsage, use.ended ? "endTimer(): this timer was already ended in this command list"
                                                       : "endTimer(): call beginTimer() on this timer first");
    use.ended = true;
    vkCmdWriteTimestamp(m_commands, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, use.timer->pool, 1);
}

void CommandList::pushDebugGroup(std::string_view name) {
    requireRecording("pushDebugGroup()");
    ++m_debugGroupDepth;
    if (!m_context->cmdBeginDebugLabel) return;
    const std::string label(name);
    VkDebugUtilsLabelEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
    info.pLabelName = label.c_str();
    m_context->cmdBeginDebugLabel(m_commands, &info);
}

void CommandList::omitNextBarrierForTesting() {
    requireRecording("omitNextBarrierForTesting()");
    m_hazards.omitNextBarrier();
}

void CommandList::popDebugGroup() {
    requireRecording("popDebugGroup()");
    if (m_debugGroupDepth == 0)
        throw Error(ErrorCode::InvalidUsage, "popDebugGroup(): no debug group is open; call pushDebugGroup() first");
    --m_debugGroupDepth;
    if (m_context->cmdEndDebugLabel) m_context->cmdEndDebugLabel(m_commands);
}

}  // namespace janus::rhi::vulkan
