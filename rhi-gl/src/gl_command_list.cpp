// Command lists record plain command structs (validated as they are recorded, so errors point
// at the call that caused them) and replay them on execute(). The objects the commands name are
// held by the list's keep-alive, once per recording, until a later recording ends without them
// or the list is destroyed.
#include <fmt/format.h>

#include <algorithm>
#include <typeinfo>

#include "gl_device.h"
#include "janus/rhi/index_value_validation.h"

namespace janus::rhi::gl {

namespace {
// Out of line and cold: formatting a message inside cast() would give every per-call path that
// uses it (setBindingSet, setPipeline, ...) a larger stack frame and more registers to save.
[[noreturn, gnu::cold, gnu::noinline]] void throwForeignHandle(const char* what, const char* kind) {
    throw Error(ErrorCode::InvalidUsage, fmt::format("{}: the {} is null or comes from another backend", what, kind));
}
[[noreturn, gnu::cold, gnu::noinline]] void throwOtherDevice(const char* what, const char* kind) {
    throw Error(ErrorCode::InvalidUsage,
                fmt::format("{}: the {} was created by another device; use resources of this device", what, kind));
}

// The backend object behind a handle. T is final, so comparing the dynamic type is the whole
// check dynamic_cast would make, without its walk of the class hierarchy (this runs per command).
template <typename T, typename Handle>
T* cast(const Context& context, const Handle& handle, const char* what, const char* kind) {
    static_assert(std::is_final_v<T>);
    if (!handle || typeid(*handle) != typeid(T)) [[unlikely]]
        throwForeignHandle(what, kind);
    T* result = static_cast<T*>(handle.get());
    if constexpr (requires { result->owner(); }) {
        // GL names mean nothing in another context.
        if (result->owner() != &context) [[unlikely]]
            throwOtherDevice(what, kind);
    }
    return result;
}

// glMemoryBarrier bits for a shader reading (or writing) a binding.
GLbitfield shaderAccessBarrier(ResourceType type) {
    switch (type) {
        case ResourceType::UniformBuffer: return GL_UNIFORM_BARRIER_BIT;
        case ResourceType::StorageBuffer: return GL_SHADER_STORAGE_BARRIER_BIT;
        case ResourceType::SampledTexture: return GL_TEXTURE_FETCH_BARRIER_BIT;
        case ResourceType::StorageImage: return GL_SHADER_IMAGE_ACCESS_BARRIER_BIT;
    }
    return kEveryMemoryBarrierBit;
}

// Whether a shader may write through a binding of this type; the pipeline's shaders narrow it
// (ShaderBinding::written: a `readonly` storage binding is only read).
bool isShaderWrite(ResourceType type) {
    return type == ResourceType::StorageBuffer || type == ResourceType::StorageImage;
}

// Notes in `found` the kinds of binding `item` is (storage write, sampled texture, any texture);
// `access` is how the pipeline's shaders use it.
void addKinds(UsedBindings& found, const BindingItem& item, const ShaderAccess& access) {
    found.writesStorage = found.writesStorage || access.write;
    found.samplesTextures = found.samplesTextures || item.type == ResourceType::SampledTexture;
    found.usesTextures = found.usesTextures || item.texture;
}

// The bytes a buffer binding shows.
std::pair<uint64_t, uint64_t> boundRange(const BindingItem& item) {
    const uint64_t end = item.range ? item.offset + item.range : item.buffer->desc().size;
    return {item.offset, end};
}

// The layout of the vertex buffer slot `attribute` reads (validated: the pipeline declares one).
const VertexBufferLayout& layoutOf(const GraphicsPipelineDesc& desc, const VertexAttribute& attribute) {
    return *std::find_if(desc.vertexBuffers.begin(), desc.vertexBuffers.end(),
                         [&](const VertexBufferLayout& l) { return l.slot == attribute.bufferSlot; });
}
}  // namespace

BindingSet::BindingSet(const Context& owner, const BindingSetDesc& desc)
    : m_owner(&owner), m_desc(desc), m_dynamicWindows(dynamicWindowsOf(desc)) {
    for (const BindingItem& item : m_desc.items) {
        m_replay.bindingPoints |= bindingPointBit(item.binding);
        const GLbitfield needs = shaderAccessBarrier(item.type);
        const bool write = isShaderWrite(item.type);
        if (!item.buffer) {
            m_replay.hasTextures = true;
            m_itemAccesses.push_back({item.texture.get(), 0, UINT64_MAX, needs, write});
            continue;
        }
        // Items are validated: the buffer is this device's and the range lies inside it.
        const auto [begin, end] = boundRange(item);
        // A dynamic window may be anywhere from the item's offset on: its access is all of that,
        // wider than one bind's window, so a barrier may be added but none missed.
        m_itemAccesses.push_back({item.buffer.get(), begin, item.dynamicOffset ? item.buffer->desc().size : end,
                                  needs, write});
        m_bufferRanges.push_back({GLintptr(begin), GLsizeiptr(end - begin),
                                  static_cast<const Buffer*>(item.buffer.get())->name(), item.binding,
                                  item.type == ResourceType::UniformBuffer ? GLenum(GL_UNIFORM_BUFFER)
                                                                           : GLenum(GL_SHADER_STORAGE_BUFFER)});
        if (item.dynamicOffset)
            m_bufferRanges.back().dynamicSlot = m_dynamicWindows.slotOf(uint32_t(&item - m_desc.items.data()));
    }
    // A set with dynamic offsets binds from bufferRanges() (BindDynamicSet): never an inline range.
    if (m_bufferRanges.size() == 1 && m_dynamicWindows.count == 0) {
        const BufferRange& only = m_bufferRanges[0];
        // Always true for a validated item (GL buffers are at most 2^31 bytes, bindings < 64);
        // checked so that a larger limit one day binds from the vector instead of truncating.
        if (uint64_t(only.offset) <= UINT32_MAX && uint64_t(only.size) <= UINT32_MAX && only.index < 64) {
            m_replay.range.offset = uint32_t(only.offset);
            m_replay.range.size = uint32_t(only.size);
            m_replay.range.buffer = only.buffer;
            m_replay.range.index = uint8_t(only.index);
            m_replay.range.storage = only.target == GL_SHADER_STORAGE_BUFFER;
            m_replay.inlineRange = true;
        }
    }
    // Then bindingPoints is bindingPointBit(range.index), which replay of the copy works out.
    m_replay.range.plain = m_replay.inlineRange && !m_replay.hasTextures;   // its only item then
}

void BindingSet::noteLastValidated(const Validated* check) const {
    m_lastValidated.store(check, std::memory_order_release);
    // Checks are never removed nor changed, so a plain one stays true for its key: the key stays
    // until another plain check replaces it.
    if (!check->found.usesTextures && !check->found.writesStorage)
        m_lastPlainCheck.store(checkKey(check->signature, check->set), std::memory_order_relaxed);
}

const BindingSet::Validated* BindingSet::findValidated(uint64_t signature, uint32_t set) const {
    const std::lock_guard lock(m_validatedMutex);
    for (const std::unique_ptr<Validated>& check : m_validated)
        if (check->signature == signature && check->set == set) {
            noteLastValidated(check.get());
            return check.get();
        }
    return nullptr;
}

const BindingSet::Validated* BindingSet::addValidated(std::unique_ptr<Validated> check) const {
    const std::lock_guard lock(m_validatedMutex);
    for (const std::unique_ptr<Validated>& existing : m_validated)
        if (existing->signature == check->signature && existing->set == check->set) return existing.get();   // another list's
    m_validated.push_back(std::move(check));
    noteLastValidated(m_validated.back().get());
    return m_validated.back().get();
}

// ---------------------------------------------------------------------------------------------
// Recording

void CommandList::throwNotRecording(const char* what) const {
    throw Error(ErrorCode::InvalidUsage, fmt::format("{} was called outside begin()/end() of the command list", what));
}

void CommandList::throwWrongPassState(const char* what) const {
    requireRecording(what);
    if (m_inRenderPass)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("{} is not allowed inside a render pass; call endRenderPass() first", what));
    throw Error(ErrorCode::InvalidUsage, fmt::format("{} needs an active render pass; call beginRenderPass() first", what));
}

void CommandList::beginImpl() {
    m_keepAlive.beginRecording();
    m_commandCount = 0;   // m_commands keeps its size: the storage is reused
    // So do the pass descriptions (no allocation per pass once seen); their textures are let go.
    for (size_t i = 0; i < m_renderPassCount; ++i) {
        m_renderPasses[i].colors.clear();
        m_renderPasses[i].depth.reset();
    }
    m_renderPassCount = 0;
    m_uploads.clear();
    m_labels.clear();
    m_mipRanges.clear();
    m_pendingWrites.clear();
    m_recording = true;
    m_recorded = false;
    m_inRenderPass = false;
    invalidateDrawState();
    m_pipeline = nullptr;
    m_bindingSets = {};
    setFound({});
    m_usedStorage.clear();
    m_accessStorage.clear();
    m_vertexBuffers.clear();
    m_indexBuffer = nullptr;
    m_indexOffset = 0;
    m_passColorFormats.clear();
    m_passDepthFormat = Format::Unknown;
    m_passSampleCount = 1;
    m_debugGroupDepth = 0;
    m_timers.clear();
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
    if (desc.sampleCount != m_passSampleCount)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("{}: pipeline '{}' renders with {} sample(s) but the render pass's attachments have {}; "
                                "set GraphicsPipelineDesc::sampleCount to the attachments' TextureDesc::sampleCount",
                                what, desc.debugName, desc.sampleCount, m_passSampleCount));
}

void CommandList::requireBindingsCached(const char* what) {
    const Pipeline& pipeline = *m_pipeline;
    const std::span<const uint32_t> sets = pipeline.usedSets();
    if (pipeline.cacheableBindings() && !sets.empty()) {
        std::array<const BindingSet::Validated*, kMaxBindingSets> checks{};
        bool all = true;
        for (const uint32_t index : sets) {
            const BindingSet* set = m_bindingSets[index];
            checks[index] = set ? set->validated(pipeline.bindingSignature(), index) : nullptr;
            all = all && checks[index];
        }
        if (all && sets.size() == 1) {
            setFound(checks[sets[0]]->found);
            if (m_found.usesTextures) requireTextureUses(what);
            return;
        }
        if (all) {
            // Each check lists its set's items in the pipeline's order: interleave them back.
            std::array<size_t, kMaxBindingSets> next{};
            m_usedStorage.clear();
            m_accessStorage.clear();
            setFound({});
            for (const ShaderBinding& binding : pipeline.bindings()) {
                const BindingSet::Validated& check = *checks[binding.set];
                const size_t i = next[binding.set]++;
                m_usedStorage.push_back(check.used[i]);
                m_accessStorage.push_back(check.accesses[i]);
                addKinds(m_found, *check.used[i].item, check.accesses[i]);
            }
            m_found.used = m_usedStorage;
            m_found.accesses = m_accessStorage;
            if (m_found.usesTextures) requireTextureUses(what);
            return;
        }
    }
    requireBindingsUncached(what);
}

void CommandList::requireBindingsUncached(const char* what) {
    // GL would silently read whatever is bound at a unit; Vulkan's validation would flag the
    // same mistake, so catch it here with the binding named.
    m_usedStorage.clear();
    m_accessStorage.clear();
    setFound({});
    for (const ShaderBinding& binding : m_pipeline->bindings()) {
        const BindingItem* found = nullptr;
        const BindingSet* set = binding.set < kMaxBindingSets ? m_bindingSets[binding.set] : nullptr;
        if (set) {
            for (const BindingItem& item : set->desc().items)
                if (item.binding == binding.binding) found = &item;
        }
        if (!found)
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("{}: the pipeline's shaders use set {} binding {} ({}), but the binding set "
                                    "given to setBindingSet({}, ...) has no item for it (or none was set)",
                                    what, binding.set, binding.binding, binding.glName, binding.set));
        if (found->type == ResourceType::UniformBuffer && binding.type == ResourceType::UniformBuffer)
            requireDynamicAgreement(*found, binding.dynamicOffset, m_pipeline->debugName(),
                                    fmt::format("{}: set {} binding {} ({})", what, binding.set, binding.binding,
                                                binding.glName));
        if (found->type != binding.type)
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("{}: binding {} is a different resource type in the binding set than in the "
                                    "shader ({})",
                                    what, binding.binding, binding.glName));
        m_usedStorage.push_back({binding.set, found});
        ShaderAccess access = set->itemAccess(size_t(found - set->desc().items.data()));
        access.write = access.write && binding.written;
        m_accessStorage.push_back(access);
        addKinds(m_found, *found, access);
        const auto where = [&] {
            return fmt::format("{}: set {} binding {} ({})", what, binding.set, binding.binding, binding.glName);
        };
        requireBufferCoversBlock(*found, binding.blockSize, where);
        if (!found->texture) continue;
        const TextureDimension viewed = found->viewDimension.value_or(found->texture->desc().dimension);
        if (binding.dimension && viewed != *binding.dimension)
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("{}: binding {} views {} texture '{}' as {} but the shader declares a {} one; match "
                                    "the shader's type or set BindingItem::viewDimension",
                                    what, binding.binding, toString(found->texture->desc().dimension),
                                    found->texture->desc().debugName, toString(viewed), toString(*binding.dimension)));
        requireSamplerMatchesShader(*found, binding.depthCompare, where);
        requireStorageFormatMatchesShader(*found, binding.imageFormat, where);
    }
    m_found.used = m_usedStorage;
    m_found.accesses = m_accessStorage;
    if (m_pipeline->cacheableBindings()) {
        // Every binding found its item: keep each set's part for the next check with this set.
        for (const uint32_t index : m_pipeline->usedSets()) {
            auto check = std::make_unique<BindingSet::Validated>();
            check->signature = m_pipeline->bindingSignature();
            check->set = index;
            for (size_t i = 0; i < m_usedStorage.size(); ++i) {
                if (m_usedStorage[i].set != index) continue;
                check->used.push_back(m_usedStorage[i]);
                check->accesses.push_back(m_accessStorage[i]);
                addKinds(check->found, *m_usedStorage[i].item, m_accessStorage[i]);
            }
            check->found.used = check->used;
            check->found.accesses = check->accesses;
            const BindingSet::Validated* kept = m_bindingSets[index]->addValidated(std::move(check));
            if (m_pipeline->usedSets().size() == 1) {
                // The list's spans may as well point at the kept check (the set outlives them).
                m_found.used = kept->found.used;
                m_found.accesses = kept->found.accesses;
            }
        }
    }
    if (m_found.usesTextures) requireTextureUses(what);
}

// The check bindRecordedSet took as passed: kept in the set for good (checks are never removed).
void CommandList::fetchFound() {
    const FoundInCheck from = m_foundInCheck;
    const BindingSet::Validated* check = from.set->validated(from.signature, from.index);
    if (!check) [[unlikely]]
        throw Error(ErrorCode::InvalidUsage, "internal: a binding set lost the binding check it passed; please report this");
    setFound(check->found);
}

void CommandList::requireTextureUses(const char* what) const {
    const std::span<const UsedBinding> used = m_found.used;
    validateViewOverlaps(used, openPass(), what);
    if (m_es) {
        // Mip ranges are texture state on ES (BASE/MAX_LEVEL): one range per texture per draw.
        for (size_t i = 0; i < used.size(); ++i)
            for (size_t j = 0; j < i; ++j) {
                const BindingItem& a = *used[i].item;
                const BindingItem& b = *used[j].item;
                if (!a.texture || a.texture != b.texture || a.type != ResourceType::SampledTexture ||
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
}

void CommandList::recordMipRanges() {
    if (!m_es) return;   // desktop GL binds texture views instead
    const auto first = uint32_t(m_mipRanges.size());
    for (const UsedBinding& used : found().used) {
        if (used.item->type != ResourceType::SampledTexture) continue;
        const ResolvedTextureView view = resolveTextureView(*used.item);
        // The binding set, held by the keep-alive, holds the texture.
        m_mipRanges.push_back({static_cast<const Texture*>(used.item->texture.get()), used.item->binding, view.baseMip,
                               view.mipCount});
    }
    if (m_mipRanges.size() > first) record(command::ApplyMipRanges{first, uint32_t(m_mipRanges.size()) - first});
}

// OpenGL ES 3.0 has no base vertex: replay moves each per-vertex attribute pointer by vertexOffset
// vertices instead (Device::specifyVertexAttributes), and GL takes a pointer as an offset into the
// buffer, which cannot be negative. Before this check such a draw read garbage without an error.
void CommandList::requireVertexOffsetInsideBuffers(int32_t vertexOffset) const {
    const GraphicsPipelineDesc& desc = m_pipeline->graphics();
    for (const VertexAttribute& attribute : desc.vertexAttributes) {
        const VertexBufferLayout& layout = layoutOf(desc, attribute);
        if (layout.perInstance) continue;
        const uint64_t offset = boundVertexBuffer(attribute.bufferSlot).offset;
        const int64_t before = -(int64_t(offset) + int64_t(attribute.offset) + int64_t(vertexOffset) * int64_t(layout.stride));
        if (before <= 0) continue;
        throw Error(ErrorCode::UnsupportedCapability,
                    fmt::format("drawIndexed: vertexOffset {} moves vertex buffer slot {} (bound at offset {}, stride {}) {} "
                                "bytes before its start; OpenGL ES 3.0 has no base vertex, so the gles backend moves the "
                                "attribute pointers by vertexOffset instead, and a pointer cannot go before its buffer. "
                                "Add vertexOffset to the indices, or bind the vertices at an offset at least {} bytes "
                                "larger with a vertexOffset that reaches them",
                                vertexOffset, attribute.bufferSlot, offset, layout.stride, before, before));
    }
}

void CommandList::requireVertexBuffers(const char* what) const {
    for (const VertexAttribute& attribute : m_pipeline->graphics().vertexAttributes) {
        const bool set = std::any_of(m_vertexBuffers.begin(), m_vertexBuffers.end(),
                                     [&](const RecordedVertexBuffer& b) { return b.slot == attribute.bufferSlot; });
        if (!set)
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("{}: the pipeline reads vertex buffer slot {}, but no buffer was set there; call "
                                    "setVertexBuffer({}, ...) first",
                                    what, attribute.bufferSlot, attribute.bufferSlot));
    }
}

// requireDrawState: each check passed with the same inputs before, unless they changed since:
// same errors, at the first draw that would have reported them, in the same order.
void CommandList::requirePipelineState(const char* what) {
    requireVertexBuffers(what);
    requireCompatiblePipeline(what);
    m_drawLimits = drawRangeLimits(m_pipeline->graphics(), [this](uint32_t slot) { return boundVertexBuffer(slot); });
    m_pipelineChecked = true;
}

BoundVertexBuffer CommandList::boundVertexBuffer(uint32_t slot) const {
    for (const RecordedVertexBuffer& b : m_vertexBuffers)
        if (b.slot == slot) return {b.buffer, b.offset};
    return {};   // not reached for a slot the pipeline reads: requireVertexBuffers found each
}

void CommandList::throwDrawOutOfRange(const DrawRange& range, bool indexed) const {
    rhi::throwDrawOutOfRange(range, m_pipeline->graphics(), [this](uint32_t slot) { return boundVertexBuffer(slot); },
                             indexed ? m_indexBuffer : nullptr, m_indexOffset, m_indexType);
}

void CommandList::recordBarrier(GLbitfield bits) {
    if (!bits) return;   // nothing to wait for
    m_drawReady = false;
    record(command::MemoryBarrier{bits});
    // The barrier orders every earlier write for the accesses it names.
    std::erase_if(m_pendingWrites, [bits](PendingWrite& write) {
        write.unsynchronized &= ~bits;
        return write.unsynchronized == 0;
    });
}

void CommandList::trackPendingShaderAccesses(bool drawing, bool indexed) {
    if (!m_pendingWrites.empty()) {
        GLbitfield needed = 0;
        for (const ShaderAccess& access : found().accesses) needed |= hazardBits(access.resource, access.begin, access.end, access.needs);
        if (drawing) {
            for (const RecordedVertexBuffer& vertices : m_vertexBuffers)
                needed |= bufferHazard(vertices.buffer, vertices.offset, UINT64_MAX, GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT);
            if (indexed) needed |= bufferHazard(m_indexBuffer, m_indexOffset, UINT64_MAX, GL_ELEMENT_ARRAY_BARRIER_BIT);
        }
        recordBarrier(needed);
    }
    if (!found().writesStorage) return;
    for (const ShaderAccess& access : m_found.accesses)
        if (access.write) addPendingWrite(access.resource, access.begin, access.end);
}

void CommandList::end() {
    requireRecording("end()");
    if (m_inRenderPass) throw Error(ErrorCode::InvalidUsage, "end() was called inside a render pass; call endRenderPass() first");
    if (m_debugGroupDepth != 0)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("end() was called with {} debug group(s) still open; pop them first", m_debugGroupDepth));
    // Whatever comes after the list (the host mapping or reading a buffer, another list) may
    // read what its shaders wrote: nothing stays pending past execute().
    GLbitfield pending = 0;
    for (const PendingWrite& write : m_pendingWrites) pending |= write.unsynchronized;
    recordBarrier(pending);
    m_keepAlive.releaseUnused();
    m_drawReady = false;
    m_recording = false;
    m_recorded = true;
}

// `desc` is validated (rhi/src/validation.cpp); the attachments must still be this device's.
void CommandList::beginRenderPassImpl(const RenderPassDesc& desc) {
    requireOutsideRenderPass("beginRenderPass");
    bool resolves = false;
    for (const Attachment& a : desc.colors) {
        cast<Texture>(*m_context, a.texture, "beginRenderPass", "attachment texture");
        if (a.resolveTexture) cast<Texture>(*m_context, a.resolveTexture, "beginRenderPass", "resolve texture");
        resolves = resolves || a.resolveTexture;
    }
    if (desc.depth) cast<Texture>(*m_context, desc.depth->texture, "beginRenderPass", "attachment texture");
    GLbitfield needed = 0;
    for (const Attachment& a : desc.colors) {
        needed |= textureHazard(a.texture.get(), GL_FRAMEBUFFER_BARRIER_BIT);
        // The resolve writes it through a framebuffer (a blit) at the pass's end.
        if (a.resolveTexture) needed |= textureHazard(a.resolveTexture.get(), GL_FRAMEBUFFER_BARRIER_BIT);
    }
    if (desc.depth) needed |= textureHazard(desc.depth->texture.get(), GL_FRAMEBUFFER_BARRIER_BIT);
    recordBarrier(needed);
    m_inRenderPass = true;
    invalidateDrawState();   // new attachments to match and not to sample
    // The stored description holds the attachments.
    if (m_renderPassCount == m_renderPasses.size()) m_renderPasses.emplace_back();
    RenderPassDesc& stored = m_renderPasses[m_renderPassCount++];
    stored.colors.assign(desc.colors.begin(), desc.colors.end());
    stored.depth = desc.depth;
    m_passColorFormats.clear();
    for (const Attachment& a : desc.colors) m_passColorFormats.push_back(a.texture->desc().format);
    m_passDepthFormat = desc.depth ? desc.depth->texture->desc().format : Format::Unknown;
    m_passSampleCount = (desc.depth ? desc.depth->texture : desc.colors[0].texture)->desc().sampleCount;
    m_passResolves = resolves;
    record(command::BeginRenderPass{uint32_t(m_renderPassCount - 1)});
}

void CommandList::endRenderPass() {
    requireInsideRenderPass("endRenderPass");
    if (m_passResolves) record(command::ResolveRenderPass{uint32_t(m_renderPassCount - 1)});
    m_inRenderPass = false;
    invalidateDrawState();
}

// Values validated by the front (rhi/src/validation.cpp).
void CommandList::setViewportImpl(const Viewport& viewport) {
    requireInsideRenderPass("setViewport");
    record(command::SetViewport{viewport});
}

void CommandList::setScissorImpl(const ScissorRect& scissor) {
    requireInsideRenderPass("setScissor");
    record(command::SetScissor{scissor});
}

void CommandList::setPipeline(const PipelineHandle& handle) {
    requireRecording("setPipeline");
    Pipeline* pipeline = cast<Pipeline>(*m_context, handle, "setPipeline", "pipeline");
    if (pipeline->isCompute() && m_inRenderPass)
        throw Error(ErrorCode::InvalidUsage, "setPipeline: a compute pipeline cannot be set inside a render pass");
    m_keepAlive.keep(handle, pipeline->keepMark);
    if (pipeline == m_pipeline) return;   // replay would bind the same program again
    m_pipeline = pipeline;
    invalidateDrawState();
    record(command::BindPipeline{pipeline});
}

// The common case, a set of this device that the list already holds, with room for the command,
// in a function that calls nothing (its registers need no saving); anything else, and every error,
// takes the general path. The front checked `set` and that the handle is not null.
void CommandList::setBindingSetImpl(uint32_t set, const BindingSetHandle& handle) {
    // A set the list holds passed cast()'s checks (its type, and the device that made it is this
    // list's) when the list first held it, so not even its type is checked again.
    if (!m_recording || m_commandCount == m_commandCapacity || !m_keepAlive.keepIfHeld(keepMarkOf(*handle))) [[unlikely]]
        return setBindingSetGeneral(set, handle);
    bindRecordedSet(set, static_cast<BindingSet*>(handle.get()));
}

// A set with dynamic uniform buffers: recorded with its offsets, and never merged with a draw.
// The same set at other offsets changes nothing a draw checks (its accesses cover every window).
void CommandList::setBindingSetImpl(uint32_t set, const BindingSetHandle& handle,
                                    std::span<const uint32_t> dynamicOffsets) {   // count and alignment checked
    BindingSet* bindings = nullptr;
    // A set the list holds passed cast()'s checks when the list first held it (as in the first form).
    if (m_recording && m_keepAlive.keepIfHeld(keepMarkOf(*handle))) [[likely]] {
        bindings = static_cast<BindingSet*>(handle.get());
    } else {
        requireRecording("setBindingSet");
        bindings = cast<BindingSet>(*m_context, handle, "setBindingSet", "binding set");
        m_keepAlive.keep(handle, keepMarkOf(*bindings));
    }
    command::BindDynamicSet bind{set, bindings, {}};
    takeDynamicOffsets(*bindings, bindings->dynamicWindows(), dynamicOffsets, bind.offsets);
    record(bind);
    if (m_bindingSets[set] == bindings) return;
    m_bindingSets[set] = bindings;
    m_bindingsChecked = false;
    m_drawReady = false;
}

void CommandList::setBindingSetGeneral(uint32_t set, const BindingSetHandle& handle) {
    requireRecording("setBindingSet");
    BindingSet* bindings = cast<BindingSet>(*m_context, handle, "setBindingSet", "binding set");
    m_keepAlive.keep(handle, keepMarkOf(*bindings));
    if (m_commandCount == m_commandCapacity) growCommands();
    bindRecordedSet(set, bindings);
}

inline void CommandList::bindRecordedSet(uint32_t set, BindingSet* bindings) {
    m_bindingSets[set] = bindings;
    recordWithRoom(command::BindBindingSet{set, bindings});
    // The set the pipeline's bindings all use, with a cached check for them, no texture (whose
    // checks depend on the pass) and no storage write (tracked per draw or dispatch): the check
    // at the next draw or dispatch would take this result, so take it now. It cannot fail, and
    // nothing but the pipeline, the sets and the pass (each of which clears it) changes it
    // before then.
    if (const Pipeline* pipeline = m_pipeline;
        pipeline && pipeline->singleSet() == set && bindings->passedPlainCheck(pipeline->bindingSignature(), set)) {
        // A ready draw stays ready: nothing it depends on besides the items changed. What the
        // check found is fetched only if something reads it (found()).
        m_foundInCheck = {bindings, pipeline->bindingSignature(), set};
        m_bindingsChecked = true;
        return;
    }
    m_bindingsChecked = false;
    m_drawReady = false;
}

// Usage, offset and slot validated by the front (rhi/src/validation.cpp).
void CommandList::setVertexBufferImpl(uint32_t slot, const BufferHandle& handle, uint64_t offset) {
    requireRecording("setVertexBuffer");
    Buffer* buffer = cast<Buffer>(*m_context, handle, "setVertexBuffer", "buffer");
    auto existing = std::find_if(m_vertexBuffers.begin(), m_vertexBuffers.end(),
                                 [&](const RecordedVertexBuffer& b) { return b.slot == slot; });
    // Already bound in this recording (and kept): nothing to record, and a ready draw stays
    // ready, as on Vulkan.
    if (existing != m_vertexBuffers.end() && existing->buffer == buffer && existing->offset == offset) return;
    m_keepAlive.keep(handle, buffer->keepMark);
    if (existing != m_vertexBuffers.end())
        *existing = {slot, buffer, offset};
    else
        m_vertexBuffers.push_back({slot, buffer, offset});
    m_pipelineChecked = false;
    m_drawReady = false;
    record(command::SetVertexBuffer{slot, buffer->name(), offset});
}

// Type, usage and offset validated by the front (rhi/src/validation.cpp).
void CommandList::setIndexBufferImpl(const BufferHandle& handle, IndexType type, uint64_t offset) {
    requireRecording("setIndexBuffer");
    Buffer* buffer = cast<Buffer>(*m_context, handle, "setIndexBuffer", "buffer");
    if (m_indexBuffer == buffer && m_indexOffset == offset && m_indexType == type) return;   // already bound
    m_keepAlive.keep(handle, buffer->keepMark);
    m_indexBuffer = buffer;
    m_indexOffset = offset;
    m_indexType = type;
    m_indexLimit = indexCountLimit(*buffer, offset, type);
    record(command::SetIndexBuffer{buffer->name(), type, offset});
}

// A draw whose state is ready (see invalidateDrawState) is only recorded: every check below would
// pass and the tracking do nothing. Anything else takes the checked path, which is the whole of
// what draw did before.
void CommandList::draw(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex, uint32_t firstInstance) {
    if (!m_drawReady || m_drawLimits.exceeded(firstVertex, vertexCount, firstInstance, instanceCount)) [[unlikely]]
        return drawChecked(vertexCount, instanceCount, firstVertex, firstInstance);
    recordDraw(command::Draw{vertexCount, instanceCount, firstVertex, firstInstance});
}

void CommandList::drawChecked(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex, uint32_t firstInstance) {
    requireInsideRenderPass("draw");
    if (!m_pipeline || m_pipeline->isCompute())
        throw Error(ErrorCode::InvalidUsage, "draw: no graphics pipeline is set; call setPipeline() first");
    requireDrawState("draw");
    if (m_drawLimits.exceeded(firstVertex, vertexCount, firstInstance, instanceCount))
        throwDrawOutOfRange({"draw", firstVertex, vertexCount, firstInstance, instanceCount}, false);
    trackShaderAccesses(true, false);
    recordDraw(command::Draw{vertexCount, instanceCount, firstVertex, firstInstance});
    m_drawReady = m_pendingWrites.empty() && !found().writesStorage;
}

void CommandList::drawIndexed(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex, int32_t vertexOffset,
                                uint32_t firstInstance) {
    // A negative vertexOffset takes the checked path: ES checks where it moves the attribute pointers.
    if (!m_drawReady || !m_indexBuffer || vertexOffset < 0 || indexValueLog() ||
        indexedDrawExceeds(m_drawLimits, m_indexLimit, firstIndex, indexCount, firstInstance, instanceCount)) [[unlikely]]
        return drawIndexedChecked(indexCount, instanceCount, firstIndex, vertexOffset, firstInstance);
    recordDraw(command::DrawIndexed{indexCount, instanceCount, firstIndex, vertexOffset, firstInstance});
}

void CommandList::drawIndexedChecked(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex,
                                     int32_t vertexOffset, uint32_t firstInstance) {
    requireInsideRenderPass("drawIndexed");
    if (!m_pipeline || m_pipeline->isCompute())
        throw Error(ErrorCode::InvalidUsage, "drawIndexed: no graphics pipeline is set; call setPipeline() first");
    requireDrawState("drawIndexed");
    if (!m_indexBuffer)
        throw Error(ErrorCode::InvalidUsage, "drawIndexed: no index buffer is set; call setIndexBuffer() first");
    if (indexedDrawExceeds(m_drawLimits, m_indexLimit, firstIndex, indexCount, firstInstance, instanceCount))
        throwDrawOutOfRange({"drawIndexed", firstIndex, indexCount, firstInstance, instanceCount}, true);
    if (m_es && vertexOffset < 0) requireVertexOffsetInsideBuffers(vertexOffset);
    if (detail::IndexValueLog* log = indexValueLog())
        log->noteIndexedDraw(*m_indexBuffer, m_indexOffset, m_indexType, firstIndex, indexCount, vertexOffset,
                             vertexLimit(m_pipeline->graphics(), [this](uint32_t slot) { return boundVertexBuffer(slot); }));
    trackShaderAccesses(true, true);
    recordDraw(command::DrawIndexed{indexCount, instanceCount, firstIndex, vertexOffset, firstInstance});
    m_drawReady = m_pendingWrites.empty() && !found().writesStorage;
}

void CommandList::dispatchImpl(uint32_t groupsX, uint32_t groupsY, uint32_t groupsZ) {   // Compute; counts in limits
    requireOutsideRenderPass("dispatch");
    if (!m_pipeline || !m_pipeline->isCompute())
        throw Error(ErrorCode::InvalidUsage, "dispatch: no compute pipeline is set; call setPipeline() first");
    if (!m_bindingsChecked) {
        requireBindings("dispatch");
        m_bindingsChecked = true;
    }
    trackShaderAccesses(false, false);
    record(command::Dispatch{groupsX, groupsY, groupsZ});
}

// Transfers: arguments are validated (rhi/src/validation.cpp); ranges and subresources exist.
// Each waits for shader writes to what it touches, with the bits for how GL touches it.
void CommandList::writeBufferImpl(const BufferHandle& handle, const void* data, uint64_t size, uint64_t dstOffset) {
    requireOutsideRenderPass("writeBuffer");
    Buffer* buffer = cast<Buffer>(*m_context, handle, "writeBuffer", "buffer");
    m_keepAlive.keep(handle, buffer->keepMark);
    recordBarrier(bufferHazard(buffer, dstOffset, dstOffset + size, GL_BUFFER_UPDATE_BARRIER_BIT));
    // The data is copied now: the caller's memory need not outlive the call.
    const uint64_t at = m_uploads.size();
    const auto* bytes = static_cast<const std::byte*>(data);
    m_uploads.insert(m_uploads.end(), bytes, bytes + size);
    record(command::WriteBuffer{buffer, at, size, dstOffset});
}

void CommandList::copyBufferImpl(const BufferHandle& dstHandle, uint64_t dstOffset, const BufferHandle& srcHandle,
                                 uint64_t srcOffset, uint64_t size) {
    requireOutsideRenderPass("copyBuffer");
    Buffer* dst = cast<Buffer>(*m_context, dstHandle, "copyBuffer", "destination buffer");
    Buffer* src = cast<Buffer>(*m_context, srcHandle, "copyBuffer", "source buffer");
    m_keepAlive.keep(dstHandle, dst->keepMark);
    m_keepAlive.keep(srcHandle, src->keepMark);
    recordBarrier(bufferHazard(dst, dstOffset, dstOffset + size, GL_BUFFER_UPDATE_BARRIER_BIT) |
                  bufferHazard(src, srcOffset, srcOffset + size, GL_BUFFER_UPDATE_BARRIER_BIT));
    record(command::CopyBuffer{dst, src, dstOffset, srcOffset, size});
}

void CommandList::copyBufferToTextureImpl(const TextureHandle& dstHandle, TextureSubresource dstSub,
                                          const BufferHandle& srcHandle, uint64_t srcOffset) {
    requireOutsideRenderPass("copyBufferToTexture");
    Texture* dst = cast<Texture>(*m_context, dstHandle, "copyBufferToTexture", "texture");
    Buffer* src = cast<Buffer>(*m_context, srcHandle, "copyBufferToTexture", "buffer");
    m_keepAlive.keep(dstHandle, dst->keepMark);
    m_keepAlive.keep(srcHandle, src->keepMark);
    recordBarrier(textureHazard(dst, GL_TEXTURE_UPDATE_BARRIER_BIT) |
                  bufferHazard(src, srcOffset, UINT64_MAX, GL_PIXEL_BUFFER_BARRIER_BIT));
    record(command::CopyBufferToTexture{dst, dstSub, src, srcOffset});
}

void CommandList::copyTextureToBufferImpl(const BufferHandle& dstHandle, uint64_t dstOffset,
                                          const TextureHandle& srcHandle, TextureSubresource srcSub) {
    requireOutsideRenderPass("copyTextureToBuffer");
    Buffer* dst = cast<Buffer>(*m_context, dstHandle, "copyTextureToBuffer", "buffer");
    Texture* src = cast<Texture>(*m_context, srcHandle, "copyTextureToBuffer", "texture");
    m_keepAlive.keep(dstHandle, dst->keepMark);
    m_keepAlive.keep(srcHandle, src->keepMark);
    // The texture is read through a framebuffer, glGetTexImage or (ES depth) a draw sampling it:
    // every kind of access.
    recordBarrier(textureHazard(src, kEveryMemoryBarrierBit) |
                  bufferHazard(dst, dstOffset, UINT64_MAX, GL_BUFFER_UPDATE_BARRIER_BIT));
    record(command::CopyTextureToBuffer{dst, dstOffset, src, srcSub});
}

void CommandList::copyTextureImpl(const TextureHandle& dstHandle, TextureSubresource dstSub,
                                  const TextureHandle& srcHandle, TextureSubresource srcSub) {
    requireOutsideRenderPass("copyTexture");
    Texture* dst = cast<Texture>(*m_context, dstHandle, "copyTexture", "destination texture");
    Texture* src = cast<Texture>(*m_context, srcHandle, "copyTexture", "source texture");
    m_keepAlive.keep(dstHandle, dst->keepMark);
    m_keepAlive.keep(srcHandle, src->keepMark);
    // glCopyImageSubData, or on ES a blit between framebuffers.
    constexpr GLbitfield copyBits = GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT;
    recordBarrier(textureHazard(dst, copyBits) | textureHazard(src, copyBits));
    record(command::CopyTexture{dst, dstSub, src, srcSub});
}

// The format's GenerateMips capability (colour-renderable and filterable) is validated.
void CommandList::generateMipsImpl(const TextureHandle& handle) {
    requireOutsideRenderPass("generateMips");
    Texture* texture = cast<Texture>(*m_context, handle, "generateMips", "texture");
    m_keepAlive.keep(handle, texture->keepMark);
    // How the driver reads and writes the levels is its own business.
    recordBarrier(textureHazard(texture, kEveryMemoryBarrierBit));
    record(command::GenerateMips{texture});
}

CommandList::TimerUse& CommandList::timerUse(const TimerQuery* timer) {
    for (TimerUse& use : m_timers)
        if (use.timer == timer) return use;
    return m_timers.emplace_back(TimerUse{timer});
}

void CommandList::beginTimer(const TimerQueryHandle& handle) {
    requireRecording("beginTimer");
    TimerQuery* timer = cast<TimerQuery>(*m_context, handle, "beginTimer", "timer");
    TimerUse& use = timerUse(timer);
    if (use.began)
        throw Error(ErrorCode::InvalidUsage,
                    "beginTimer: this timer was already begun in this command list; use one timer per measurement");
    use.began = true;
    m_keepAlive.keep(handle, timer->keepMark);
    record(command::BeginTimer{timer});
}

void CommandList::endTimer(const TimerQueryHandle& handle) {
    requireRecording("endTimer");
    TimerQuery* timer = cast<TimerQuery>(*m_context, handle, "endTimer", "timer");
    TimerUse& use = timerUse(timer);
    if (!use.began || use.ended)
        throw Error(ErrorCode::InvalidUsage, use.ended ? "endTimer: this timer was already ended in this command list"
                                                       : "endTimer: call beginTimer() on this timer first in this command list");
    use.ended = true;
    m_keepAlive.keep(handle, timer->keepMark);
    record(command::EndTimer{timer});
}

void CommandList::pushDebugGroup(std::string_view name) {
    requireRecording("pushDebugGroup");
    ++m_debugGroupDepth;
    m_labels.emplace_back(name);
    record(command::PushDebugGroup{uint32_t(m_labels.size() - 1)});
}

void CommandList::popDebugGroup() {
    requireRecording("popDebugGroup");
    if (m_debugGroupDepth == 0) throw Error(ErrorCode::InvalidUsage, "popDebugGroup: no debug group is open");
    --m_debugGroupDepth;
    record(command::PopDebugGroup{});
}

// ---------------------------------------------------------------------------------------------
// Replay

void CommandList::replay(Device& device) {
    if (m_recording || !m_recorded)
        throw Error(ErrorCode::InvalidUsage, "execute() needs a command list that was recorded with begin() ... end()");
    const GLFunctions& gl = device.gl();
    struct Replayer {
        CommandList& list;
        Device& device;
        const GLFunctions& gl;
        void operator()(const command::BeginRenderPass& c) { device.beginRenderPass(list.m_renderPasses[c.pass]); }
        void operator()(const command::ResolveRenderPass& c) { device.resolveRenderPass(list.m_renderPasses[c.pass]); }
        void operator()(const command::SetViewport& c) {
            // GL's window origin is row 0 as well, so y needs no flip.
            const Viewport& v = c.viewport;
            gl.glViewport(GLint(v.x), GLint(v.y), GLsizei(v.width), GLsizei(v.height));
            device.context().state.setDepthRange(v.minDepth, v.maxDepth);
        }
        void operator()(const command::SetScissor& c) {
            gl.glScissor(c.scissor.x, c.scissor.y, GLsizei(c.scissor.width), GLsizei(c.scissor.height));
        }
        void operator()(const command::BindPipeline& c) { device.bindPipeline(*c.pipeline); }
        void operator()(const command::BindBindingSet& c) { device.bindBindingSet(c.set, *c.bindings); }
        void operator()(const command::BindDynamicSet& c) { device.bindDynamicSet(c.set, *c.bindings, c.offsets); }
        void operator()(const command::SetVertexBuffer& c) { device.setVertexBuffer(c.slot, c.buffer, c.offset); }
        void operator()(const command::SetIndexBuffer& c) { device.setIndexBuffer(c.buffer, c.type, c.offset); }
        void operator()(const command::ApplyMipRanges& c) {
            device.applyMipRanges(std::span(list.m_mipRanges).subspan(c.first, c.count));
        }
        void operator()(const command::Draw& c) {
            device.draw(c.vertexCount, c.instanceCount, c.firstVertex, c.firstInstance);
        }
        void operator()(const command::BindSetAndDraw& c) {
            device.bindBindingSet(c.range, *c.bindings);
            (*this)(c.draw);
        }
        [[gnu::always_inline]] void operator()(const command::BindSetAndDrawOne& c) {
            device.bindBindingSet(c.range, *c.bindings);
            device.draw(c.vertexCount, 1, c.firstVertex, 0);
        }
        void operator()(const command::BindSetAndDrawIndexed& c) {
            device.bindBindingSet(c.set, *c.bindings);
            (*this)(c.draw);
        }
        void operator()(const command::DrawIndexed& c) {
            device.drawIndexed(c.indexCount, c.instanceCount, c.firstIndex, c.vertexOffset, c.firstInstance);
        }
        void operator()(const command::Dispatch& c) { device.dispatch(c.x, c.y, c.z); }
        void operator()(const command::MemoryBarrier& c) { device.memoryBarrier(c.bits); }
        void operator()(const command::WriteBuffer& c) {
            device.bufferSubData(*c.buffer, list.m_uploads.data() + c.bytesOffset, c.size, c.dstOffset);
        }
        void operator()(const command::CopyBuffer& c) {
            gl.glBindBuffer(GL_COPY_READ_BUFFER, c.src->name());
            gl.glBindBuffer(GL_COPY_WRITE_BUFFER, c.dst->name());
            gl.glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, GLintptr(c.srcOffset),
                                   GLintptr(c.dstOffset), GLsizeiptr(c.size));
        }
        void operator()(const command::CopyBufferToTexture& c) {
            // Unpacking from a bound pixel buffer: the "pointer" is an offset into it.
            gl.glBindBuffer(GL_PIXEL_UNPACK_BUFFER, c.src->name());
            device.uploadTexture(*c.dst, c.dstSub, reinterpret_cast<const void*>(uintptr_t(c.srcOffset)));
            gl.glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
        }
        void operator()(const command::CopyTextureToBuffer& c) {
            // Through the CPU: ES 3.0 can read some formats only in a wider form that needs repacking.
            const std::vector<std::byte> pixels = device.downloadTexture(*c.src, c.srcSub);
            device.bufferSubData(*c.dst, pixels.data(), pixels.size(), c.dstOffset);
        }
        void operator()(const command::CopyTexture& c) { device.copyTextureImage(*c.dst, c.dstSub, *c.src, c.srcSub); }
        void operator()(const command::GenerateMips& c) {
            const Texture& texture = *c.texture;
            gl.glActiveTexture(GL_TEXTURE0 + kScratchTextureUnit);
            gl.glBindTexture(texture.target(), texture.name());
            // glGenerateMipmap starts at GL_TEXTURE_BASE_LEVEL: undo a mip-range view's (GLES).
            if (device.isES()) texture.applyMipRange(0, texture.desc().mipLevels);
            gl.glGenerateMipmap(texture.target());
        }
        void operator()(const command::BeginTimer& c) {
            device.timestamp(c.timer->beginQuery(), true);
            c.timer->begun = true;
            c.timer->ended = false;
        }
        void operator()(const command::EndTimer& c) {
            device.timestamp(c.timer->endQuery(), false);
            c.timer->ended = true;
        }
        void operator()(const command::PushDebugGroup& c) {
            const std::string& label = list.m_labels[c.label];
            if (gl.glPushDebugGroup) gl.glPushDebugGroup(GL_DEBUG_SOURCE_APPLICATION, 0, GLsizei(label.size()), label.c_str());
        }
        void operator()(const command::PopDebugGroup&) {
            if (gl.glPopDebugGroup) gl.glPopDebugGroup();
        }
    };
    Replayer replayer{*this, device, gl};
    // A switch rather than std::visit, whose table of out-of-line calls costs a call per command.
    static_assert(std::variant_size_v<Command> == 27, "one case per command below");
#define JANUS_REPLAY_CASE(N) \
    case N: replayer(*std::get_if<N>(&command)); break;
    for (const Command& command : std::span(m_commands).first(m_commandCount)) {
        // A draw with its set, the command of most lists: one compare instead of the table's jump.
        if (command.index() == kCommandIndex<command::BindSetAndDrawOne>) [[likely]] {
            replayer(*std::get_if<command::BindSetAndDrawOne>(&command));
            continue;
        }
        switch (command.index()) {
                JANUS_REPLAY_CASE(0)
                JANUS_REPLAY_CASE(1)
                JANUS_REPLAY_CASE(2)
                JANUS_REPLAY_CASE(3)
                JANUS_REPLAY_CASE(4)
                JANUS_REPLAY_CASE(5)
                JANUS_REPLAY_CASE(6)
                JANUS_REPLAY_CASE(7)
                JANUS_REPLAY_CASE(8)
                JANUS_REPLAY_CASE(9)
                JANUS_REPLAY_CASE(10)
                JANUS_REPLAY_CASE(11)
                JANUS_REPLAY_CASE(12)
                JANUS_REPLAY_CASE(13)
                JANUS_REPLAY_CASE(14)
                JANUS_REPLAY_CASE(15)
                JANUS_REPLAY_CASE(16)
                JANUS_REPLAY_CASE(17)
                JANUS_REPLAY_CASE(18)
                JANUS_REPLAY_CASE(19)
                JANUS_REPLAY_CASE(20)
                JANUS_REPLAY_CASE(21)
                JANUS_REPLAY_CASE(22)
                JANUS_REPLAY_CASE(23)
                JANUS_REPLAY_CASE(24)
                JANUS_REPLAY_CASE(25)
                JANUS_REPLAY_CASE(26)
        }
    }
#undef JANUS_REPLAY_CASE
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
    FramebufferKey& key = m_passKey;
    std::vector<const Texture*>& colors = m_passColors;
    key.colors.clear();
    key.depth = {};
    colors.clear();
    const Texture* depth = nullptr;
    for (const Attachment& a : desc.colors) {
        auto* texture = static_cast<const Texture*>(a.texture.get());
        colors.push_back(texture);
        key.colors.push_back(texture->attachmentKey(a.subresource));
    }
    if (desc.depth) {
        depth = static_cast<const Texture*>(desc.depth->texture.get());
        key.depth = depth->attachmentKey(desc.depth->subresource);
    }
    const GLuint fbo = m_context->framebuffer(key, colors, depth);
    f.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    // Transfers and mip generation since the last pass bound textures at units of their own.
    if (m_drawChecks & kCheckSamplerUnits) m_plainDraws = false;

    const Texture* any = colors.empty() ? depth : colors[0];
    const uint32_t mip = colors.empty() ? desc.depth->subresource.mipLevel : desc.colors[0].subresource.mipLevel;
    m_renderWidth = any->width(mip);
    m_renderHeight = any->height(mip);
    f.glViewport(0, 0, GLsizei(m_renderWidth), GLsizei(m_renderHeight));
    f.glScissor(0, 0, GLsizei(m_renderWidth), GLsizei(m_renderHeight));
    GLStateCache& state = m_context->state;
    state.setDepthRange(0.0f, 1.0f);

    // A multisampled texture's first pass loads zeros (Texture::takeFirstUse).
    auto clears = [](const Attachment& a, const Texture& texture) {
        const bool first = texture.isRenderbuffer() && texture.takeFirstUse();
        return a.loadOp == LoadOp::Clear || (first && a.loadOp == LoadOp::Load);
    };
    auto clearValue = [](const Attachment& a) {
        return a.loadOp == LoadOp::Clear ? a.clearColor : std::array<float, 4>{0.0f, 0.0f, 0.0f, 0.0f};
    };
    uint32_t clearColor = 0;   // a bit per colour attachment (Limits::maxColorAttachments is at most 8)
    for (size_t i = 0; i < desc.colors.size(); ++i) clearColor |= uint32_t(clears(desc.colors[i], *colors[i])) << i;
    const bool clearDepth = desc.depth && clears(*desc.depth, *depth);
    // Clears obey the write masks, which the previous pipeline may have narrowed.
    if (clearColor) state.setAllColorMasks(0xF);
    if (clearDepth) state.setDepthMask(true);
    for (size_t i = 0; i < desc.colors.size(); ++i) {
        const Attachment& a = desc.colors[i];
        if (!(clearColor & (1u << i))) continue;
        const std::array<float, 4> value = clearValue(a);
        if (formatInfo(colors[i]->desc().format).kind == FormatKind::UInt) {
            const GLuint uintValue[4] = {GLuint(value[0]), GLuint(value[1]), GLuint(value[2]), GLuint(value[3])};
            f.glClearBufferuiv(GL_COLOR, GLint(i), uintValue);
        } else {
            f.glClearBufferfv(GL_COLOR, GLint(i), value.data());
        }
    }
    if (clearDepth) {
        const float value = desc.depth->loadOp == LoadOp::Clear ? desc.depth->clearDepth : 0.0f;
        f.glClearBufferfv(GL_DEPTH, 0, &value);
    }
    if (m_pipeline) m_pipeline->applyState();
}

// Blits are clipped by the scissor (the pass may have narrowed it) but not by write masks.
void Device::resolveRenderPass(const RenderPassDesc& desc) {
    const GLFunctions& f = gl();
    for (const Attachment& a : desc.colors) {
        if (!a.resolveTexture) continue;
        auto* source = static_cast<const Texture*>(a.texture.get());
        auto* target = static_cast<const Texture*>(a.resolveTexture.get());
        FramebufferKey readKey, drawKey;
        readKey.colors.push_back(source->attachmentKey(a.subresource));
        drawKey.colors.push_back(target->attachmentKey(a.resolveSubresource));
        const GLuint readFbo = m_context->framebuffer(readKey, {source}, nullptr);
        const GLuint drawFbo = m_context->framebuffer(drawKey, {target}, nullptr);
        f.glBindFramebuffer(GL_READ_FRAMEBUFFER, readFbo);
        f.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, drawFbo);
        const auto width = GLint(source->width(0)), height = GLint(source->height(0));
        f.glScissor(0, 0, width, height);
        f.glBlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
}

void Device::bindPipeline(const Pipeline& pipeline) {
    // Nothing a list replays changes program or pipeline state without restoring it (a render
    // pass re-applies it, so does the GLES depth read-back), so the same pipeline again is a no-op.
    if (&pipeline == m_pipeline) return;
    // Attribute pointers depend on the vertex layout only, which many pipelines share.
    if (!m_pipeline || !sameVertexLayout(m_pipeline->graphics(), pipeline.graphics())) m_vertexStateDirty = true;
    m_plainDraws = false;   // its base-instance uniform may not be 0
    m_pipeline = &pipeline;
    // Points taken from a set: this pipeline may read them (restoreTakenPoints checks at its draw;
    // m_plainDraws is false, above).
    static_assert(kMaxBindingSets == 4, "the next line names every index");
    if (m_takenPoints[0] | m_takenPoints[1] | m_takenPoints[2] | m_takenPoints[3]) m_drawChecks |= kRestoreTakenPoints;
    m_context->replayPipeline = &pipeline.debugName();
    pipeline.applyState();
}

void Device::bindTextures(const BindingSet& bindings, uint64_t points) {
    if (m_drawChecks & kCheckSamplerUnits) m_plainDraws = false;   // the next draw checks the units again
    const GLFunctions& f = gl();
    for (const BindingItem& item : bindings.desc().items) {
        if (!(bindingPointBit(item.binding) & points)) continue;
        switch (item.type) {
            case ResourceType::UniformBuffer:
            case ResourceType::StorageBuffer: break;   // bindBindingSet bound them
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

// `set` takes `points`: the other sets lose those of theirs.
void Device::takePoints(uint32_t set, uint64_t points) {
    for (uint32_t i = 0; i < kMaxBindingSets; ++i) {
        const uint64_t taken = i == set ? 0 : m_setPoints[i] & points;
        if (!taken) continue;
        m_takenPoints[i] |= taken;
        m_boundSets[i] = nullptr;
        m_exclusivePoints[i] = 0;
        m_drawChecks |= kRestoreTakenPoints;
        m_plainDraws = false;   // the next draw restores them
    }
}

// Binds again, from the set the list bound at its index, each point the pipeline reads that
// another set took: every binding then shows the item of the set the shader declares it in, as
// on Vulkan. Points the pipeline does not read stay taken (the next pipeline may need them back).
void Device::restoreTakenPoints() {
    const Pipeline& pipeline = *m_pipeline;
    const GLFunctions& f = gl();
    for (const uint32_t set : pipeline.usedSets()) {   // each bound by the list (checked when recorded)
        const uint64_t points = pipeline.setPoints(set) & m_takenPoints[set];
        if (!points) continue;
        const BindingSet& bindings = *m_listSets[set];
        for (const BindingSet::BufferRange& b : bindings.bufferRanges())
            if (bindingPointBit(b.index) & points)
                f.glBindBufferRange(b.target, b.index, b.buffer, rangeOffset(b, set), b.size);
        if (bindings.hasTextures()) bindTextures(bindings, points);
        m_takenPoints[set] &= ~points;
        takePoints(set, points);
    }
    // What this pipeline reads is in place (the sets it uses read disjoint points), until a set
    // takes points again or another pipeline comes (bindPipeline checks again then).
    m_drawChecks &= uint8_t(~kRestoreTakenPoints);
}

void Device::runDrawChecks(const char* call) {
    if (m_drawChecks & kRestoreTakenPoints) restoreTakenPoints();
    if (m_drawChecks & kCheckSamplerUnits) checkSamplerUnits(call);
}

void Device::applyMipRanges(std::span<const TextureMipRange> ranges) {
    // A range is set on the texture bound at its unit: the pipeline's own first, where another
    // set took the unit (restoreTakenPoints would come at the draw, after this).
    if (m_drawChecks & kRestoreTakenPoints) restoreTakenPoints();
    for (const TextureMipRange& r : ranges) {
        if (r.texture->hasMipRange(r.baseMip, r.mipCount)) continue;
        gl().glActiveTexture(GL_TEXTURE0 + r.unit);   // where the binding set bound it
        r.texture->applyMipRange(r.baseMip, r.mipCount);
    }
}

void Device::setVertexBuffer(uint32_t slot, GLuint buffer, uint64_t offset) {
    if (slot >= m_vertexBuffers.size()) m_vertexBuffers.resize(slot + 1);
    VertexBinding& binding = m_vertexBuffers[slot];
    if (binding.buffer == buffer && binding.offset == offset) return;
    binding = {buffer, offset};
    markVertexStateDirty();
}

void Device::setIndexBuffer(GLuint buffer, IndexType type, uint64_t offset) {
    m_indexBuffer = buffer;
    m_indexType = type;
    m_indexOffset = offset;
}

void Device::specifyVertexAttributes(int64_t baseVertexOffset, uint32_t baseInstanceOffset) {
    m_vertexStateDirty = false;
    m_vertexStateBase = baseVertexOffset;
    m_vertexStateInstanceBase = baseInstanceOffset;
    const GLFunctions& f = gl();
    const GraphicsPipelineDesc& desc = m_pipeline->graphics();
    uint32_t wanted = 0;
    for (const VertexAttribute& attribute : desc.vertexAttributes) {
        const VertexBufferLayout& layout = layoutOf(desc, attribute);
        const VertexBinding& binding = m_vertexBuffers[attribute.bufferSlot];   // bound: checked at record time
        const int64_t stepOffset = (layout.perInstance ? int64_t(baseInstanceOffset) : baseVertexOffset) * int64_t(layout.stride);
        const auto pointer = reinterpret_cast<const void*>(
            uintptr_t(int64_t(binding.offset) + int64_t(attribute.offset) + stepOffset));
        f.glBindBuffer(GL_ARRAY_BUFFER, binding.buffer);
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

void Device::drawBaseInstance(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex,
                              uint32_t firstInstance) {
    bindVertexAttributes(0, 0);
    gl().glDrawArraysInstancedBaseInstance(m_pipeline->mode(), GLint(firstVertex), GLsizei(vertexCount),
                                           GLsizei(instanceCount), firstInstance);
}

void Device::drawIndexed(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex, int32_t vertexOffset,
                           uint32_t firstInstance) {
    m_plainDraws = false;   // ES moves the attribute pointers by vertexOffset, and firstInstance sets the uniform
    if (m_drawChecks) [[unlikely]] runDrawChecks("draw");
    const GLFunctions& f = gl();
    const GLenum mode = m_pipeline->mode();
    const GLenum type = m_indexType == IndexType::UInt16 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
    const uint64_t indexSize = m_indexType == IndexType::UInt16 ? 2 : 4;
    const auto indices = reinterpret_cast<const void*>(uintptr_t(m_indexOffset + uint64_t(firstIndex) * indexSize));
    setBaseInstance(firstInstance);
    if (m_boundIndexBuffer != m_indexBuffer) {
        f.glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_indexBuffer);
        m_boundIndexBuffer = m_indexBuffer;
    }
    // As in draw(): one instance through the plain entry points, which GL defines as the
    // instanced ones with one instance.
    if (!isES()) {
        bindVertexAttributes(0, 0);
        if (instanceCount == 1 && firstInstance == 0) [[likely]] {
            if (vertexOffset == 0)
                f.glDrawElements(mode, GLsizei(indexCount), type, indices);
            else
                f.glDrawElementsBaseVertex(mode, GLsizei(indexCount), type, indices, vertexOffset);
            return;
        }
        f.glDrawElementsInstancedBaseVertexBaseInstance(mode, GLsizei(indexCount), type, indices, GLsizei(instanceCount),
                                                        vertexOffset, firstInstance);
        return;
    }
    // ES 3.0 has no base vertex or base instance: shift the attribute pointers instead.
    bindVertexAttributes(vertexOffset, firstInstance);
    if (instanceCount == 1) [[likely]]
        f.glDrawElements(mode, GLsizei(indexCount), type, indices);
    else
        f.glDrawElementsInstanced(mode, GLsizei(indexCount), type, indices, GLsizei(instanceCount));
}

void Device::checkSamplerUnits(const char* call) {
    const GLFunctions& f = gl();
    for (const Pipeline::SamplerUniform& sampler : m_pipeline->samplerUniforms()) {
        f.glActiveTexture(GL_TEXTURE0 + GLenum(sampler.unit));
        GLint texture = 0, samplerObject = 0, compareMode = GL_NONE;
        f.glGetIntegerv(sampler.bindingQuery, &texture);
        f.glGetIntegerv(GL_SAMPLER_BINDING, &samplerObject);
        if (samplerObject != 0) f.glGetSamplerParameteriv(GLuint(samplerObject), GL_TEXTURE_COMPARE_MODE, &compareMode);
        std::string problem;
        if (texture == 0)
            problem = fmt::format("no {} texture is bound there", sampler.targetName);
        else if (sampler.shadow && compareMode == GL_NONE)
            problem = "the sampler bound there does not compare, and the shader's is a shadow sampler (SamplerDesc::setCompare)";
        else if (!sampler.shadow && compareMode != GL_NONE)
            problem = "the sampler bound there compares depth, and the shader's is not a shadow sampler";
        if (problem.empty()) continue;
        m_context->collectDebugMessage(
            {MessageSeverity::Error,
             fmt::format("GL {} check: pipeline '{}' samples '{}' through texture unit {}, but {}; drivers leave that "
                         "undefined (NVIDIA reports it as id 131222)",
                         call, m_pipeline->debugName(), sampler.name, sampler.unit, problem)});
    }
}

void Device::dispatch(uint32_t x, uint32_t y, uint32_t z) {
    if (m_drawChecks) [[unlikely]] runDrawChecks("dispatch");
    const GLFunctions& f = gl();
    f.glDispatchCompute(x, y, z);
}

// Recorded by the command list's hazard tracking (see CommandList::recordBarrier): only where a
// command reads or overwrites what a shader wrote, and at the end of a list that wrote anything.
void Device::memoryBarrier(GLbitfield bits) {
    if (gl().glMemoryBarrier) gl().glMemoryBarrier(bits);
}

}  // namespace janus::rhi::gl
