// Internal types of the GL backend (OpenGL 4.3 core and OpenGL ES 3.0 share all of them; the
// differences are flags on Context and on the device's capabilities).
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <utility>
#include <tuple>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "gl_functions.h"
#include "gl_platform.h"
#include "gl_shader_translation.h"
#include "gl_state_cache.h"
#include "janus/rhi/draw_range_validation.h"
#include "janus/rhi/dynamic_offsets.h"
#include "janus/rhi/keep_alive.h"
#include "janus/rhi/rhi.h"
#include "janus/rhi/texture_view_validation.h"

namespace janus::rhi::gl {

// How a Janus format is stored and transferred in GL.
struct GLFormat {
    GLenum internalFormat = 0;
    GLenum uploadFormat = 0;   // pixel format of tightly packed Janus data
    GLenum uploadType = 0;
};
const GLFormat& glFormat(Format format);
GLenum compareFunction(CompareOp op);

// One attachment of a framebuffer object: which texture image it shows.
struct AttachmentKey {
    GLuint texture = 0;
    uint32_t mipLevel = 0;
    uint32_t layer = 0;
    bool renderbuffer = false;   // `texture` names a renderbuffer (a multisampled texture): another name space
    auto operator<=>(const AttachmentKey&) const = default;
};

struct FramebufferKey {
    std::vector<AttachmentKey> colors;
    AttachmentKey depth;   // texture 0 = none
    auto operator<=>(const FramebufferKey&) const = default;
};

class Texture;

// The GL objects resource destructors delete (Context::deleteObjects).
enum class GLObjectKind : uint8_t { Buffer, Texture, Renderbuffer, Sampler, Shader, Program, Query };

// A context's platform and the thread it is current on: what a thread needs to let go of the
// context, held by the context and by that thread (so a context destroyed elsewhere is still
// released, and its platform destroyed, when the thread lets go: docs/ARCHITECTURE.md, "Threads").
struct ContextBinding {
    std::unique_ptr<Platform> platform;
    std::atomic<std::thread::id> thread{};   // the thread it is current on; std::thread::id() for none
};

// The context and everything tied to it. Shared by the device and every resource, so GL objects
// can be deleted (with their context current) in whatever order handles are released.
class Context {
public:
    // `platform`'s context is current on the calling thread (creating it made it so).
    Context(std::unique_ptr<Platform> platform, bool es);
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    // Makes this context current on the calling thread unless it already is, and deletes what
    // destructors on other threads left for it. A context is current on one thread at a time:
    // throws Error(InvalidUsage) while another thread holds it (until that thread calls
    // releaseFromThread() or exits), Error(DeviceLost) when the platform refuses.
    void makeCurrent();
    // Where the context is current on the calling thread: flushes and unbinds it there.
    void releaseFromThread() noexcept;
    // For Device's and Context's destructors, which must never throw: makes the context current
    // and returns true, or, when that fails (another thread holds it; at process exit the driver's
    // EGL may already be shut down, and static objects are destroyed after it), returns false and
    // says so on stderr, once per context. The caller then leaves its GL objects to the driver;
    // from then on every call returns false at once.
    bool makeCurrentForTeardown() noexcept;
    // For resource destructors, which may run on any thread: deletes the objects now where the
    // context is current on the calling thread, else at its next makeCurrent (or destruction).
    // Never throws.
    void deleteObjects(GLObjectKind kind, std::span<const GLuint> names) noexcept;

    bool isES() const { return m_es; }
    const std::string& platformName() const { return m_platformName; }

    // Framebuffer objects are cached by attachments; a texture's deletion drops those naming it
    // (GL reuses texture names, so a stale entry would render into a deleted texture).
    GLuint framebuffer(const FramebufferKey& key, const std::vector<const Texture*>& colorTextures,
                       const Texture* depthTexture);
    void forgetTexture(GLuint texture, bool renderbuffer = false);

    // Debug output, filled by the KHR_debug callback.
    void collectDebugMessage(DebugMessage message);
    std::vector<DebugMessage> takeDebugMessages();
    std::vector<DebugMessage> takePerformanceMessages();
    std::function<void(const DebugMessage&)> messageCallback;
    // The debug name of the pipeline a list's replay bound last (empty outside replay): driver
    // messages name it, since a message about a draw rarely says which one.
    const std::string* replayPipeline = nullptr;

    GLFunctions gl;
    GLStateCache state;   // the fixed-function state set through it, as last set (after gl: it calls gl)
    GLuint vertexArray = 0;
    // glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE) is in effect: shaders are translated without
    // SPIRV-Cross's clip depth fix-up.
    bool zeroToOneClipDepth = false;
    // glClearTexImage exists (GL 4.4, ARB/EXT_clear_texture): new textures are zeroed with it.
    bool clearTexImage = false;
    // Validation is on: each draw and dispatch checks what its program's samplers will read
    // (Device::checkSamplerUnits).
    bool checkSamplerUnits = false;

private:
    bool currentHere() const;
    void acquire();
    void deleteNow(GLObjectKind kind, std::span<const GLuint> names);
    void deleteDeferred();

    std::shared_ptr<ContextBinding> m_binding;
    bool m_es;
    bool m_unreachableAtTeardown = false;   // makeCurrentForTeardown failed (and said so)
    std::string m_platformName;
    std::map<FramebufferKey, GLuint> m_framebuffers;
    std::vector<DebugMessage> m_debugMessages;
    std::vector<DebugMessage> m_performanceMessages;   // severity Performance, apart from the above
    // Objects whose handles were released on a thread where the context was not current.
    std::mutex m_deferredMutex;
    std::vector<std::pair<GLObjectKind, GLuint>> m_deferred;
    std::atomic<bool> m_hasDeferred{false};
};
using ContextPtr = std::shared_ptr<Context>;

// ---------------------------------------------------------------------------------------------

class Buffer final : public IBuffer {
public:
    const Context* owner() const { return m_context.get(); }
    Buffer(ContextPtr context, const BufferDesc& desc);
    ~Buffer() override;
    const BufferDesc& desc() const override { return m_desc; }
    GLuint name() const { return m_name; }
    KeepMark keepMark;

private:
    ContextPtr m_context;
    BufferDesc m_desc;
    GLuint m_name = 0;
};

class Texture final : public ITexture {
public:
    const Context* owner() const { return m_context.get(); }
    Texture(ContextPtr context, const TextureDesc& resolvedDesc);
    ~Texture() override;
    const TextureDesc& desc() const override { return m_desc; }
    GLuint name() const { return m_name; }
    GLenum target() const { return m_target; }
    const GLFormat& format() const { return glFormat(m_desc.format); }
    // Width/height/depth-or-layers of a mip level.
    uint32_t width(uint32_t mip) const { return mipExtent(m_desc.width, mip); }
    uint32_t height(uint32_t mip) const { return mipExtent(m_desc.height, mip); }
    uint32_t layers(uint32_t mip) const;
    uint64_t subresourceSize(uint32_t mip) const;
    // Attaches one image to the bound framebuffer object at `attachmentPoint`.
    void attach(GLenum framebufferTarget, GLenum attachmentPoint, uint32_t mip, uint32_t layer) const;
    // A multisampled texture is a renderbuffer (GLES 3.0 has no multisampled textures; they are
    // only rendered to and resolved, never sampled).
    bool isRenderbuffer() const { return m_target == GL_RENDERBUFFER; }
    AttachmentKey attachmentKey(TextureSubresource sub) const { return {m_name, sub.mipLevel, sub.layer, isRenderbuffer()}; }
    // True once, for a multisampled texture no pass has rendered to yet: its first pass clears
    // it to zero where it would load it (new textures read as zero; a renderbuffer cannot be
    // cleared without a framebuffer, which only a pass has).
    bool takeFirstUse() const { return std::exchange(m_firstUse, false); }

    // Desktop GL: a texture view (glTextureView) showing `view`, created on first use and
    // cached; the texture itself when the view is the whole texture. Returns name and target.
    std::pair<GLuint, GLenum> viewFor(const ResolvedTextureView& view) const;
    // GLES (no texture views): shows mips [base, base + count) to samplers through
    // GL_TEXTURE_BASE_LEVEL / GL_TEXTURE_MAX_LEVEL. The texture must be bound to the active unit.
    // Every sampled binding sets its range, so no range leaks from one binding to the next.
    void applyMipRange(uint32_t baseMip, uint32_t mipCount) const;
    bool hasMipRange(uint32_t baseMip, uint32_t mipCount) const {
        return m_baseLevel == baseMip && m_maxLevel == baseMip + mipCount - 1;
    }
    KeepMark keepMark;

private:
    void createRenderbuffer();
    void zeroContents() const;

    ContextPtr m_context;
    TextureDesc m_desc;
    GLuint m_name = 0;
    GLenum m_target = 0;
    mutable std::map<std::tuple<int, uint32_t, uint32_t, uint32_t, uint32_t>, GLuint> m_views;
    mutable bool m_firstUse = false;    // multisampled textures: takeFirstUse
    mutable uint32_t m_baseLevel = 0;   // GLES: the range applyMipRange last set
    mutable uint32_t m_maxLevel = 0;
};

class Sampler final : public ISampler {
public:
    const Context* owner() const { return m_context.get(); }
    Sampler(ContextPtr context, const SamplerDesc& desc, bool anisotropySupported);
    ~Sampler() override;
    const SamplerDesc& desc() const override { return m_desc; }
    // Validation rejects linear filtering of formats the device cannot filter, so every texture
    // a sampler is bound with is complete under it.
    GLuint name() const { return m_name; }

private:
    ContextPtr m_context;
    SamplerDesc m_desc;
    GLuint m_name = 0;
};

// A texture unit nobody binds resources to (bindings are < 16 by convention), so creating or
// updating a texture never disturbs a bound binding set.
inline constexpr GLuint kScratchTextureUnit = 31;
// The unit of the internal depth-to-colour copy's source (binding 30 in shaders/rhi-gl).
inline constexpr GLuint kDepthCopyTextureUnit = 30;

class Shader final : public IShader {
public:
    const Context* owner() const { return m_context.get(); }
    Shader(ContextPtr context, const ShaderDesc& desc);
    ~Shader() override;
    const ShaderDesc& desc() const override { return m_desc; }
    std::string translatedSource() const override { return m_source; }
    GLuint name() const { return m_name; }
    const std::vector<ShaderBinding>& bindings() const { return m_bindings; }
    const std::vector<ShaderInput>& inputs() const { return m_inputs; }

private:
    ContextPtr m_context;
    ShaderDesc m_desc;
    std::string m_source;
    GLuint m_name = 0;
    std::vector<ShaderBinding> m_bindings;
    std::vector<ShaderInput> m_inputs;
};

// GL binding point / unit b as a bit of a mask; bindings from 63 up share the top bit (a set's
// masks may then overlap where its items do not: only ever more work, never a missed overlap).
constexpr uint64_t bindingPointBit(uint32_t binding) {
    return binding < 63 ? uint64_t(1) << binding : uint64_t(1) << 63;
}

class Pipeline final : public IPipeline {
public:
    const Context* owner() const { return m_context.get(); }
    Pipeline(ContextPtr context, const GraphicsPipelineDesc& desc);
    Pipeline(ContextPtr context, const ComputePipelineDesc& desc);
    ~Pipeline() override;
    bool isCompute() const override { return m_compute; }
    GLuint program() const { return m_program; }
    const GraphicsPipelineDesc& graphics() const { return m_graphics; }
    // Location of SPIRV-Cross's emulated gl_InstanceIndex base, or -1.
    GLint baseInstanceLocation() const { return m_baseInstanceLocation; }
    // The value that uniform holds (program state, so it survives switching programs).
    mutable GLint baseInstanceValue = 0;
    const std::vector<ShaderBinding>& bindings() const { return m_bindings; }
    // What binding checks are cached under (BindingSet::validated): an id per distinct list of
    // (set, binding, type, dimension, depth compare, image format, block size), the same for pipelines whose shaders use the same
    // bindings, never reused by another list (ids are not addresses, so a pipeline destroyed
    // and another made at the same address cannot hit its entries).
    uint64_t bindingSignature() const { return m_bindingSignature; }
    // The set indices the bindings use (each once, ascending), all < kMaxBindingSets; and
    // cacheableBindings() is false when some binding uses a set index >= kMaxBindingSets (nothing can
    // be bound there: the uncached check reports it).
    std::span<const uint32_t> usedSets() const { return m_usedSets; }
    bool cacheableBindings() const { return m_cacheableBindings; }
    // The one set index the bindings use, or kMaxBindingSets (several, none, or not cacheable).
    uint32_t singleSet() const { return m_singleSet; }
    // The binding points (bindingPointBit) the shaders read from set `set` < kMaxBindingSets.
    uint64_t setPoints(uint32_t set) const { return m_setPoints[set]; }
    // The glDraw* mode of the topology.
    GLenum mode() const { return m_mode; }
    // Applies rasterizer, depth and blend state.
    void applyState() const;
    KeepMark keepMark;

    // The program's active sampler uniforms, each element of an array apart (only with
    // Context::checkSamplerUnits): what Device::checkSamplerUnits compares with the bound state.
    struct SamplerUniform {
        std::string name;
        GLint unit = 0;
        GLenum bindingQuery = 0;   // GL_TEXTURE_BINDING_2D, ..._CUBE_MAP, ...
        const char* targetName = "";
        bool shadow = false;       // sampler*Shadow: needs a comparing sampler
    };
    const std::vector<SamplerUniform>& samplerUniforms() const { return m_samplerUniforms; }
    const std::string& debugName() const { return m_debugName; }

private:
    void link(const std::vector<const Shader*>& shaders, const std::string& debugName,
              std::span<const DynamicUniformBuffer> dynamic);
    void findSamplerUniforms();
    std::vector<SamplerUniform> m_samplerUniforms;
    std::string m_debugName;

    ContextPtr m_context;
    bool m_compute = false;
    GraphicsPipelineDesc m_graphics;
    GLuint m_program = 0;
    GLint m_baseInstanceLocation = -1;
    std::vector<ShaderBinding> m_bindings;
    uint64_t m_bindingSignature = 0;
    std::vector<uint32_t> m_usedSets;
    bool m_cacheableBindings = true;
    uint32_t m_singleSet = kMaxBindingSets;
    std::array<uint64_t, kMaxBindingSets> m_setPoints{};
    GLenum m_mode = GL_TRIANGLES;
};

// How a draw or dispatch accesses one binding item, for hazard tracking: the resource (IBuffer
// or ITexture), its bytes (textures: 0..UINT64_MAX), the glMemoryBarrier bits a read of it
// waits for and whether shaders may write it (storage buffers and images).
struct ShaderAccess {
    const void* resource;
    uint64_t begin, end;
    GLbitfield needs;
    bool write;
};

// What a passed binding check found: the bound items the pipeline uses, how it accesses them
// (parallel to `used`) and what kinds they include.
struct UsedBindings {
    std::span<const UsedBinding> used;
    std::span<const ShaderAccess> accesses;
    bool writesStorage = false;     // a storage buffer or image
    bool samplesTextures = false;   // a sampled texture
    bool usesTextures = false;      // a texture or image
};

// One buffer binding as its glBindBufferRange, in 16 bytes (offset and size fit 32 bits: GL
// buffers are at most Limits::maxBufferSize = 2^31 bytes; binding points < 64). A binding set of
// exactly one buffer item holds its range so (BindingSet::ReplayState), and a command binding a
// set before a draw copies it (command::BindSetAndDraw, BindSetAndDrawOne).
struct InlineRange {
    uint32_t offset = 0, size = 0;
    GLuint buffer = 0;
    uint8_t index = 0;      // the binding point
    bool storage = false;   // GL_SHADER_STORAGE_BUFFER, else GL_UNIFORM_BUFFER
    bool plain = false;     // the set is this range and nothing else: replay binds it from the copy
    uint8_t set = 0;        // in a command: the set index it binds the set at
    GLenum target() const { return storage ? GLenum(GL_SHADER_STORAGE_BUFFER) : GLenum(GL_UNIFORM_BUFFER); }
};
static_assert(sizeof(InlineRange) == 16);

// A draw that binds a set reads one cache line of it: the keep mark (IBindingSet's, after the
// vtable pointer), the key of the last passed binding check with no texture and no storage write
// (which is all a per-draw bind needs to know of the check), then what replay binds: the binding
// points and a one-buffer set's range. Recording reads it; replay reads it again, except for a
// plain set (its one buffer range and nothing else) bound right before a draw, whose range the
// draw's command carries. Aligned to a line and laid out so, such a bind touches one line of the
// set and no other allocation: applications draw with many sets (a uniform slice per draw), so
// the line is rarely in the first-level cache, and every further line was a further miss per draw.
class alignas(64) BindingSet final : public IBindingSet {
public:
    BindingSet(const Context& owner, const BindingSetDesc& desc);
    const BindingSetDesc& desc() const override { return m_desc; }
    // The context whose GL names the items hold: binding the set in another is refused. Compared,
    // never dereferenced (the set does not keep its context alive; its items' objects do).
    const Context* owner() const { return m_owner; }
    // The binding points / units the set binds (bindingPointBit of each item). Two sets whose
    // masks are disjoint cannot overwrite each other's bindings.
    uint64_t bindingPoints() const { return m_replay.bindingPoints; }
    // The buffer items as the glBindBufferRange calls that bind them, resolved when the set is
    // made (replay binds them without visiting the items' objects); the textures and images are
    // bound from the items.
    struct BufferRange {
        GLintptr offset;
        GLsizeiptr size;
        GLuint buffer;
        GLuint index;   // the binding point
        GLenum target;  // GL_UNIFORM_BUFFER or GL_SHADER_STORAGE_BUFFER
        // A dynamic uniform buffer: which of the set's offsets moves it (DynamicWindows order).
        uint32_t dynamicSlot = kNotDynamic;
        static constexpr uint32_t kNotDynamic = ~0u;
    };
    std::span<const BufferRange> bufferRanges() const { return m_bufferRanges; }
    // What replay reads of a set, in the set's first line. A set of exactly one buffer item, the
    // common per-draw set, binds it from here (`inlineRange`): then `range` is bufferRanges()[0]
    // (offset and size fit 32 bits: GL buffers are at most Limits::maxBufferSize = 2^31 bytes).
    // Any other set binds bufferRanges().
    struct ReplayState {
        uint64_t bindingPoints = 0;
        InlineRange range;   // its `set` unused here
        bool inlineRange = false;
        bool hasTextures = false;
    };
    const ReplayState& replayState() const { return m_replay; }
    bool hasTextures() const { return m_replay.hasTextures; }
    // Its dynamic uniform buffers' windows (BindingItem::dynamicOffset), in binding order.
    const DynamicWindows& dynamicWindows() const { return m_dynamicWindows; }
    // The access of desc().items[i], resolved when the set is made.
    const ShaderAccess& itemAccess(size_t i) const { return m_itemAccesses[i]; }

    // A passed binding check, cached in the set: every binding of the pipelines with binding
    // signature `signature` at set index `set` has an item of its type (and view dimension) in
    // this set. `used` / `accesses` are those items in the pipeline's binding order. Immutable
    // once made; owned by the set, so they live as long as it (and a set made later at the same
    // address starts with none).
    struct Validated {
        uint64_t signature;
        uint32_t set;
        UsedBindings found;   // views of the vectors below (never moved: the check is on the heap)
        std::vector<UsedBinding> used;
        std::vector<ShaderAccess> accesses;
    };
    // The check for (signature, set) if it passed before, else null. The last one found or
    // added is compared without a lock; others are looked up under the set's mutex (several
    // command lists may record with one set at once).
    const Validated* validated(uint64_t signature, uint32_t set) const {
        if (const Validated* last = lastValidated(signature, set)) [[likely]] return last;
        return findValidated(signature, set);
    }
    // The same, looking at the last one only.
    const Validated* lastValidated(uint64_t signature, uint32_t set) const {
        const Validated* last = m_lastValidated.load(std::memory_order_acquire);
        return last && last->signature == signature && last->set == set ? last : nullptr;
    }
    // Whether the check for (signature, set) passed and found no texture and no storage write:
    // the last such check found or added, compared without touching the check itself (a bind
    // per draw would otherwise read one more cache line, the check's). Its UsedBindings are
    // validated(signature, set)->found.
    bool passedPlainCheck(uint64_t signature, uint32_t set) const {
        return m_lastPlainCheck.load(std::memory_order_relaxed) == checkKey(signature, set);
    }
    // Keeps a passed check (unless one for its key is there already) and returns the kept one.
    const Validated* addValidated(std::unique_ptr<Validated> check) const;
    // The byte after the last one a per-draw bind reads (recording and replay), from the set's
    // start: at most 64, one cache line (tests/rhi/gl_draw_calls_test.cpp checks it).
    size_t bindBytes() const {
        return size_t(reinterpret_cast<const std::byte*>(&m_replay + 1) - reinterpret_cast<const std::byte*>(this));
    }

private:
    // Signatures are ids from 1 up and sets < kMaxBindingSets = 4: distinct keys, never 0.
    static constexpr uint64_t checkKey(uint64_t signature, uint32_t set) { return signature << 2 | set; }
    static_assert(kMaxBindingSets == 4, "checkKey keeps the set in two bits");
    const Validated* findValidated(uint64_t signature, uint32_t set) const;
    // Under m_validatedMutex: `check` is the last one found or added.
    void noteLastValidated(const Validated* check) const;

    mutable std::atomic<uint64_t> m_lastPlainCheck{0};        // first line; 0: none
    ReplayState m_replay;                                     // the rest of the first line
    static_assert(sizeof(ReplayState) == 32, "the first line holds the replay state");
    const Context* m_owner;   // for cast(): a bind of a set the list holds does not check it again
    mutable std::atomic<const Validated*> m_lastValidated{nullptr};
    std::vector<BufferRange> m_bufferRanges;   // all of them
    BindingSetDesc m_desc;
    DynamicWindows m_dynamicWindows;
    std::vector<ShaderAccess> m_itemAccesses;
    mutable std::mutex m_validatedMutex;
    mutable std::vector<std::unique_ptr<Validated>> m_validated;
};

class TimerQuery final : public ITimerQuery {
public:
    const Context* owner() const { return m_context.get(); }
    explicit TimerQuery(ContextPtr context);
    ~TimerQuery() override;
    GLuint beginQuery() const { return m_queries[0]; }
    GLuint endQuery() const { return m_queries[1]; }
    bool begun = false;
    bool ended = false;
    KeepMark keepMark;

private:
    ContextPtr m_context;
    GLuint m_queries[2] = {0, 0};
};

// ---------------------------------------------------------------------------------------------

class Device;

// GLES mip-range emulation: the range a draw's sampled binding shows of its texture.
struct TextureMipRange {
    const Texture* texture;
    uint32_t unit, baseMip, mipCount;
};

// What a command list replays: plain structs, so recording a command allocates nothing (the
// vector's capacity is reused from one recording to the next). Objects are named by pointer; the
// list's keep-alive holds each one for as long as the recording needs it.
namespace command {
struct BeginRenderPass { uint32_t pass; };   // index into CommandList::m_renderPasses
struct ResolveRenderPass { uint32_t pass; };   // its attachments' resolves, at the pass's end
struct SetViewport { Viewport viewport; };
struct SetScissor { ScissorRect scissor; };
struct BindPipeline { const Pipeline* pipeline; };
struct BindBindingSet { uint32_t set; const BindingSet* bindings; };
// A set with dynamic uniform buffers and its offsets (setBindingSet's second form). Never merged
// with a draw: replay binds its ranges at the offsets every time.
struct BindDynamicSet { uint32_t set; const BindingSet* bindings; std::array<uint32_t, kMaxDynamicOffsetsPerSet> offsets; };
struct SetVertexBuffer { uint32_t slot; GLuint buffer; uint64_t offset; };
struct SetIndexBuffer { GLuint buffer; IndexType type; uint64_t offset; };
struct ApplyMipRanges { uint32_t first, count; };   // into CommandList::m_mipRanges
struct Draw { uint32_t vertexCount, instanceCount, firstVertex, firstInstance; };
struct DrawIndexed { uint32_t indexCount, instanceCount, firstIndex; int32_t vertexOffset; uint32_t firstInstance; };
struct Dispatch { uint32_t x, y, z; };
struct MemoryBarrier { GLbitfield bits; };
struct WriteBuffer { const Buffer* buffer; uint64_t bytesOffset, size, dstOffset; };   // bytes in m_uploads
struct CopyBuffer { const Buffer* dst; const Buffer* src; uint64_t dstOffset, srcOffset, size; };
struct CopyBufferToTexture { const Texture* dst; TextureSubresource dstSub; const Buffer* src; uint64_t srcOffset; };
struct CopyTextureToBuffer { const Buffer* dst; uint64_t dstOffset; const Texture* src; TextureSubresource srcSub; };
struct CopyTexture { const Texture* dst; TextureSubresource dstSub; const Texture* src; TextureSubresource srcSub; };
struct GenerateMips { const Texture* texture; };
struct BeginTimer { TimerQuery* timer; };
struct EndTimer { TimerQuery* timer; };
struct PushDebugGroup { uint32_t label; };   // index into CommandList::m_labels
struct PopDebugGroup {};
// A set bound right before a draw, recorded as one command: replay dispatches once per draw.
// BindSetAndDraw copies the set's range (a plain set's is all it binds) while recording reads the
// set anyway, so that replay binds a plain set without reading it: replay comes a whole list
// later, and reading the set's line again was one cache line more per draw. (No room for the copy
// beside an indexed draw: a command stays 48 bytes.)
struct BindSetAndDraw { const BindingSet* bindings; InlineRange range; Draw draw; };
// The same for a draw of one instance from instance 0, the draw of most lists: replay reads and
// tests no instance arguments.
struct BindSetAndDrawOne { const BindingSet* bindings; InlineRange range; uint32_t vertexCount, firstVertex; };
struct BindSetAndDrawIndexed { uint32_t set; const BindingSet* bindings; DrawIndexed draw; };
}  // namespace command

using Command = std::variant<command::BeginRenderPass, command::SetViewport, command::SetScissor, command::BindPipeline,
                             command::BindBindingSet, command::SetVertexBuffer, command::SetIndexBuffer,
                             command::ApplyMipRanges, command::Draw, command::DrawIndexed, command::Dispatch,
                             command::MemoryBarrier, command::WriteBuffer, command::CopyBuffer,
                             command::CopyBufferToTexture, command::CopyTextureToBuffer, command::CopyTexture,
                             command::GenerateMips, command::BeginTimer, command::EndTimer, command::PushDebugGroup,
                             command::PopDebugGroup, command::BindSetAndDraw, command::BindSetAndDrawIndexed,
                             command::BindSetAndDrawOne, command::BindDynamicSet, command::ResolveRenderPass>;
// A draw writes one at recording and reads it at replay: a command per draw stays this small.
static_assert(sizeof(Command) == 48, "a command grew");
// Command::index() of a command of type T.
template <class T>
inline constexpr size_t kCommandIndex = Command(std::in_place_type<T>).index();

namespace command {
// The draw recorded right after a set bind, over that bind (CommandList::recordDraw). Written field
// by field: no copy of the command is read back right after being written. mergeBind writes the
// bind's half, in place of the bind.
template <class Merged>
Merged& mergeBind(Command& command) {
    const BindBindingSet bind = std::get<BindBindingSet>(command);
    Merged& merged = command.emplace<Merged>();
    merged.bindings = bind.bindings;
    merged.range = bind.bindings->replayState().range;
    merged.range.set = uint8_t(bind.set);
    return merged;
}
inline void merge(Command& command, Draw draw) {
    if (draw.instanceCount == 1 && draw.firstInstance == 0) [[likely]] {
        BindSetAndDrawOne& merged = mergeBind<BindSetAndDrawOne>(command);
        merged.vertexCount = draw.vertexCount;
        merged.firstVertex = draw.firstVertex;
        return;
    }
    mergeBind<BindSetAndDraw>(command).draw = draw;
}
inline void merge(Command& command, DrawIndexed draw) {
    const BindBindingSet bind = std::get<BindBindingSet>(command);
    command.emplace<BindSetAndDrawIndexed>(BindSetAndDrawIndexed{bind.set, bind.bindings, draw});
}
}  // namespace command

// Every bit glMemoryBarrier takes in OpenGL 4.3 and OpenGL ES 3.1. GL_ALL_BARRIER_BITS is valid
// only whole: a pending write that started from it and had some bits issued would leave
// undefined bits set, which NVIDIA rejects (GL_INVALID_VALUE) where Mesa ignores them.
inline constexpr GLbitfield kEveryMemoryBarrierBit =
    GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_ELEMENT_ARRAY_BARRIER_BIT | GL_UNIFORM_BARRIER_BIT |
    GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_COMMAND_BARRIER_BIT |
    GL_PIXEL_BUFFER_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
    GL_FRAMEBUFFER_BARRIER_BIT | GL_TRANSFORM_FEEDBACK_BARRIER_BIT | GL_ATOMIC_COUNTER_BARRIER_BIT |
    GL_SHADER_STORAGE_BARRIER_BIT;

class CommandList final : public ICommandList {
public:
    // The list holds the device's context, not the device: it may be recorded (and released)
    // after the device is gone, like any resource.
    explicit CommandList(ContextPtr context) : m_context(std::move(context)), m_es(m_context->isES()) {}
    const Context* owner() const { return m_context.get(); }

    void beginImpl() override;
    void end() override;
    void beginRenderPassImpl(const RenderPassDesc& desc) override;
    void endRenderPass() override;
    void setViewportImpl(const Viewport& viewport) override;
    void setScissorImpl(const ScissorRect& scissor) override;
    void setPipeline(const PipelineHandle& pipeline) override;
    void setBindingSetImpl(uint32_t set, const BindingSetHandle& bindings) override;
    void setBindingSetImpl(uint32_t set, const BindingSetHandle& bindings,
                           std::span<const uint32_t> dynamicOffsets) override;
    // setBindingSetImpl's whole path: its fast path calls nothing, so it saves no registers.
    [[gnu::noinline]] void setBindingSetGeneral(uint32_t set, const BindingSetHandle& bindings);
    // What both paths do once the set is checked and held and the list has room for a command.
    void bindRecordedSet(uint32_t set, BindingSet* bindings);
    void setVertexBufferImpl(uint32_t slot, const BufferHandle& buffer, uint64_t offset) override;
    void setIndexBufferImpl(const BufferHandle& buffer, IndexType type, uint64_t offset) override;
    void draw(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex, uint32_t firstInstance) override;
    void drawIndexed(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex, int32_t vertexOffset,
                     uint32_t firstInstance) override;
    void dispatchImpl(uint32_t groupsX, uint32_t groupsY, uint32_t groupsZ) override;
    void writeBufferImpl(const BufferHandle& dst, const void* data, uint64_t size, uint64_t dstOffset) override;
    void copyBufferImpl(const BufferHandle& dst, uint64_t dstOffset, const BufferHandle& src, uint64_t srcOffset,
                    uint64_t size) override;
    void copyBufferToTextureImpl(const TextureHandle& dst, TextureSubresource dstSub, const BufferHandle& src,
                             uint64_t srcOffset) override;
    void copyTextureToBufferImpl(const BufferHandle& dst, uint64_t dstOffset, const TextureHandle& src,
                             TextureSubresource srcSub) override;
    void copyTextureImpl(const TextureHandle& dst, TextureSubresource dstSub, const TextureHandle& src,
                     TextureSubresource srcSub) override;
    void generateMipsImpl(const TextureHandle& texture) override;
    void beginTimer(const TimerQueryHandle& timer) override;
    void endTimer(const TimerQueryHandle& timer) override;
    void pushDebugGroup(std::string_view name) override;
    void popDebugGroup() override;
    // GL: nothing. The hazard tracking below is tested by counting the glMemoryBarrier calls
    // replay makes (tests/rhi/gl_barriers_test.cpp); no GL tool reports a missing barrier.
    void omitNextBarrierForTesting() override {}
    // Shader writes no barrier has ordered yet for every access (one entry per written range).
    size_t pendingWriteCountForTesting() const { return m_pendingWrites.size(); }
    size_t recordedCommandCountForTesting() const { return m_commandCount; }

    // Called by Device::execute.
    void replay(Device& device);   // on the device that made it (Device::execute checks)

private:
    template <typename T>
    void record(T command) {
        // Into the storage of earlier recordings; growing is out of line, so recording a command
        // is a store and an increment.
        static_assert(std::is_trivially_copyable_v<Command>);
        if (m_commandCount == m_commandCapacity) [[unlikely]] growCommands();
        recordWithRoom(command);
    }
    // record() where the caller made sure there is room.
    template <typename T>
    void recordWithRoom(T command) {
        m_commands[m_commandCount++] = Command(std::in_place_type<T>, command);
    }
    // A draw right after a set bind takes the bind's place as one BindSetAndDraw(One, Indexed). A draw
    // is in a pass, whose BeginRenderPass was recorded: there is a last command.
    template <class DrawCommand>
    void recordDraw(DrawCommand draw) {
        Command& last = m_commands[m_commandCount - 1];
        if (std::holds_alternative<command::BindBindingSet>(last)) {
            command::merge(last, draw);
            return;
        }
        record(draw);
    }
    [[gnu::noinline]] void growCommands() {
        m_commands.resize(std::max<size_t>(256, m_commands.size() * 2));
        m_commandCapacity = m_commands.size();
    }
    // Inline checks per command; the throwing halves are out of line.
    void requireRecording(const char* what) const {
        if (!m_recording) [[unlikely]] throwNotRecording(what);
    }
    void requireOutsideRenderPass(const char* what) const {
        if (!m_recording || m_inRenderPass) [[unlikely]] throwWrongPassState(what);
    }
    void requireInsideRenderPass(const char* what) const {
        if (!m_recording || !m_inRenderPass) [[unlikely]] throwWrongPassState(what);
    }
    [[noreturn]] void throwNotRecording(const char* what) const;
    [[noreturn]] void throwWrongPassState(const char* what) const;


    // Draw and dispatch state is validated when it changed since the last check, not per
    // command: m_pipelineChecked covers the pipeline against the vertex buffers and the pass's
    // formats, m_bindingsChecked the pipeline's bindings against the sets (and the pass).
    void requireDrawState(const char* what) {
        if (!m_pipelineChecked) [[unlikely]] requirePipelineState(what);
        if (!m_bindingsChecked) {
            requireBindings(what);
            if (found().samplesTextures) recordMipRanges();
            m_bindingsChecked = true;
        }
    }
    // A draw whose checks and hazard tracking would all pass and do nothing: recording, in a
    // render pass, a graphics pipeline set, pipeline state and bindings checked, no write pending
    // and none by the bound items. Set by the checked path of draw (and kept by a setBindingSet
    // whose check is cached), cleared by everything that changes one of these.
    void invalidateDrawState() {
        m_pipelineChecked = m_bindingsChecked = false;
        m_drawReady = false;
    }
    // The checks and tracking of draw / drawIndexed, then the command (out of line).
    void drawChecked(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex, uint32_t firstInstance);
    void drawIndexedChecked(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex, int32_t vertexOffset,
                            uint32_t firstInstance);
    void requirePipelineState(const char* what);
    BoundVertexBuffer boundVertexBuffer(uint32_t slot) const;   // what setVertexBuffer set at `slot`
    [[noreturn]] void throwDrawOutOfRange(const DrawRange& range, bool indexed) const;
    void requireCompatiblePipeline(const char* what) const;
    // Checks what the pipeline's shaders use against the bound sets; points m_found at the
    // items they use. Each set's part of a passed check is cached in the set
    // (BindingSet::Validated) under the pipeline's binding signature: when every set the
    // pipeline uses has it, only the checks that depend on more than one set or on the render
    // pass (textures only) run again.
    void requireBindings(const char* what) {
        // Inline: one set whose last check is the pipeline's (a set bound per draw).
        const Pipeline& pipeline = *m_pipeline;
        const uint32_t index = pipeline.singleSet();
        if (index < kMaxBindingSets) {
            if (const BindingSet* set = m_bindingSets[index]) {
                if (const BindingSet::Validated* check = set->lastValidated(pipeline.bindingSignature(), index)) {
                    setFound(check->found);
                    if (m_found.usesTextures) requireTextureUses(what);
                    return;
                }
            }
        }
        requireBindingsCached(what);
    }
    void requireBindingsCached(const char* what);
    void requireBindingsUncached(const char* what);
    // The checks of textures across bindings and against the pass, on m_found (current).
    void requireTextureUses(const char* what) const;
    // GLES: re-applies the mip ranges of the sampled textures a draw uses right before it (an
    // item of a set bound later, unused by the draw, may have set another range on the texture).
    void recordMipRanges();
    void requireVertexBuffers(const char* what) const;
    // ES: a negative vertexOffset keeps every per-vertex attribute pointer inside its buffer.
    void requireVertexOffsetInsideBuffers(int32_t vertexOffset) const;
    const RenderPassDesc* openPass() const { return m_inRenderPass ? &m_renderPasses[m_renderPassCount - 1] : nullptr; }

    // Hazards between shader writes (storage buffers and images, which GL leaves unordered) and
    // later accesses, tracked while recording. A write stays pending for the barrier bits not
    // issued since; a command touching a pending range first gets glMemoryBarrier with the bits
    // its kind of access needs.
    struct PendingWrite {
        const void* resource;   // IBuffer or ITexture
        uint64_t begin, end;    // bytes of a buffer; textures: the whole texture
        GLbitfield unsynchronized;
    };
    // The subset of `needs` a command must wait for before it accesses [begin, end) of `resource`.
    GLbitfield hazardBits(const void* resource, uint64_t begin, uint64_t end, GLbitfield needs) const {
        for (const PendingWrite& write : m_pendingWrites)
            if (write.resource == resource && write.begin < end && begin < write.end && (write.unsynchronized & needs))
                return needs;
        return 0;
    }
    GLbitfield bufferHazard(const IBuffer* buffer, uint64_t begin, uint64_t end, GLbitfield needs) const {
        return m_pendingWrites.empty() ? 0 : hazardBits(buffer, begin, end, needs);
    }
    GLbitfield textureHazard(const ITexture* texture, GLbitfield needs) const {
        return m_pendingWrites.empty() ? 0 : hazardBits(texture, 0, UINT64_MAX, needs);
    }
    void recordBarrier(GLbitfield bits);   // no barrier for 0
    // Before a draw or dispatch: waits for what its bindings (and a draw's vertex and index
    // buffers) read, then notes what its storage bindings write.
    void trackShaderAccesses(bool drawing, bool indexed) {
        if (m_pendingWrites.empty() && !found().writesStorage) return;   // nothing to wait for or note
        trackPendingShaderAccesses(drawing, indexed);
    }
    void trackPendingShaderAccesses(bool drawing, bool indexed);
    void addPendingWrite(const void* resource, uint64_t begin, uint64_t end) {
        m_drawReady = false;
        // A write touching or overlapping one already listed for the resource merges into it (the
        // merged range unsynchronized for every access again: at worst a barrier more, never one
        // missed), so the list holds at most one entry per written range and each check stays
        // cheap. Neighbouring slices written one after another (one dispatch per slice) merge too.
        // Appending instead let draws that write two buffers in turn grow it by two entries each,
        // and every later draw scan them all (quadratic recording).
        for (PendingWrite& write : m_pendingWrites)
            if (write.resource == resource && begin <= write.end && write.begin <= end) {
                write.begin = std::min(write.begin, begin);
                write.end = std::max(write.end, end);
                write.unsynchronized = kEveryMemoryBarrierBit;
                return;
            }
        m_pendingWrites.push_back({resource, begin, end, kEveryMemoryBarrierBit});
    }

    ContextPtr m_context;
    bool m_es = false;
    std::vector<Command> m_commands;   // the first m_commandCount are this recording's
    size_t m_commandCount = 0;
    size_t m_commandCapacity = 0;   // m_commands.size()
    // Command payloads that own memory, referenced by index from m_commands.
    std::vector<RenderPassDesc> m_renderPasses;   // the first m_renderPassCount are this recording's
    size_t m_renderPassCount = 0;
    std::vector<std::byte> m_uploads;
    std::vector<std::string> m_labels;
    std::vector<TextureMipRange> m_mipRanges;

    KeepAliveList m_keepAlive;   // everything the recording references

    bool m_recording = false;
    bool m_recorded = false;
    bool m_inRenderPass = false;
    bool m_pipelineChecked = false;
    bool m_bindingsChecked = false;
    bool m_drawReady = false;   // see invalidateDrawState()
    const Pipeline* m_pipeline = nullptr;   // last pipeline set (held by m_keepAlive)
    // How far draws may read the vertex buffers (requirePipelineState) and the index buffer.
    DrawRangeLimits m_drawLimits;
    uint64_t m_indexLimit = 0;
    std::vector<Format> m_passColorFormats;   // formats of the open render pass
    Format m_passDepthFormat = Format::Unknown;
    uint32_t m_passSampleCount = 1;   // the open pass's attachments' TextureDesc::sampleCount
    bool m_passResolves = false;      // the open pass resolves an attachment at its end
    std::array<const BindingSet*, kMaxBindingSets> m_bindingSets{};   // by set index
    // The bound items the pipeline uses (last check) and how it accesses them (parallel): in a
    // cached check of the set, or in the storage below. Read it through found(): a set bound with
    // a passed plain check (bindRecordedSet) leaves it to be fetched from that check when read.
    UsedBindings m_found;
    struct FoundInCheck {
        const BindingSet* set = nullptr;   // null: m_found is current
        uint64_t signature = 0;
        uint32_t index = 0;
    } m_foundInCheck;
    const UsedBindings& found() {
        if (m_foundInCheck.set) [[unlikely]] fetchFound();
        return m_found;
    }
    void fetchFound();
    void setFound(const UsedBindings& found) {
        m_found = found;
        m_foundInCheck.set = nullptr;
    }
    std::vector<UsedBinding> m_usedStorage;
    std::vector<ShaderAccess> m_accessStorage;
    struct RecordedVertexBuffer {
        uint32_t slot;
        const Buffer* buffer;
        uint64_t offset;
    };
    std::vector<RecordedVertexBuffer> m_vertexBuffers;   // slots given a buffer since begin()
    const Buffer* m_indexBuffer = nullptr;
    uint64_t m_indexOffset = 0;
    IndexType m_indexType = IndexType::UInt32;
    std::vector<PendingWrite> m_pendingWrites;
    int m_debugGroupDepth = 0;
    // The timers this recording began and ended: each once per list, begun before it ends (as on
    // Vulkan, where both timestamps live in the list).
    struct TimerUse {
        const TimerQuery* timer = nullptr;
        bool began = false, ended = false;
    };
    std::vector<TimerUse> m_timers;
    TimerUse& timerUse(const TimerQuery* timer);
};

// ---------------------------------------------------------------------------------------------

class Device final : public IDevice {
public:
    explicit Device(const DeviceDesc& desc);
    // With a platform made elsewhere (tests inject doubles through it); desc.glPlatform is ignored.
    Device(const DeviceDesc& desc, std::unique_ptr<Platform> platform);
    ~Device() override;

    BufferHandle createBufferImpl(const BufferDesc& desc) override;
    TextureHandle createTextureImpl(const TextureDesc& desc) override;
    SamplerHandle createSamplerImpl(const SamplerDesc& desc) override;
    ShaderHandle createShaderImpl(const ShaderDesc& desc) override;
    PipelineHandle createGraphicsPipelineImpl(const GraphicsPipelineDesc& desc) override;
    PipelineHandle createComputePipelineImpl(const ComputePipelineDesc& desc) override;
    BindingSetHandle createBindingSetImpl(const BindingSetDesc& desc) override;
    TimerQueryHandle createTimerQueryImpl() override;
    CommandListHandle createCommandListImpl() override;

    void executeImpl(const CommandListHandle& commandList) override;
    void waitIdle() override;
    void detachFromThread() override { m_context->releaseFromThread(); }

    void writeBufferImpl(const BufferHandle& buffer, const void* data, uint64_t size, uint64_t offset) override;
    std::vector<std::byte> readBufferImpl(const BufferHandle& buffer, uint64_t offset, uint64_t size) override;
    void writeTextureImpl(const TextureHandle& texture, TextureSubresource sub, const void* data, uint64_t size) override;
    std::vector<std::byte> readTextureImpl(const TextureHandle& texture, TextureSubresource sub) override;
    std::optional<double> timerSeconds(const TimerQueryHandle& timer) override;
    std::vector<DebugMessage> takeDebugMessages() override;
    void collectFrontMessage(const DebugMessage& message) override;
    std::vector<DebugMessage> takePerformanceMessages() override;
    void insertPerformanceMessageForTesting(const std::string& text) override;
    void provokeValidationErrorForTesting() override;

    // --- used while replaying command lists (context current) ---
    Context& context() { return *m_context; }
    const GLFunctions& gl() const { return m_context->gl; }
    bool isES() const { return m_context->isES(); }
    void bufferSubData(const Buffer& buffer, const void* data, uint64_t size, uint64_t offset);
    void uploadTexture(const Texture& texture, TextureSubresource sub, const void* pixels);
    std::vector<std::byte> downloadTexture(const Texture& texture, TextureSubresource sub);
    // ES 3.0 without NV_read_depth: draws the depth image into an r32f target and reads that.
    std::vector<std::byte> readDepthThroughColor(const Texture& texture, TextureSubresource sub);
    void copyTextureImage(const Texture& dst, TextureSubresource dstSub, const Texture& src,
                          TextureSubresource srcSub);
    void beginRenderPass(const RenderPassDesc& desc);
    // Blits each multisampled colour attachment with a resolveTexture into it.
    void resolveRenderPass(const RenderPassDesc& desc);
    void bindPipeline(const Pipeline& pipeline);
    // GL has one binding point per number for all sets: a set takes the points of its items from
    // whatever was there, also from the other sets. What the current pipeline reads of a set whose
    // points were taken is bound again before its next draw or dispatch (restoreTakenPoints).
    void bindBindingSet(uint32_t set, const BindingSet& bindings) {
        if (!claimSet(set, bindings, [&] { return bindings.bindingPoints(); })) return;
        const GLFunctions& f = gl();
        const BindingSet::ReplayState& r = bindings.replayState();   // the line `points` came from
        if (r.inlineRange) [[likely]]
            f.glBindBufferRange(r.range.target(), r.range.index, r.range.buffer, GLintptr(r.range.offset),
                                GLsizeiptr(r.range.size));
        else
            bindBufferRanges(set, bindings);
        if (r.hasTextures) bindTextures(bindings, ~uint64_t(0));
    }
    // A set with dynamic uniform buffers, at `offsets`: its ranges are bound even when the set is
    // (only the offsets may have changed).
    void bindDynamicSet(uint32_t set, const BindingSet& bindings,
                        const std::array<uint32_t, kMaxDynamicOffsetsPerSet>& offsets) {
        const bool claimed = claimSet(set, bindings, [&] { return bindings.bindingPoints(); });
        m_dynamicOffsets[set] = offsets;
        bindBufferRanges(set, bindings);
        if (claimed && bindings.hasTextures()) bindTextures(bindings, ~uint64_t(0));
    }
    // Every buffer range of the set bound at `set`, a dynamic one where its offset puts it.
    void bindBufferRanges(uint32_t set, const BindingSet& bindings) {
        const GLFunctions& f = gl();
        for (const BindingSet::BufferRange& b : bindings.bufferRanges())
            f.glBindBufferRange(b.target, b.index, b.buffer, rangeOffset(b, set), b.size);
    }
    // Where range `b` of the set bound at `set` starts: moved by its dynamic offset, if it has one.
    GLintptr rangeOffset(const BindingSet::BufferRange& b, uint32_t set) const {
        return b.dynamicSlot == BindingSet::BufferRange::kNotDynamic ? b.offset
                                                                     : b.offset + GLintptr(m_dynamicOffsets[set][b.dynamicSlot]);
    }
    // The same from a command's copy of a plain set's range, without reading the set.
    void bindBindingSet(const InlineRange& range, const BindingSet& bindings) {
        if (!range.plain) return bindBindingSet(range.set, bindings);
        // Its one item is at binding point range.index < 64: that is all the set binds.
        if (!claimSet(range.set, bindings, [&] { return uint64_t(1) << range.index; })) return;
        m_drawCalls.bindBufferRange(range.target(), range.index, range.buffer, GLintptr(range.offset),
                                    GLsizeiptr(range.size));
    }
    // Notes `bindings` as bound at `set` (false, and nothing done, when it is already), with its
    // binding points (`points()`, asked only then): a set that shares points with another's takes
    // them (takePoints). Reads nothing of the set but its address.
    template <class Points>
    bool claimSet(uint32_t set, const BindingSet& bindings, Points points) {
        if (m_boundSets[set] == &bindings) return false;
        const uint64_t mask = points();
        m_listSets[set] = &bindings;
        m_boundSets[set] = &bindings;
        if (mask != m_exclusivePoints[set] || mask == 0) [[unlikely]] {   // 0 also means "not exclusive"
            m_takenPoints[set] = 0;
            m_setPoints[set] = 0;   // so the next line finds the other sets' points only
            static_assert(kMaxBindingSets == 4, "the next line names every index");
            const bool shared = (m_setPoints[0] | m_setPoints[1] | m_setPoints[2] | m_setPoints[3]) & mask;
            if (shared) takePoints(set, mask);
            m_setPoints[set] = mask;
            m_exclusivePoints[set] = shared ? 0 : mask;
        }
        return true;
    }
    // The texture and image items of a set at `points` (bindBindingSet binds its buffer ranges).
    void bindTextures(const BindingSet& bindings, uint64_t points);
    void applyMipRanges(std::span<const TextureMipRange> ranges);
    void setVertexBuffer(uint32_t slot, GLuint buffer, uint64_t offset);
    void setIndexBuffer(GLuint buffer, IndexType type, uint64_t offset);
    void draw(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex, uint32_t firstInstance) {
        // One instance from instance 0 with nothing to set up: the call alone. (The sampler-unit
        // check, with validation on, ran at the draw that set m_plainDraws, and nothing it reads
        // changed since: texture binds and passes clear m_plainDraws then.)
        if (m_plainDraws && instanceCount == 1 && firstInstance == 0) [[likely]] {
            m_drawCalls.drawArrays(m_plainDrawMode, GLint(firstVertex), GLsizei(vertexCount));
            return;
        }
        drawGeneral(vertexCount, instanceCount, firstVertex, firstInstance);
    }
    [[gnu::noinline]] void drawGeneral(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex,
                                       uint32_t firstInstance) {
        m_plainDraws = false;
        const Pipeline& pipeline = *m_pipeline;
        if (m_drawChecks) [[unlikely]] runDrawChecks("draw");
        setBaseInstance(firstInstance);
        if (firstInstance != 0 && !m_es) [[unlikely]] {
            drawBaseInstance(vertexCount, instanceCount, firstVertex, firstInstance);
            return;
        }
        // ES 3.0 has no base instance: the per-instance attribute pointers start at firstInstance
        // instead (gl_InstanceIndex gets it from the base-instance uniform above).
        bindVertexAttributes(0, m_es ? firstInstance : 0);
        // One instance through the plain entry point, the call an application makes for it (and
        // the overhead bench's raw side): GL defines it as the instanced draw with one instance.
        if (instanceCount == 1) [[likely]]
            gl().glDrawArrays(pipeline.mode(), GLint(firstVertex), GLsizei(vertexCount));
        else
            gl().glDrawArraysInstanced(pipeline.mode(), GLint(firstVertex), GLsizei(vertexCount), GLsizei(instanceCount));
        // From instance 0 the attribute pointers start at vertex and instance 0 and the
        // base-instance uniform is 0: what the next such draw needs, until something changes.
        m_plainDraws = firstInstance == 0;
        m_plainDrawMode = pipeline.mode();
    }
    void drawBaseInstance(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex, uint32_t firstInstance);
    void drawIndexed(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex, int32_t vertexOffset,
                     uint32_t firstInstance);
    void dispatch(uint32_t x, uint32_t y, uint32_t z);
    // Validation: reports (as an error debug message) a sampler of the current program whose
    // texture unit has no texture of its target bound, and a shadow sampler read without depth
    // comparison (or a plain one with it). Drivers leave these undefined; NVIDIA reports them
    // (id 131222), Mesa does not, so without this check they would surface on users' machines.
    void checkSamplerUnits(const char* call);
    // What a draw or dispatch does first when m_drawChecks is not 0.
    void runDrawChecks(const char* call);
    void memoryBarrier(GLbitfield bits);
    // glQueryCounter(GL_TIMESTAMP); `beginsTimer`: the first of a timer's two.
    void timestamp(GLuint query, bool beginsTimer);
    uint32_t renderWidth() const { return m_renderWidth; }
    uint32_t renderHeight() const { return m_renderHeight; }

private:
    Capabilities detectCapabilities();
    std::vector<FormatCapabilities> queryFormatCapabilities(const Capabilities& caps) const;
    void setupDebugOutput();
    void setupDefaultState();
    // Offsets (in elements) of the per-vertex and per-instance attributes: ES 3.0's stand-in for
    // base vertex and base instance.
    void bindVertexAttributes(int64_t baseVertexOffset, uint32_t baseInstanceOffset) {
        if (!m_vertexStateDirty && baseVertexOffset == m_vertexStateBase && baseInstanceOffset == m_vertexStateInstanceBase)
            return;
        specifyVertexAttributes(baseVertexOffset, baseInstanceOffset);
    }
    void specifyVertexAttributes(int64_t baseVertexOffset, uint32_t baseInstanceOffset);
    void setBaseInstance(uint32_t firstInstance) {
        // SPIRV-Cross emulates gl_InstanceIndex as gl_InstanceID + this uniform (0 after linking).
        const GLint location = m_pipeline->baseInstanceLocation();
        if (location < 0 || GLint(firstInstance) == m_pipeline->baseInstanceValue) return;
        gl().glUniform1i(location, GLint(firstInstance));
        m_pipeline->baseInstanceValue = GLint(firstInstance);
    }
    bool hasExtension(std::string_view name) const;

    ContextPtr m_context;
    std::vector<std::string> m_extensions;
    bool m_anisotropy = false;
    bool m_readDepthNV = false;
    std::shared_ptr<Pipeline> m_depthCopyPipeline;   // created on first use

    // Replay state.
    const Pipeline* m_pipeline = nullptr;
    // The context's entry points of a plain draw and its set's bind, copied at every execute(): a
    // call through them is one load fewer than through the context, on every draw.
    struct DrawCalls {
        PFNGLBINDBUFFERRANGEPROC bindBufferRange = nullptr;
        PFNGLDRAWARRAYSPROC drawArrays = nullptr;
    } m_drawCalls;
    // The set the list bound last at each index, its binding points, and those of them another
    // set took since (restoreTakenPoints binds what the pipeline reads of those again).
    std::array<const BindingSet*, kMaxBindingSets> m_listSets{};
    std::array<uint64_t, kMaxBindingSets> m_setPoints{};
    std::array<uint64_t, kMaxBindingSets> m_takenPoints{};
    // m_listSets[i] while none of its points was taken (else null): binding it again changes nothing.
    std::array<const BindingSet*, kMaxBindingSets> m_boundSets{};
    // m_setPoints[i] while no other set holds or took any of them (else 0): a set with the same
    // points bound at i again takes nothing from the others and has nothing taken, so it only binds.
    std::array<uint64_t, kMaxBindingSets> m_exclusivePoints{};
    // The offsets the list gave with the set at each index (BindDynamicSet), for its dynamic ranges.
    std::array<std::array<uint32_t, kMaxDynamicOffsetsPerSet>, kMaxBindingSets> m_dynamicOffsets{};
    void takePoints(uint32_t set, uint64_t points);
    void restoreTakenPoints();
    bool m_es = false;   // isES(), read per draw
    // What a draw or dispatch checks first (runDrawChecks), one flag read per draw.
    enum DrawCheck : uint8_t { kRestoreTakenPoints = 1, kCheckSamplerUnits = 2 };
    uint8_t m_drawChecks = 0;
    bool m_timestampsPerTile = false;   // llvmpipe: see timestamp()
    struct VertexBinding { GLuint buffer = 0; uint64_t offset = 0; };
    // By slot (a vector, not a map: cleared by every execute, it keeps its storage).
    std::vector<VertexBinding> m_vertexBuffers;
    GLuint m_indexBuffer = 0;
    IndexType m_indexType = IndexType::UInt32;
    uint64_t m_indexOffset = 0;
    uint32_t m_enabledAttributes = 0;   // bit per location
    // beginRenderPass's scratch, kept for its capacity: a frame's passes allocate nothing.
    FramebufferKey m_passKey;
    std::vector<const Texture*> m_passColors;
    // Draw-to-draw redundancy: attribute pointers, index buffer and base-instance uniform are only
    // respecified when something they depend on changed.
    bool m_vertexStateDirty = true;
    // Set by a draw from instance 0 (the attribute pointers from vertex and instance 0, the
    // base-instance uniform 0), cleared by whatever changes that, by whatever leaves binding
    // points to restore (kRestoreTakenPoints), and with the sampler-unit check on by texture binds
    // and new passes: a draw of one instance from instance 0 then calls glDrawArrays alone
    // (Device::draw), in the mode of the pipeline that set it (m_plainDrawMode: one load fewer).
    bool m_plainDraws = false;
    GLenum m_plainDrawMode = 0;
    void markVertexStateDirty() {
        m_vertexStateDirty = true;
        m_plainDraws = false;
    }
    int64_t m_vertexStateBase = 0;
    uint32_t m_vertexStateInstanceBase = 0;
    GLuint m_boundIndexBuffer = 0;
    uint32_t m_renderWidth = 0, m_renderHeight = 0;
};

// Turns the info log and source of a failed compile into an error message that quotes the
// offending line of the translated source.
std::string describeCompileFailure(const std::string& log, const std::string& source);

}  // namespace janus::rhi::gl
