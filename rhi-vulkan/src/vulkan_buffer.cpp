// Buffers and host-visible staging buffers.
#include <fmt/format.h>

#include <cstring>

#include "vulkan_backend.h"

namespace janus::rhi::vulkan {

Buffer::Buffer(ContextPtr context, const BufferDesc& desc) : m_context(std::move(context)), m_desc(desc) {
    VkBufferUsageFlags usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    if (any(desc.usage, BufferUsage::Vertex)) usage |= VK_BUFFER_USAGE_VERTEX_BUFFER_BIT;
    if (any(desc.usage, BufferUsage::Index)) usage |= VK_BUFFER_USAGE_INDEX_BUFFER_BIT;
    if (any(desc.usage, BufferUsage::Uniform)) usage |= VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT;
    if (any(desc.usage, BufferUsage::Storage)) usage |= VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = desc.size;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    check(vkCreateBuffer(m_context->device, &info, nullptr, &buffer), ErrorCode::InvalidDescription,
          fmt::format("vkCreateBuffer for '{}' ({} bytes)", desc.debugName, desc.size));
    try {
        VkMemoryRequirements requirements;
        vkGetBufferMemoryRequirements(m_context->device, buffer, &requirements);
        VkMemoryPropertyFlags memoryFlags = 0;
        m_memory = m_context->allocate(requirements, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT,
                                       fmt::format("buffer '{}'", desc.debugName), &memoryFlags);
        check(vkBindBufferMemory(m_context->device, buffer, m_memory, 0), ErrorCode::OutOfMemory,
              "vkBindBufferMemory");
        zeroFill(requirements, memoryFlags);
    } catch (...) {
        if (m_memory) vkFreeMemory(m_context->device, m_memory, nullptr);
        vkDestroyBuffer(m_context->device, buffer, nullptr);
        throw;
    }
    m_context->setObjectName(VK_OBJECT_TYPE_BUFFER, uint64_t(buffer), desc.debugName);
}

// New buffers read as zero, as on GL, so results never depend on stale memory. Host-visible
// memory is cleared on the CPU (visible to the next submission); otherwise the GPU fills it.
void Buffer::zeroFill(const VkMemoryRequirements& requirements, VkMemoryPropertyFlags memoryFlags) {
    const VkMemoryPropertyFlags hostMemory = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    if ((memoryFlags & hostMemory) == hostMemory) {
        void* pointer = nullptr;
        check(vkMapMemory(m_context->device, m_memory, 0, VK_WHOLE_SIZE, 0, &pointer), ErrorCode::OutOfMemory,
              "vkMapMemory");
        std::memset(pointer, 0, requirements.size);
        vkUnmapMemory(m_context->device, m_memory);
    } else {
        m_context->submitAndWait([&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, buffer, 0, VK_WHOLE_SIZE, 0); });
    }
}

Buffer::~Buffer() {
    vkDestroyBuffer(m_context->device, buffer, nullptr);
    vkFreeMemory(m_context->device, m_memory, nullptr);
}

StagingBuffer::StagingBuffer(ContextPtr context, uint64_t bytes) : size(bytes), m_context(std::move(context)) {
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = bytes;
    info.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    check(vkCreateBuffer(m_context->device, &info, nullptr, &buffer), ErrorCode::OutOfMemory,
          fmt::format("vkCreateBuffer for a {}-byte staging buffer", bytes));
    try {
        VkMemoryRequirements requirements;
        vkGetBufferMemoryRequirements(m_context->device, buffer, &requirements);
        // Coherent so no flush/invalidate is needed around the memcpy.
        m_memory = m_context->allocate(requirements,
                                       VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                                       VK_MEMORY_PROPERTY_HOST_CACHED_BIT, "staging buffer");
        check(vkBindBufferMemory(m_context->device, buffer, m_memory, 0), ErrorCode::OutOfMemory,
              "vkBindBufferMemory");
        void* pointer = nullptr;
        check(vkMapMemory(m_context->device, m_memory, 0, VK_WHOLE_SIZE, 0, &pointer), ErrorCode::OutOfMemory,
              "vkMapMemory");
        mapped = static_cast<std::byte*>(pointer);
    } catch (...) {
        if (m_memory) vkFreeMemory(m_context->device, m_memory, nullptr);
        vkDestroyBuffer(m_context->device, buffer, nullptr);
        throw;
    }
}

StagingBuffer::~StagingBuffer() {
    vkDestroyBuffer(m_context->device, buffer, nullptr);
    vkFreeMemory(m_context->device, m_memory, nullptr);   // unmaps implicitly
}

}  // namespace janus::rhi::vulkan
