// Binding sets: descriptor pools and sets, written lazily for each layout they are used with.
#include <fmt/format.h>

#include <algorithm>
#include <cassert>

#include "vulkan_backend.h"

namespace janus::rhi::vulkan {
namespace {

const char* typeName(VkDescriptorType type) {
    switch (type) {
        case VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER:
        case VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC: return "UniformBuffer";
        case VK_DESCRIPTOR_TYPE_STORAGE_BUFFER: return "StorageBuffer";
        case VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER: return "SampledTexture";
        case VK_DESCRIPTOR_TYPE_STORAGE_IMAGE: return "StorageImage";
        default: return "unsupported descriptor";
    }
}

VkDescriptorType toVkDescriptorType(ResourceType type) {
    switch (type) {
        case ResourceType::UniformBuffer: return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        case ResourceType::StorageBuffer: return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        case ResourceType::SampledTexture: return VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        case ResourceType::StorageImage: return VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    }
    return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
}

const char* viewTypeName(VkImageViewType type) {
    switch (type) {
        case VK_IMAGE_VIEW_TYPE_2D: return "2D";
        case VK_IMAGE_VIEW_TYPE_3D: return "3D";
        case VK_IMAGE_VIEW_TYPE_CUBE: return "cube";
        case VK_IMAGE_VIEW_TYPE_2D_ARRAY: return "2D array";
        case VK_IMAGE_VIEW_TYPE_CUBE_ARRAY: return "cube array";
        default: return "other";
    }
}

VkImageViewType toVkViewType(TextureDimension dim) {
    switch (dim) {
        case TextureDimension::Texture2D: return VK_IMAGE_VIEW_TYPE_2D;
        case TextureDimension::Texture3D: return VK_IMAGE_VIEW_TYPE_3D;
        case TextureDimension::TextureCube: return VK_IMAGE_VIEW_TYPE_CUBE;
        case TextureDimension::Texture2DArray: return VK_IMAGE_VIEW_TYPE_2D_ARRAY;
        case TextureDimension::TextureCubeArray: return VK_IMAGE_VIEW_TYPE_CUBE_ARRAY;
    }
    return VK_IMAGE_VIEW_TYPE_2D;
}

// The hazard-tracking keys of a view: exact for one mip, else whole mips (conservative).
KeyRange viewKeys(const ResolvedTextureView& view, TextureDimension textureDimension) {
    if (view.mipCount == 1 && textureDimension != TextureDimension::Texture3D)
        return {uint64_t(view.baseMip) << 32 | view.baseLayer, uint64_t(view.baseMip) << 32 | (view.baseLayer + view.layerCount)};
    return {uint64_t(view.baseMip) << 32, uint64_t(view.baseMip + view.mipCount) << 32};
}

// What a command using `item` through binding `b` reads or writes.
ResourceAccess accessOf(const BindingItem& item, const ReflectedBinding& b) {
    ResourceAccess access;
    access.stages = pipelineStagesOf(b.stages);
    access.write = b.written;
    switch (b.type) {
        case VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER:
        case VK_DESCRIPTOR_TYPE_STORAGE_BUFFER: {
            const uint64_t size = item.buffer->desc().size;
            access.resource = item.buffer.get();
            access.range = {item.offset, item.range ? item.offset + item.range : size};
            access.access = b.type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER ? VK_ACCESS_UNIFORM_READ_BIT
                            : b.written ? VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT
                                        : VK_ACCESS_SHADER_READ_BIT;
            break;
        }
        case VK_DESCRIPTOR_TYPE_STORAGE_IMAGE:
            access.resource = item.texture.get();
            access.range = viewKeys(resolveTextureView(item), item.texture->desc().dimension);
            access.access = b.written ? VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT : VK_ACCESS_SHADER_READ_BIT;
            break;
        case VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC:
            // Wherever its offsets move the window: all of the buffer from the item's offset on.
            // Wider than one draw's slice, it can add a barrier but never miss one, and rebinding
            // at another offset changes nothing the tracking saw.
            access.resource = item.buffer.get();
            access.range = {item.offset, item.buffer->desc().size};
            access.access = VK_ACCESS_UNIFORM_READ_BIT;
            break;
        default:   // sampled texture: every mip and layer of the view may be read
            access.resource = item.texture.get();
            access.range = viewKeys(resolveTextureView(item), item.texture->desc().dimension);
            access.access = VK_ACCESS_SHADER_READ_BIT;
            break;
    }
    return access;
}

}  // namespace

// `desc` is validated (rhi/src/validation.cpp); what is left is that its objects are this device's.
BindingSet::BindingSet(ContextPtr context, const BindingSetDesc& desc)
    : m_owner(context.get()), m_context(std::move(context)), m_desc(desc), m_dynamicWindows(dynamicWindowsOf(desc)) {
    for (const BindingItem& item : desc.items) {
        if (item.buffer) native<Buffer>(item.buffer, fmt::format("binding {}: the buffer", item.binding), m_context.get());
        if (item.texture) native<Texture>(item.texture, fmt::format("binding {}: the texture", item.binding), m_context.get());
        if (item.sampler) native<Sampler>(item.sampler, fmt::format("binding {}: the sampler", item.binding), m_context.get());
    }
}

BindingSet::~BindingSet() {
    if (m_firstUse.set) m_context->freeDescriptorSet({m_firstUse.pool, m_firstUse.set});
    for (auto& [layout, use] : m_otherUses) m_context->freeDescriptorSet({use->pool, use->set});
}

const BindingSet::LayoutUse& BindingSet::createOrFind(const DescriptorSetLayoutInfo& layout, uint32_t set,
                                                      std::string_view pipelineName) {
    std::lock_guard lock(m_mutex);
    if (m_firstUse.layout.load(std::memory_order_relaxed) == layout.layout) {
        m_last.store(&m_firstUse, std::memory_order_release);
        return m_firstUse;
    }
    if (auto it = m_otherUses.find(layout.layout); it != m_otherUses.end()) {
        m_last.store(it->second.get(), std::memory_order_release);
        return *it->second;
    }

    // Check everything before creating anything, so a failure leaves no half-written set.
    std::vector<const BindingItem*> items;
    for (const ReflectedBinding& b : layout.bindings) {
        auto item = std::find_if(m_desc.items.begin(), m_desc.items.end(),
                                 [&](const BindingItem& i) { return i.binding == b.binding; });
        if (item == m_desc.items.end())
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("the pipeline's shaders read set {} binding {} ('{}', {}), but the binding set "
                                    "bound to set {} has no item for binding {}",
                                    set, b.binding, b.name, typeName(b.type), set, b.binding));
        const bool dynamic = b.type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC;
        if (item->type == ResourceType::UniformBuffer && (dynamic || b.type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER))
            requireDynamicAgreement(*item, dynamic, pipelineName,
                                    fmt::format("set {} binding {} ('{}')", set, b.binding, b.name));
        if (toVkDescriptorType(item->type) != (dynamic ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : b.type))
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("set {} binding {} ('{}') is a {} in the shader but the binding set gives a {}", set,
                                    b.binding, b.name, typeName(b.type), typeName(toVkDescriptorType(item->type))));
        if (item->texture && toVkViewType(resolveTextureView(*item).dimension) != b.viewType)
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("set {} binding {} ('{}') is a {} image in the shader but the binding views {} "
                                    "texture '{}' as {}; match the shader's type or set BindingItem::viewDimension",
                                    set, b.binding, b.name, viewTypeName(b.viewType),
                                    toString(item->texture->desc().dimension), item->texture->desc().debugName,
                                    toString(resolveTextureView(*item).dimension)));
        const auto where = [&] { return fmt::format("set {} binding {} ('{}')", set, b.binding, b.name); };
        requireSamplerMatchesShader(*item, b.depthCompare, where);
        requireStorageFormatMatchesShader(*item, b.imageFormat, where);
        requireBufferCoversBlock(*item, b.blockSize, where);
        items.push_back(&*item);
    }

    // Filled in completely before it is published (m_firstUse.layout / the map / m_last).
    const Context::DescriptorAllocation allocation = m_context->allocateDescriptorSet(layout);

    // Stable storage for the infos the writes point at.
    std::vector<VkDescriptorBufferInfo> bufferInfos(items.size());
    std::vector<VkDescriptorImageInfo> imageInfos(items.size());
    std::vector<VkWriteDescriptorSet> writes;
    try {
        for (size_t i = 0; i < items.size(); ++i) {
            const BindingItem& item = *items[i];
            const ReflectedBinding& b = layout.bindings[i];
            VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
            write.dstSet = allocation.set;
            write.dstBinding = b.binding;
            write.descriptorCount = 1;
            write.descriptorType = b.type;
            if (item.buffer) {
                bufferInfos[i] = {static_cast<Buffer*>(item.buffer.get())->buffer, item.offset,
                                  item.range ? item.range : VK_WHOLE_SIZE};
                write.pBufferInfo = &bufferInfos[i];
            } else {
                auto* texture = static_cast<Texture*>(item.texture.get());
                const ResolvedTextureView v = resolveTextureView(item);
                // A volume's view has its one array layer (the slices are its depth).
                const bool volume = v.dimension == TextureDimension::Texture3D;
                const uint32_t baseLayer = volume ? 0 : v.baseLayer, layers = volume ? 1 : v.layerCount;
                if (b.type == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE) {
                    imageInfos[i] = {VK_NULL_HANDLE,
                                     texture->view(b.viewType, v.baseMip, 1, baseLayer, layers, VK_IMAGE_USAGE_STORAGE_BIT),
                                     VK_IMAGE_LAYOUT_GENERAL};
                } else {
                    imageInfos[i] = {static_cast<Sampler*>(item.sampler.get())->sampler,
                                     texture->view(b.viewType, v.baseMip, v.mipCount, baseLayer, layers,
                                                   VK_IMAGE_USAGE_SAMPLED_BIT),
                                     VK_IMAGE_LAYOUT_GENERAL};
                }
                write.pImageInfo = &imageInfos[i];
            }
            writes.push_back(write);
        }
    } catch (...) {
        m_context->freeDescriptorSet(allocation);
        throw;
    }
    vkUpdateDescriptorSets(m_context->device, uint32_t(writes.size()), writes.data(), 0, nullptr);
    LayoutUse* use = &m_firstUse;
    if (m_firstUse.layout.load(std::memory_order_relaxed))
        use = m_otherUses.emplace(layout.layout, std::make_unique<LayoutUse>()).first->second.get();
    use->set = allocation.set;
    use->pool = allocation.pool;
    for (const BindingItem* item : items)
        if (item->texture) use->textureItems.push_back(item);
    use->hasTextureItems = !use->textureItems.empty();
    for (size_t i = 0; i < items.size(); ++i) {
        if (layout.bindings[i].type != VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC) continue;
        use->dynamicOffsetIndex[use->dynamicCount++] = uint8_t(m_dynamicWindows.slotOf(uint32_t(items[i] - m_desc.items.data())));
    }
    use->plainBind = !use->hasTextureItems && use->dynamicCount == 0;
    use->offsetsAsGiven = use->dynamicCount == m_dynamicWindows.count;
    for (uint32_t i = 0; i < use->dynamicCount; ++i)
        use->offsetsAsGiven = use->offsetsAsGiven && use->dynamicOffsetIndex[i] == i;
    if (items.size() <= use->fewAccesses.size()) {
        for (size_t i = 0; i < items.size(); ++i) use->fewAccesses[i] = accessOf(*items[i], layout.bindings[i]);
        use->accesses = std::span(use->fewAccesses.data(), items.size());
    } else {
        for (size_t i = 0; i < items.size(); ++i) use->manyAccesses.push_back(accessOf(*items[i], layout.bindings[i]));
        use->accesses = use->manyAccesses;
    }
    // Not a dynamic one: the straight-line binds (bindInPass) pass no offsets.
    if (use->plainBind && use->accesses.size() == 1 && !use->accesses[0].write) {
        const ResourceAccess& read = use->accesses[0];
        assert(read.stages == layout.onlyBindingStages);   // what joinPassReads takes instead of reading it here
        use->onlyRead = {read.resource, read.range};
    }
    use->layout.store(layout.layout, std::memory_order_release);   // last: findUse and readers under the lock match on it
    m_last.store(use, std::memory_order_release);
    return *use;
}

// ---------------------------------------------------------------------------------------------
// Shared descriptor pools

namespace {
// A shared pool: this many sets, and this many descriptors of each type the RHI uses. A layout
// with more than kMostSharedDescriptors of one type gets a dedicated pool, so that a few large
// sets do not use up a shared pool the small ones fit in. A pool that runs out of one type is
// passed over (the next one, or a new one, takes the set).
constexpr uint32_t kSetsPerPool = 256;
constexpr uint32_t kDescriptorsPerType = 1024;
constexpr uint32_t kMostSharedDescriptors = 16;
constexpr VkDescriptorType kPooledTypes[] = {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC,
                                             VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                                             VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};

std::vector<VkDescriptorPoolSize> descriptorCounts(const DescriptorSetLayoutInfo& layout) {
    std::vector<VkDescriptorPoolSize> sizes;
    for (const ReflectedBinding& b : layout.bindings) {
        auto it = std::find_if(sizes.begin(), sizes.end(), [&](const auto& s) { return s.type == b.type; });
        if (it == sizes.end())
            sizes.push_back({b.type, b.count});
        else
            it->descriptorCount += b.count;
    }
    return sizes;
}
}  // namespace

Context::DescriptorAllocation Context::allocateDescriptorSet(const DescriptorSetLayoutInfo& layout) {
    std::vector<VkDescriptorPoolSize> needed = descriptorCounts(layout);
    const bool fitsShared = std::all_of(needed.begin(), needed.end(), [](const VkDescriptorPoolSize& s) {
        return std::find(std::begin(kPooledTypes), std::end(kPooledTypes), s.type) != std::end(kPooledTypes) &&
               s.descriptorCount <= kMostSharedDescriptors;
    });
    VkDescriptorSetAllocateInfo allocInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    allocInfo.descriptorSetCount = 1;
    allocInfo.pSetLayouts = &layout.layout;
    DescriptorAllocation allocation;

    std::lock_guard lock(m_descriptorMutex);   // pools need external synchronisation
    if (fitsShared) {
        // Newest first: older pools have room only where sets were freed.
        for (auto pool = m_descriptorPools.rbegin(); pool != m_descriptorPools.rend(); ++pool) {
            if (pool->dedicated || pool->liveSets == kSetsPerPool) continue;
            allocInfo.descriptorPool = pool->pool;
            const VkResult result = vkAllocateDescriptorSets(device, &allocInfo, &allocation.set);
            if (result == VK_SUCCESS) {
                ++pool->liveSets;
                allocation.pool = pool->pool;
                return allocation;
            }
            if (result != VK_ERROR_OUT_OF_POOL_MEMORY && result != VK_ERROR_FRAGMENTED_POOL)
                check(result, ErrorCode::OutOfMemory, "vkAllocateDescriptorSets");
        }
        needed.clear();
        for (VkDescriptorType type : kPooledTypes) needed.push_back({type, kDescriptorsPerType});
    }
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    poolInfo.maxSets = fitsShared ? kSetsPerPool : 1;
    poolInfo.poolSizeCount = uint32_t(needed.size());
    poolInfo.pPoolSizes = needed.data();
    DescriptorPool pool{VK_NULL_HANDLE, 1, !fitsShared};
    check(vkCreateDescriptorPool(device, &poolInfo, nullptr, &pool.pool), ErrorCode::OutOfMemory,
          "vkCreateDescriptorPool");
    allocInfo.descriptorPool = pool.pool;
    const VkResult result = vkAllocateDescriptorSets(device, &allocInfo, &allocation.set);
    if (result != VK_SUCCESS) {
        vkDestroyDescriptorPool(device, pool.pool, nullptr);
        check(result, ErrorCode::OutOfMemory, "vkAllocateDescriptorSets");
    }
    m_descriptorPools.push_back(pool);
    allocation.pool = pool.pool;
    return allocation;
}

void Context::freeDescriptorSet(const DescriptorAllocation& allocation) noexcept {
    std::lock_guard lock(m_descriptorMutex);
    auto pool = std::find_if(m_descriptorPools.begin(), m_descriptorPools.end(),
                             [&](const DescriptorPool& p) { return p.pool == allocation.pool; });
    if (pool == m_descriptorPools.end()) return;
    if (pool->dedicated) {
        vkDestroyDescriptorPool(device, pool->pool, nullptr);
        m_descriptorPools.erase(pool);
        return;
    }
    vkFreeDescriptorSets(device, pool->pool, 1, &allocation.set);   // returns VK_SUCCESS only
    --pool->liveSets;
}

}  // namespace janus::rhi::vulkan
