// Internal classes of the Vulkan backend. Nothing here is visible to RHI users.
//
// Ownership: every object holds a shared_ptr to the Context (instance + device), so handles that
// outlive the IDevice stay valid and the VkDevice is destroyed after the last of them.
// Synchronisation (see docs/ARCHITECTURE.md): images live in VK_IMAGE_LAYOUT_GENERAL from
// creation on; a command list tracks what its commands read and write since its last barrier
// (HazardTracker) and emits a memory barrier only before a command with a real hazard.
#pragma once

#include <vulkan/vulkan.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <concepts>
#include <typeinfo>
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <vector>

#include "janus/rhi/backends.h"
#include "janus/rhi/draw_range_validation.h"
#include "janus/rhi/dynamic_offsets.h"
#include "janus/rhi/keep_alive.h"
#include "janus/rhi/texture_view_validation.h"
#include "vulkan_command_memory.h"

namespace janus::rhi::vulkan {

// Throws rhi::Error unless `result` is VK_SUCCESS. Out-of-memory and device-lost results keep
// their own codes; everything else gets `code`.
void check(VkResult result, ErrorCode code, std::string_view what);
const char* resultName(VkResult result);

VkFormat toVkFormat(Format format);
VkCompareOp toVkCompareOp(CompareOp op);
VkImageAspectFlags aspectOf(Format format);

// One binding of one descriptor set as the pipeline's shaders declare it (from SPIR-V reflection).
struct ReflectedBinding {
    uint32_t set = 0;
    uint32_t binding = 0;
    VkDescriptorType type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    uint32_t count = 1;
    VkShaderStageFlags stages = 0;
    VkImageViewType viewType = VK_IMAGE_VIEW_TYPE_2D;   // images only: the view the shader expects
    bool depthCompare = false;   // a shadow sampler (sampler2DShadow and kin)
    uint32_t imageFormat = 0;    // storage images: the format qualifier (SPIR-V ImageFormat, 0: none)
    uint64_t blockSize = 0;      // buffers: the block's bytes (storage: before a runtime array)
    // Storage buffers / images: whether some stage may write it (no NonWritable decoration).
    // Uniform buffers and sampled textures are never written.
    bool written = false;
    std::string name;
};

// A descriptor set layout plus what each binding needs, so binding sets can be written for it.
struct DescriptorSetLayoutInfo {
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    std::vector<ReflectedBinding> bindings;
    // A one-binding layout: the pipeline stages that read it (a binding set's one read, see
    // BindingSet::LayoutUse::onlyRead), here where a draw finds it next to `layout`.
    VkPipelineStageFlags onlyBindingStages = 0;
};

inline VkPipelineStageFlags pipelineStagesOf(VkShaderStageFlags shaderStages) {
    VkPipelineStageFlags stages = 0;
    if (shaderStages & VK_SHADER_STAGE_VERTEX_BIT) stages |= VK_PIPELINE_STAGE_VERTEX_SHADER_BIT;
    if (shaderStages & VK_SHADER_STAGE_FRAGMENT_BIT) stages |= VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT;
    if (shaderStages & VK_SHADER_STAGE_COMPUTE_BIT) stages |= VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    return stages;
}

// The instance, device and queue, shared by every object of one IDevice.
class Context {
public:
    Context() = default;
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;
    ~Context();

    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;
    uint32_t apiVersion = 0;
    VkPhysicalDeviceProperties properties{};
    VkPhysicalDeviceMemoryProperties memoryProperties{};
    VkPhysicalDeviceFeatures enabledFeatures{};
    uint64_t maxMemoryAllocationSize = 0;
    // VK_EXT_line_rasterization's Bresenham lines are enabled: line lists rasterise by the
    // diamond-exit rule, as GL's do, so line pixels agree across backends.
    bool bresenhamLines = false;
    uint32_t timestampValidBits = 0;
    bool debugUtils = false;
    // Command pools allocate host memory through each list's CommandMemory (on unless
    // JANUS_VULKAN_COMMAND_MEMORY=off; vulkan_device.cpp, useCommandMemory()).
    bool commandMemory = false;

    PFN_vkCmdBeginRendering cmdBeginRendering = nullptr;
    PFN_vkCmdEndRendering cmdEndRendering = nullptr;
    // The per-draw / per-dispatch commands, from vkGetDeviceProcAddr: they reach the driver (or
    // the layers) directly instead of through the loader's trampoline.
    PFN_vkCmdBindPipeline cmdBindPipeline = nullptr;
    PFN_vkCmdBindDescriptorSets cmdBindDescriptorSets = nullptr;
    PFN_vkCmdBindVertexBuffers cmdBindVertexBuffers = nullptr;
    PFN_vkCmdBindIndexBuffer cmdBindIndexBuffer = nullptr;
    PFN_vkCmdDraw cmdDraw = nullptr;
    PFN_vkCmdDrawIndexed cmdDrawIndexed = nullptr;
    PFN_vkCmdDispatch cmdDispatch = nullptr;
    PFN_vkCmdBeginDebugUtilsLabelEXT cmdBeginDebugLabel = nullptr;
    PFN_vkCmdEndDebugUtilsLabelEXT cmdEndDebugLabel = nullptr;
    PFN_vkSetDebugUtilsObjectNameEXT setDebugObjectName = nullptr;
    PFN_vkCreateDebugUtilsMessengerEXT createMessenger = nullptr;
    PFN_vkDestroyDebugUtilsMessengerEXT destroyMessenger = nullptr;

    std::function<void(const DebugMessage&)> messageCallback;
    std::mutex messageMutex;
    std::vector<DebugMessage> messages;
    std::vector<DebugMessage> performanceMessages;   // severity Performance, apart from `messages`
    void addMessage(DebugMessage message);

    // Serialises vkQueueSubmit / vkQueueWaitIdle and the immediate command buffer.
    std::recursive_mutex queueMutex;
    // Command lists' submissions are numbered (under queueMutex); waitIdle() records the last one it
    // waited for, so a list submitted before it knows that its fence has signalled without asking
    // the driver (vkWaitForFences on every begin() after a waitIdle(), otherwise).
    uint64_t lastSubmission = 0;
    std::atomic<uint64_t> finishedSubmissions{0};
    VkCommandPool immediatePool = VK_NULL_HANDLE;
    VkCommandBuffer immediateCommands = VK_NULL_HANDLE;
    VkFence immediateFence = VK_NULL_HANDLE;

    // Records with `record`, submits after all earlier work and waits for completion. The
    // recorded commands are wrapped in full barriers (including host visibility).
    void submitAndWait(const std::function<void(VkCommandBuffer)>& record);
    void waitIdle();

    // `chosen`, when given, receives the property flags of the memory type used.
    VkDeviceMemory allocate(const VkMemoryRequirements& requirements, VkMemoryPropertyFlags required,
                            VkMemoryPropertyFlags preferred, std::string_view what,
                            VkMemoryPropertyFlags* chosen = nullptr);
    void setObjectName(VkObjectType type, uint64_t handle, const std::string& name);
    VkFormatProperties formatProperties(Format format) const;

    // Layouts are cached for the context's lifetime: pipelines with equal sets share one.
    const DescriptorSetLayoutInfo& descriptorSetLayout(const std::vector<ReflectedBinding>& bindings);

    // Descriptor sets come from pools shared by every binding set (vulkan_binding.cpp): a pool
    // per set costs a driver allocation each and scatters small blocks through the heap. A layout
    // with more descriptors of one type than a shared pool is sized for gets a pool of its own.
    struct DescriptorAllocation {
        VkDescriptorPool pool = VK_NULL_HANDLE;
        VkDescriptorSet set = VK_NULL_HANDLE;
    };
    DescriptorAllocation allocateDescriptorSet(const DescriptorSetLayoutInfo& layout);
    void freeDescriptorSet(const DescriptorAllocation& allocation) noexcept;

private:
    std::mutex m_layoutMutex;
    std::map<std::string, std::unique_ptr<DescriptorSetLayoutInfo>> m_layouts;
    struct DescriptorPool {
        VkDescriptorPool pool = VK_NULL_HANDLE;
        uint32_t liveSets = 0;
        bool dedicated = false;   // holds one set's descriptors; destroyed with it
    };
    std::mutex m_descriptorMutex;
    std::vector<DescriptorPool> m_descriptorPools;
};
using ContextPtr = std::shared_ptr<Context>;

// The Context of a device this backend made, else null: for tools that replace entry points in it
// (the overhead bench's null-driver runs, bench/null_driver.h).
Context* contextOf(IDevice& device);

// A full memory barrier: all earlier commands finish and their writes are visible to all later ones.
void fullBarrier(VkCommandBuffer cmd);
// Makes all device writes visible to the host once the submission's fence has signalled.
void hostBarrier(VkCommandBuffer cmd);

// Casts an RHI handle to this backend's class; throws InvalidUsage for null or foreign objects:
// another backend's, or another device's (`owner`: the context of the device using it; its Vulkan
// handles mean nothing in another VkDevice). The backend classes are final, so comparing the
// dynamic type is exact and cheaper than dynamic_cast (this runs on every bind and draw).
[[noreturn]] void throwNotThisBackend(bool null, std::string_view what);
[[noreturn]] void throwOtherDevice(std::string_view what);
// `describe()` names the object; called only for a message (a name may cost a format).
template <class Native, class Interface, std::invocable Describe>
Native* native(const std::shared_ptr<Interface>& handle, Describe&& describe, const Context* owner) {
    static_assert(std::is_final_v<Native>);
    if (!handle || typeid(*handle) != typeid(Native)) [[unlikely]] throwNotThisBackend(!handle, describe());
    auto* object = static_cast<Native*>(handle.get());
    if (object->owner() != owner) [[unlikely]] throwOtherDevice(describe());
    return object;
}
template <class Native, class Interface>
Native* native(const std::shared_ptr<Interface>& handle, std::string_view what, const Context* owner) {
    return native<Native>(handle, [what] { return what; }, owner);
}

// What one command does to one resource, for hazard tracking. Buffers are tracked by byte
// range; textures by subresource key (mip << 32 | layer, see subresourceKeys).
struct KeyRange {
    uint64_t begin = 0;
    uint64_t end = 0;   // exclusive
};
struct ResourceAccess {
    const void* resource = nullptr;   // the Buffer or Texture
    KeyRange range;
    VkPipelineStageFlags stages = 0;
    VkAccessFlags access = 0;
    bool write = false;               // read-write accesses count as writes
};
inline KeyRange subresourceKeys(uint32_t mip, uint32_t layer) {
    const uint64_t key = uint64_t(mip) << 32 | layer;
    return {key, key + 1};
}
inline KeyRange mipKeys(uint32_t mip) { return {uint64_t(mip) << 32, uint64_t(mip + 1) << 32}; }
inline constexpr KeyRange kAllSubresources{0, UINT64_MAX};

// The accesses of one command list since its last barrier. A command whose accesses conflict
// with them (read or write after a write, write after a read) needs a barrier first; barrier()
// emits one that orders everything tracked before all later commands and starts afresh.
class HazardTracker {
public:
    // Start of a command list: earlier submissions may have written anything.
    void reset();
    bool conflicts(const ResourceAccess& access) const;
    void record(const ResourceAccess& access);
    // The accesses of one command: a barrier first if any conflicts, then tracks them all (all
    // are checked before any is tracked: a command does not conflict with itself).
    void access(VkCommandBuffer cmd, std::span<const ResourceAccess> accesses);
    // One access: a dispatch binding one storage range. Inline and without calls for the common
    // case (the resource touched last, no conflict, its range continuing the last one tracked);
    // anything else is accessOneGeneral's, which starts over (nothing is changed before).
    [[gnu::always_inline]] void accessOne(VkCommandBuffer cmd, const ResourceAccess& only) {
        Tracked* tracked = m_lastFound;
        if (!m_unknownWrites && tracked && tracked->resource == only.resource && !tracked->writes.hullOverlaps(only.range) &&
            !(only.write && tracked->reads.hullOverlaps(only.range))) [[likely]] {   // no conflict, even by hull
            RangeSet& set = only.write ? tracked->writes : tracked->reads;
            if (set.extendLast(only.range)) [[likely]] {
                m_srcStages |= only.stages;
                if (only.write) m_srcAccess |= only.access & kWriteAccess;
                return;
            }
        }
        accessOneGeneral(cmd, only);
    }
    [[gnu::noinline]] void accessOneGeneral(VkCommandBuffer cmd, const ResourceAccess& only);
    bool hasWrites() const { return m_unknownWrites || m_srcAccess != 0; }
    void barrier(VkCommandBuffer cmd);
    // The next barrier() forgets what it would order without recording it (tests only).
    void omitNextBarrier() { m_omitNextBarrier = true; }

private:
    // After a barrier: nothing earlier needs ordering against later commands.
    void forget();
    // Sorted, disjoint, non-adjacent ranges (adjacent ones merge, so a run of neighbouring
    // slices stays one range).
    // The fast paths are inline: they are the per-draw / per-dispatch cost.
    struct RangeSet {
        std::vector<KeyRange> ranges;
        // From the first range's begin to the last one's end; {max, 0} (overlapping nothing) when
        // empty. Most checks end at it: one compare pair, no look at the vector.
        KeyRange hull{UINT64_MAX, 0};
        bool hullOverlaps(KeyRange range) const { return range.begin < hull.end && hull.begin < range.end; }
        bool overlaps(KeyRange range) const {
            if (!hullOverlaps(range)) return false;
            return ranges.size() == 1 || overlapsAny(range);   // one range: it is the hull
        }
        void add(KeyRange range) {
            if (!extendLast(range)) insert(range);
        }
        // Adds `range` if it starts inside or right after the last range (a run of neighbouring
        // slices); false (nothing changed) otherwise.
        bool extendLast(KeyRange range) {
            if (ranges.empty() || range.begin < ranges.back().begin || ranges.back().end < range.begin) return false;
            ranges.back().end = std::max(ranges.back().end, range.end);
            hull.end = std::max(hull.end, range.end);   // the last range ends the hull
            return true;
        }
        bool overlapsAny(KeyRange range) const;
        void insert(KeyRange range);
    };
    struct Tracked {
        const void* resource;
        RangeSet reads;
        RangeSet writes;
    };
    // Consecutive commands mostly touch the resource found last: that lookup is inline.
    Tracked* find(const void* resource) {
        if (m_lastFound && m_lastFound->resource == resource) [[likely]] return m_lastFound;
        return search(resource);
    }
    Tracked* search(const void* resource);
    const Tracked* find(const void* resource) const { return const_cast<HazardTracker*>(this)->find(resource); }
    static bool conflicts(const Tracked& tracked, const ResourceAccess& access) {
        if (tracked.writes.overlaps(access.range)) return true;           // read or write after write
        return access.write && tracked.reads.overlaps(access.range);      // write after read
    }
    void record(Tracked& tracked, const ResourceAccess& access) {
        (access.write ? tracked.writes : tracked.reads).add(access.range);
        m_srcStages |= access.stages;
        if (access.write) m_srcAccess |= access.access & kWriteAccess;
    }
    static constexpr VkAccessFlags kWriteAccess =
        VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
        VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_HOST_WRITE_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    std::vector<Tracked> m_tracked;   // few resources between two barriers: a linear search wins
    Tracked* m_lastFound = nullptr;   // consecutive commands mostly touch the same resource
    bool m_unknownWrites = true;
    bool m_omitNextBarrier = false;
    VkPipelineStageFlags m_srcStages = 0;
    VkAccessFlags m_srcAccess = 0;
};

// ---------------------------------------------------------------------------------------------

class Buffer final : public IBuffer {
public:
    Buffer(ContextPtr context, const BufferDesc& desc);
    const Context* owner() const { return m_context.get(); }   // the device that made it
    ~Buffer() override;
    const BufferDesc& desc() const override { return m_desc; }

    VkBuffer buffer = VK_NULL_HANDLE;
    KeepMark keepMark;

private:
    void zeroFill(const VkMemoryRequirements& requirements, VkMemoryPropertyFlags memoryFlags);
    ContextPtr m_context;
    BufferDesc m_desc;
    VkDeviceMemory m_memory = VK_NULL_HANDLE;
};

// Host-visible scratch memory for uploads and readbacks, mapped for its whole life.
class StagingBuffer {
public:
    StagingBuffer(ContextPtr context, uint64_t size);
    ~StagingBuffer();
    StagingBuffer(const StagingBuffer&) = delete;
    StagingBuffer& operator=(const StagingBuffer&) = delete;

    VkBuffer buffer = VK_NULL_HANDLE;
    std::byte* mapped = nullptr;
    uint64_t size = 0;

private:
    ContextPtr m_context;
    VkDeviceMemory m_memory = VK_NULL_HANDLE;
};

class Texture final : public ITexture {
public:
    Texture(ContextPtr context, const TextureDesc& desc);
    const Context* owner() const { return m_context.get(); }   // the device that made it
    ~Texture() override;
    const TextureDesc& desc() const override { return m_desc; }

    // Image array layers: 6 for a cube, arrayLayers for arrays (layer-faces for cube arrays), else 1.
    uint32_t arrayLayers() const {
        return m_desc.dimension == TextureDimension::Texture3D ? 1 : textureLayerCount(m_desc);
    }
    VkExtent3D extent(uint32_t mip) const;
    // Bytes of one subresource (one face / slice of one mip), rows tightly packed.
    uint64_t subresourceSize(uint32_t mip) const;
    // Image subresource + offset addressing one face / slice for copies.
    VkImageSubresourceLayers copyLayers(TextureSubresource sub) const;
    VkOffset3D copyOffset(TextureSubresource sub) const;
    VkExtent3D copyExtent(TextureSubresource sub) const;

    // Cached views (one VkImageView per distinct view); `usage` restricts what the view may be used for.
    VkImageView view(VkImageViewType type, uint32_t baseMip, uint32_t mipCount, uint32_t baseLayer,
                     uint32_t layerCount, VkImageUsageFlags usage);
    // A 2D view of one face / slice at one mip, for use as an attachment.
    VkImageView attachmentView(TextureSubresource sub);

    VkImage image = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkImageAspectFlags aspect = 0;
    KeepMark keepMark;

private:
    ContextPtr m_context;
    TextureDesc m_desc;
    VkDeviceMemory m_memory = VK_NULL_HANDLE;
    std::mutex m_viewMutex;
    std::map<std::tuple<int, uint32_t, uint32_t, uint32_t, uint32_t, uint32_t>, VkImageView> m_views;
};

class Sampler final : public ISampler {
public:
    Sampler(ContextPtr context, const SamplerDesc& desc);
    const Context* owner() const { return m_context.get(); }   // the device that made it
    ~Sampler() override;
    const SamplerDesc& desc() const override { return m_desc; }

    VkSampler sampler = VK_NULL_HANDLE;

private:
    ContextPtr m_context;
    SamplerDesc m_desc;
};

class Shader final : public IShader {
public:
    Shader(ContextPtr context, const ShaderDesc& desc);
    const Context* owner() const { return m_context.get(); }   // the device that made it
    ~Shader() override;
    const ShaderDesc& desc() const override { return m_desc; }
    std::string translatedSource() const override { return {}; }

    VkShaderModule module = VK_NULL_HANDLE;
    VkShaderStageFlagBits stage = VK_SHADER_STAGE_VERTEX_BIT;
    std::vector<ReflectedBinding> bindings;

private:
    ContextPtr m_context;
    ShaderDesc m_desc;
};

class Pipeline final : public IPipeline {
public:
    Pipeline(ContextPtr context, const GraphicsPipelineDesc& desc);
    const Context* owner() const { return m_context.get(); }   // the device that made it
    Pipeline(ContextPtr context, const ComputePipelineDesc& desc);
    ~Pipeline() override;
    bool isCompute() const override { return m_compute; }

    VkPipeline pipeline = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    static constexpr uint32_t kMaxSets = 4;
    std::array<const DescriptorSetLayoutInfo*, kMaxSets> sets{};
    GraphicsPipelineDesc graphicsDesc;   // graphics only: formats and vertex slots for draw checks
    std::string debugName;
    uint32_t usedSets = 0;               // bit s: set s has bindings
    KeepMark keepMark;

private:
    // `dynamic`: the uniform buffers read with dynamic offsets (their layout binding is a
    // UNIFORM_BUFFER_DYNAMIC).
    void createLayout(const std::vector<const Shader*>& shaders, std::span<const DynamicUniformBuffer> dynamic);
    ContextPtr m_context;
    bool m_compute = false;
    std::vector<ShaderHandle> m_shaders;
};

class alignas(64) BindingSet final : public IBindingSet {
public:
    BindingSet(ContextPtr context, const BindingSetDesc& desc);
    const Context* owner() const { return m_owner; }   // the device that made it
    ~BindingSet() override;
    const BindingSetDesc& desc() const override { return m_desc; }

    // A set's one read when that is all a draw tracks of it (one access, no texture to check, no
    // write): the straight-line paths' whole test (joinPassReads). Its stages are the layout's
    // (DescriptorSetLayoutInfo::onlyBindingStages).
    struct OnlyRead {
        const void* resource = nullptr;   // null: the set has no such read
        KeyRange range;
    };
    // The descriptor set holding these resources for one set layout, and what a command using
    // it reads and writes. Never moves once created (`accesses` may point into it).
    // What a bind reads comes first: for the first use, which lies inline, that is the set's
    // first cache line (bindBytes), as is all the tracking of a one-read set; a general draw or
    // dispatch reads `accesses` and `hasTextureItems` in the next one.
    struct LayoutUse {
        std::atomic<VkDescriptorSetLayout> layout{VK_NULL_HANDLE};   // stored last: the use is ready
        VkDescriptorSet set = VK_NULL_HANDLE;
        OnlyRead onlyRead;
        std::span<const ResourceAccess> accesses;
        bool hasTextureItems = false;                  // !textureItems.empty(), next to the rest
        // No texture items and no dynamic offsets: the straight-line dispatch may bind it.
        bool plainBind = false;
        // The layout's dynamic uniform buffers, in binding order (the order vkCmdBindDescriptorSets
        // takes their offsets): each one's index among the set's (DynamicWindows order).
        uint8_t dynamicCount = 0;
        std::array<uint8_t, kMaxDynamicOffsetsPerSet> dynamicOffsetIndex{};
        // dynamicOffsetIndex is 0, 1, ... up to all of the set's: the offsets as given are the bind's.
        bool offsetsAsGiven = false;
        std::array<ResourceAccess, 2> fewAccesses{};   // most sets: no second allocation to visit
        std::vector<ResourceAccess> manyAccesses;
        VkDescriptorPool pool = VK_NULL_HANDLE;
        // The texture items the layout's shaders use, for the view-overlap check at draw/dispatch.
        std::vector<const BindingItem*> textureItems;
    };
    // Written on first use. `pipelineName` is for the messages.
    const LayoutUse& useWith(const DescriptorSetLayoutInfo& layout, uint32_t set, std::string_view pipelineName) {
        if (const LayoutUse* use = findUse(layout.layout)) return *use;
        return createOrFind(layout, set, pipelineName);
    }
    // Its dynamic uniform buffers' windows (BindingItem::dynamicOffset), in binding order.
    const DynamicWindows& dynamicWindows() const { return m_dynamicWindows; }

    // The use for `layout`, found without a lock (binds are hot) when it is the first one (usually
    // the only one; then nothing outside the set's first line is read) or the last one used, else
    // null.
    const LayoutUse* findUse(VkDescriptorSetLayout layout) const {
        if (m_firstUse.layout.load(std::memory_order_acquire) == layout) return &m_firstUse;
        const LayoutUse* last = m_last.load(std::memory_order_acquire);
        return last && last->layout.load(std::memory_order_relaxed) == layout ? last : nullptr;
    }

    // Starts loading what the next draw / dispatch will read of this set (its accesses), so the
    // cache miss overlaps the Vulkan calls in between. Address arithmetic only, no load.
    void prefetchFirstUse() const { __builtin_prefetch(m_firstUse.fewAccesses.data()); }

    // What a bind touches comes first, next to the object's header: binding sets are many, and
    // each bind of a different one may miss the cache. The byte after the last one a bind of
    // the first use reads, from the set's start: at most 64, one cache line
    // (tests/rhi/vulkan_binding_set_test.cpp checks it). The keep mark is IBindingSet's, right
    // after the vtable pointer (keepMarkOf).
    size_t bindBytes() const {
        return size_t(reinterpret_cast<const std::byte*>(&m_firstUse.onlyRead + 1) -
                      reinterpret_cast<const std::byte*>(this));
    }
    const LayoutUse& firstUse() const { return m_firstUse; }

private:
    LayoutUse m_firstUse;   // the first layout used (usually the only one), inline
    std::atomic<const LayoutUse*> m_last{nullptr};   // the last use found by createOrFind
    const Context* m_owner;   // m_context without the indirection, for native()

    const LayoutUse& createOrFind(const DescriptorSetLayoutInfo& layout, uint32_t set, std::string_view pipelineName);
    ContextPtr m_context;
    BindingSetDesc m_desc;
    DynamicWindows m_dynamicWindows;
    std::mutex m_mutex;
    std::map<VkDescriptorSetLayout, std::unique_ptr<LayoutUse>> m_otherUses;
};

class TimerQuery final : public ITimerQuery {
public:
    explicit TimerQuery(ContextPtr context);
    const Context* owner() const { return m_context.get(); }   // the device that made it
    ~TimerQuery() override;

    VkQueryPool pool = VK_NULL_HANDLE;
    bool submitted = false;   // both timestamps were in a command list that was executed

private:
    ContextPtr m_context;
};

class CommandList final : public ICommandList {
public:
    explicit CommandList(ContextPtr context);
    ~CommandList() override;
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
    void setDynamicSetChecked(uint32_t set, const BindingSetHandle& bindings, std::span<const uint32_t> dynamicOffsets);
    void bindDynamicSet(uint32_t set, const BindingSetHandle& bindings, BindingSet& bindingSet);
    void bindDynamicUse(VkPipelineBindPoint bindPoint, VkPipelineLayout layout, uint32_t set,
                        const BindingSet::LayoutUse& use);
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
    void omitNextBarrierForTesting() override;

    // Called by the device: submits the recorded work with this list's fence.
    void submit();
    // Waits until the last submission finished, then drops the resources it kept alive.
    void waitUntilDone();
    // The host memory the driver records this list's commands into (tests look at it).
    const CommandMemory& commandMemory() const { return m_commandMemory; }
    bool usesCommandMemory() const { return m_poolCallbacks != nullptr; }

private:
    enum class State { Initial, Recording, Executable };
    // Inline checks (every call makes them); the throwing parts are out of line.
    void requireRecording(std::string_view call) const {
        if (m_state != State::Recording) [[unlikely]] throwNotRecording(call);
    }
    void requireOutsideRenderPass(std::string_view call) const {
        if (m_state != State::Recording || inRenderPass()) [[unlikely]] throwNotRecordingOrInPass(call);
    }
    [[noreturn]] void throwNotRecording(std::string_view call) const;
    void requireInsideRenderPass(std::string_view call) const;
    // setBindingSet's checks in full (out of line), then bindSet.
    void setBindingSetChecked(uint32_t set, const BindingSetHandle& bindings);
    void bindSet(uint32_t set, const BindingSetHandle& bindings, BindingSet* bindingSet);
    void bindHeldSet(uint32_t set, BindingSet& bindingSet);
    // The per-draw set of a pass, bound and tracked when it is set (see the definition); false
    // leaves it to the next draw.
    bool bindInPass(uint32_t set, const BindingSet& bindingSet);
    // Whether a draw now needs no bind, tracking or check besides its range (prepareDraw would do
    // nothing): then draw() is the range check and the vkCmdDraw.
    bool drawStateBound() const;
    bool indexedDrawStateBound() const;
    [[gnu::noinline]] void drawPrepared(uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex,
                                        uint32_t firstInstance);
    [[gnu::noinline]] void drawIndexedPrepared(uint32_t indexCount, uint32_t instanceCount, uint32_t firstIndex,
                                               int32_t vertexOffset, uint32_t firstInstance);
    [[noreturn]] void throwNotRecordingOrInPass(std::string_view call) const;
    void bindDescriptorSets(Pipeline& pipeline, VkPipelineBindPoint bindPoint, uint32_t& dirtyMask,
                            std::array<const BindingSet::LayoutUse*, Pipeline::kMaxSets>& uses);
    [[noreturn]] void throwNoBindingSet(const Pipeline& pipeline, uint32_t set) const;
    void checkDrawState(std::string_view call);
    // validateViewOverlaps over the texture items of the sets `pipeline` uses.
    void checkViewOverlaps(const Pipeline& pipeline, const std::array<const BindingSet::LayoutUse*, Pipeline::kMaxSets>& uses,
                           bool inPass, std::string_view call);
    void checkTextureViewOverlaps(const Pipeline& pipeline,
                                  const std::array<const BindingSet::LayoutUse*, Pipeline::kMaxSets>& uses, bool inPass,
                                  std::string_view call);
    void prepareDraw(std::string_view call);
    // The common draw inline; false leaves the rest to prepareDraw (state-driven, so it picks up
    // wherever this stopped).
    bool prepareDrawFast();
    // What setVertexBuffer set at a slot the bound pipeline reads (checkDrawState found each).
    BoundVertexBuffer boundVertexBuffer(uint32_t slot) const {
        return {m_vertexBindings[slot].buffer, m_vertexBindings[slot].offset};
    }
    [[noreturn]] void throwDrawOutOfRange(std::string_view call, bool indexed) const;
    // Validation on: the draw in m_drawArguments, for the check of its index values at execute.
    [[gnu::noinline]] void noteIndexedDraw();
    [[gnu::noinline]] void prepareDrawGeneral(std::string_view call);
    // The same for dispatches.
    bool prepareDispatchFast();
    [[gnu::noinline]] void prepareDispatchGeneral();
    [[noreturn]] void throwDrawOutsidePass(std::string_view call) const;
    // The accesses of the sets `untracked` (bits) of a draw's pipeline, after the view check.
    void trackDrawBindings(const Pipeline& pipeline, uint32_t untracked, std::string_view call);
    void trackVertexBuffers(const Pipeline& pipeline);
    // Hands the reads gathered in m_passReads to the hazard tracker.
    void flushPassReads();
    // Widens m_passReads (same resource) by a read of `range` in `stages`.
    void widenPassReads(const KeyRange& range, VkPipelineStageFlags stages);
    bool joinPassReads(const BindingSet::LayoutUse& use, const DescriptorSetLayoutInfo& layout);
    // Barrier first if any of `accesses` conflicts with what was tracked, then tracks them.
    void access(std::initializer_list<ResourceAccess> accesses);

    ContextPtr m_context;
    struct DrawArguments {
        uint32_t count, instances, first, firstInstance;
        int32_t vertexOffset;   // drawIndexed only
    } m_drawArguments{};   // draw()'s and drawIndexed()'s, across the bind (see draw())
    // How far draws may read the bound vertex buffers (checkDrawState) and the index buffer.
    DrawRangeLimits m_drawLimits;
    uint64_t m_indexLimit = 0;
    std::array<uint32_t, 3> m_dispatchGroups{};   // dispatch()'s, the same way
    CommandMemory m_commandMemory;   // the pool's host memory where Context::commandMemory; outlives it
    const VkAllocationCallbacks* m_poolCallbacks;   // m_commandMemory's, or none (the driver's own)
    VkCommandPool m_pool = VK_NULL_HANDLE;
    VkCommandBuffer m_prologue = VK_NULL_HANDLE;   // query resets, which must precede the work
    VkCommandBuffer m_commands = VK_NULL_HANDLE;
    // The context's entry points of the straight-line draw and bind paths, copied at begin(): a call
    // through them is one load fewer than through the context, on every draw.
    struct DrawCalls {
        PFN_vkCmdBindDescriptorSets bindDescriptorSets = nullptr;
        PFN_vkCmdDraw draw = nullptr;
        PFN_vkCmdDrawIndexed drawIndexed = nullptr;
    } m_drawCalls;
    VkFence m_fence = VK_NULL_HANDLE;
    bool m_pending = false;
    uint64_t m_submission = 0;   // the number Context gave its last submission
    State m_state = State::Initial;
    HazardTracker m_hazards;

    KeepAliveList m_keepAlive;   // everything the recording references
    std::vector<std::shared_ptr<StagingBuffer>> m_staging;
    struct TimerUse {
        std::shared_ptr<TimerQuery> timer;
        bool began = false;
        bool ended = false;
    };
    std::vector<TimerUse> m_timers;
    TimerUse& timerUse(const TimerQueryHandle& timer);

    // What stands between a draw and its straight-line path (drawStateBound): one bit per piece of
    // draw-time work not done, set by whatever undoes it and cleared where it is done, so that a
    // draw tests all of them in one word.
    enum DrawNeed : uint32_t {
        kNeedsRenderPass = 1u,       // no render pass is open (a pass opens only while recording)
        kNeedsStateCheck = 2u,       // checkDrawState has not passed since the pipeline, pass or vertex buffers
                                     // changed (clear only with a graphics pipeline: the check requires one)
        kNeedsVertexTracking = 4u,   // the bound vertex buffers are not tracked for this pass
        kNeedsSets = 8u,             // a set the pipeline uses is not bound, or not tracked for this pass
        kNeedsIndexTracking = 16u,   // drawIndexed only: no index buffer, or it is not tracked for this pass
        kNeedsEverything = 31u,
        // Not in kNeedsEverything: a set was bound with dynamic offsets (setBindingSet's second
        // form). Only the general path binds it (bindDescriptorSets passes the offsets).
        kNeedsDynamicBind = 32u,
    };
    uint32_t m_drawNeeds = kNeedsEverything;
    bool inRenderPass() const { return (m_drawNeeds & kNeedsRenderPass) == 0; }
    RenderPassDesc m_passDesc;   // the open pass's attachments, for the view-overlap check
    std::vector<UsedBinding> m_usedTextures;   // scratch for checkViewOverlaps
    std::vector<Format> m_passColorFormats;
    struct PassScratch {   // beginRenderPass's, kept for its capacity
        std::vector<ResourceAccess> accesses;
        std::vector<VkRenderingAttachmentInfo> colors;
    } m_passScratch;
    // Resolves into a layer other than 0 (a cube face, an array layer, a 3D slice), which
    // endRenderPass records with vkCmdResolveImage: lavapipe wrote a resolve attachment's view
    // of such a layer into layer 0 (tests/rhi/multisample_test.cpp).
    struct LayerResolve {
        Texture* from;
        Texture* to;
        TextureSubresource sub;
    };
    std::vector<LayerResolve> m_layerResolves;
    Format m_passDepthFormat = Format::Unknown;
    uint32_t m_passSampleCount = 1;   // the open pass's attachments' TextureDesc::sampleCount
    // Bound objects; m_keepAlive owns them.
    Pipeline* m_graphicsPipeline = nullptr;
    Pipeline* m_computePipeline = nullptr;
    std::array<BindingSet*, Pipeline::kMaxSets> m_bindingSets{};
    // The offsets last given with the set at each index (setBindingSet's second form), in the
    // set's binding order; read only for a set that has dynamic uniform buffers.
    std::array<std::array<uint32_t, kMaxDynamicOffsetsPerSet>, Pipeline::kMaxSets> m_dynamicOffsets{};
    // What is bound to each set for each bind point (updated when the sets are bound).
    std::array<const BindingSet::LayoutUse*, Pipeline::kMaxSets> m_graphicsSetUses{};
    std::array<const BindingSet::LayoutUse*, Pipeline::kMaxSets> m_computeSetUses{};
    uint32_t m_dirtyGraphicsSets = 0;
    uint32_t m_dirtyComputeSets = 0;
    struct VertexBinding {
        Buffer* buffer = nullptr;
        uint64_t offset = 0;
    };
    std::vector<VertexBinding> m_vertexBindings;
    Buffer* m_indexBuffer = nullptr;
    uint64_t m_indexOffset = 0;
    VkIndexType m_indexType = VK_INDEX_TYPE_UINT16;
    // Draw-time work done once per render pass / state change rather than per draw: the state
    // checks, and tracking what the draws read (no barrier is possible inside a pass anyway; see
    // also m_drawNeeds).
    uint32_t m_passTrackedSets = 0;   // bit s: set s's accesses are tracked for this pass
    // Reads of the open pass's draws from one resource, gathered as one range (flushPassReads).
    ResourceAccess m_passReads;
    int m_debugGroupDepth = 0;
};

}  // namespace janus::rhi::vulkan
