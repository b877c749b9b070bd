// The shared Context: errors, format tables, memory, immediate submissions, layout cache.
#include <fmt/format.h>

#include "vulkan_backend.h"

namespace janus::rhi::vulkan {

const char* resultName(VkResult result) {
    switch (result) {
        case VK_SUCCESS: return "VK_SUCCESS";
        case VK_NOT_READY: return "VK_NOT_READY";
        case VK_TIMEOUT: return "VK_TIMEOUT";
        case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
        case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
        case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
        case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
        case VK_ERROR_MEMORY_MAP_FAILED: return "VK_ERROR_MEMORY_MAP_FAILED";
        case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
        case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
        case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
        case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
        case VK_ERROR_TOO_MANY_OBJECTS: return "VK_ERROR_TOO_MANY_OBJECTS";
        case VK_ERROR_FORMAT_NOT_SUPPORTED: return "VK_ERROR_FORMAT_NOT_SUPPORTED";
        case VK_ERROR_FRAGMENTED_POOL: return "VK_ERROR_FRAGMENTED_POOL";
        case VK_ERROR_OUT_OF_POOL_MEMORY: return "VK_ERROR_OUT_OF_POOL_MEMORY";
        case VK_ERROR_INVALID_SHADER_NV: return "VK_ERROR_INVALID_SHADER_NV";
        default: return "VkResult(other)";
    }
}

void check(VkResult result, ErrorCode code, std::string_view what) {
    if (result == VK_SUCCESS) return;
    if (result == VK_ERROR_OUT_OF_HOST_MEMORY || result == VK_ERROR_OUT_OF_DEVICE_MEMORY)
        code = ErrorCode::OutOfMemory;
    else if (result == VK_ERROR_DEVICE_LOST)
        code = ErrorCode::DeviceLost;
    throw Error(code, fmt::format("{} failed with {} ({})", what, resultName(result), int(result)));
}

VkFormat toVkFormat(Format format) {
    switch (format) {
        case Format::RGBA8_UNORM: return VK_FORMAT_R8G8B8A8_UNORM;
        case Format::RGBA8_SRGB: return VK_FORMAT_R8G8B8A8_SRGB;
        case Format::RGBA16_FLOAT: return VK_FORMAT_R16G16B16A16_SFLOAT;
        case Format::RGBA32_FLOAT: return VK_FORMAT_R32G32B32A32_SFLOAT;
        case Format::R11G11B10_FLOAT: return VK_FORMAT_B10G11R11_UFLOAT_PACK32;
        case Format::R32_UINT: return VK_FORMAT_R32_UINT;
        case Format::RGBA32_UINT: return VK_FORMAT_R32G32B32A32_UINT;
        case Format::R32_FLOAT: return VK_FORMAT_R32_SFLOAT;
        case Format::D32_FLOAT: return VK_FORMAT_D32_SFLOAT;
        case Format::Unknown: break;
    }
    return VK_FORMAT_UNDEFINED;
}

VkCompareOp toVkCompareOp(CompareOp op) {
    switch (op) {
        case CompareOp::Never: return VK_COMPARE_OP_NEVER;
        case CompareOp::Less: return VK_COMPARE_OP_LESS;
        case CompareOp::Equal: return VK_COMPARE_OP_EQUAL;
        case CompareOp::LessOrEqual: return VK_COMPARE_OP_LESS_OR_EQUAL;
        case CompareOp::Greater: return VK_COMPARE_OP_GREATER;
        case CompareOp::NotEqual: return VK_COMPARE_OP_NOT_EQUAL;
        case CompareOp::GreaterOrEqual: return VK_COMPARE_OP_GREATER_OR_EQUAL;
        case CompareOp::Always: return VK_COMPARE_OP_ALWAYS;
    }
    return VK_COMPARE_OP_ALWAYS;
}

VkImageAspectFlags aspectOf(Format format) {
    return isDepthFormat(format) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
}

void fullBarrier(VkCommandBuffer cmd) {
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1, &barrier,
                         0, nullptr, 0, nullptr);
}

// Makes all device writes visible to the host once the submission's fence has signalled.
void throwNotThisBackend(bool null, std::string_view what) {
    throw Error(ErrorCode::InvalidUsage, std::string(what) + (null ? " is null" : " was not created by a Vulkan device"));
}

void throwOtherDevice(std::string_view what) {
    throw Error(ErrorCode::InvalidUsage,
                std::string(what) + " was created by another device; use resources of this device");
}

void hostBarrier(VkCommandBuffer cmd) {
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT | VK_ACCESS_HOST_WRITE_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0,
                         nullptr, 0, nullptr);
}

Context::~Context() {
    if (device) {
        vkDeviceWaitIdle(device);
        for (const DescriptorPool& pool : m_descriptorPools) vkDestroyDescriptorPool(device, pool.pool, nullptr);
        for (auto& [key, info] : m_layouts) vkDestroyDescriptorSetLayout(device, info->layout, nullptr);
        if (immediateFence) vkDestroyFence(device, immediateFence, nullptr);
        if (immediatePool) vkDestroyCommandPool(device, immediatePool, nullptr);
        vkDestroyDevice(device, nullptr);
    }
    if (messenger && destroyMessenger) destroyMessenger(instance, messenger, nullptr);
    if (instance) vkDestroyInstance(instance, nullptr);
}

void Context::addMessage(DebugMessage message) {
    std::function<void(const DebugMessage&)> callback;
    {
        std::lock_guard lock(messageMutex);
        (message.severity == MessageSeverity::Performance ? performanceMessages : messages).push_back(message);
        callback = messageCallback;
    }
    if (callback) callback(message);
}

void Context::submitAndWait(const std::function<void(VkCommandBuffer)>& record) {
    std::lock_guard lock(queueMutex);
    check(vkResetCommandPool(device, immediatePool, 0), ErrorCode::DeviceLost, "vkResetCommandPool");
    VkCommandBufferBeginInfo beginInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    beginInfo.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(immediateCommands, &beginInfo), ErrorCode::DeviceLost, "vkBeginCommandBuffer");
    fullBarrier(immediateCommands);
    record(immediateCommands);
    hostBarrier(immediateCommands);
    check(vkEndCommandBuffer(immediateCommands), ErrorCode::DeviceLost, "vkEndCommandBuffer");

    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &immediateCommands;
    check(vkResetFences(device, 1, &immediateFence), ErrorCode::DeviceLost, "vkResetFences");
    check(vkQueueSubmit(queue, 1, &submit, immediateFence), ErrorCode::DeviceLost, "vkQueueSubmit");
    check(vkWaitForFences(device, 1, &immediateFence, VK_TRUE, UINT64_MAX), ErrorCode::DeviceLost,
          "vkWaitForFences");
}

void Context::waitIdle() {
    std::lock_guard lock(queueMutex);
    check(vkQueueWaitIdle(queue), ErrorCode::DeviceLost, "vkQueueWaitIdle");
    finishedSubmissions.store(lastSubmission, std::memory_order_release);
}

VkDeviceMemory Context::allocate(const VkMemoryRequirements& requirements, VkMemoryPropertyFlags required,
                                 VkMemoryPropertyFlags preferred, std::string_view what,
                                 VkMemoryPropertyFlags* chosen) {
    auto pick = [&](VkMemoryPropertyFlags flags) -> int {
        for (uint32_t i = 0; i < memoryProperties.memoryTypeCount; ++i)
            if ((requirements.memoryTypeBits & (1u << i)) &&
                (memoryProperties.memoryTypes[i].propertyFlags & flags) == flags)
                return int(i);
        return -1;
    };
    int type = pick(required | preferred);
    if (type < 0) type = pick(required);
    if (type < 0)
        throw Error(ErrorCode::OutOfMemory,
                    fmt::format("{}: the device has no memory type with properties 0x{:x} for it", what, required));
    VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    info.allocationSize = requirements.size;
    info.memoryTypeIndex = uint32_t(type);
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkResult result = vkAllocateMemory(device, &info, nullptr, &memory);
    if (result != VK_SUCCESS)
        throw Error(ErrorCode::OutOfMemory, fmt::format("{}: vkAllocateMemory of {} bytes failed with {}; "
                                                        "free resources or make it smaller",
                                                        what, requirements.size, resultName(result)));
    if (chosen) *chosen = memoryProperties.memoryTypes[type].propertyFlags;
    return memory;
}

void Context::setObjectName(VkObjectType type, uint64_t handle, const std::string& name) {
    if (!setDebugObjectName || name.empty()) return;
    VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
    info.objectType = type;
    info.objectHandle = handle;
    info.pObjectName = name.c_str();
    setDebugObjectName(device, &info);
}

VkFormatProperties Context::formatProperties(Format format) const {
    VkFormatProperties props{};
    vkGetPhysicalDeviceFormatProperties(physicalDevice, toVkFormat(format), &props);
    return props;
}

const DescriptorSetLayoutInfo& Context::descriptorSetLayout(const std::vector<ReflectedBinding>& bindings) {
    std::string key;
    for (const auto& b : bindings)
        key += fmt::format("{}:{}:{}:{}:{}:{}:{}:{}:{};", b.binding, int(b.type), b.count, b.stages, int(b.viewType),
                          b.written,   // written: the binding sets' hazard tracking reads it
                          b.depthCompare, b.imageFormat, b.blockSize);   // BindingSet::createOrFind checks items against them
    std::lock_guard lock(m_layoutMutex);
    if (auto it = m_layouts.find(key); it != m_layouts.end()) return *it->second;

    std::vector<VkDescriptorSetLayoutBinding> vkBindings;
    for (const auto& b : bindings) vkBindings.push_back({b.binding, b.type, b.count, b.stages, nullptr});
    VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    info.bindingCount = uint32_t(vkBindings.size());
    info.pBindings = vkBindings.data();
    auto result = std::make_unique<DescriptorSetLayoutInfo>();
    result->bindings = bindings;
    if (bindings.size() == 1) result->onlyBindingStages = pipelineStagesOf(bindings[0].stages);
    check(vkCreateDescriptorSetLayout(device, &info, nullptr, &result->layout), ErrorCode::InvalidDescription,
          "vkCreateDescriptorSetLayout");
    return *m_layouts.emplace(key, std::move(result)).first->second;
}

}  // namespace janus::rhi::vulkan
