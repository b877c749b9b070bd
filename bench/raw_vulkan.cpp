// The raw Vulkan side: the same workload written directly against Vulkan 1.3, the way an
// application without an RHI would write it (everything created up front, one descriptor set per
// draw/dispatch, a command buffer re-recorded per frame, submit + fence wait).
#include <fmt/format.h>
#include <janus/shaders/shaders.h>
#include <vulkan/vulkan.h>

#include <cstring>
#include <iterator>
#include <string>
#include <vector>

#include "null_driver.h"
#include "rhi_scene.h"
#include "vulkan_command_memory.h"

namespace janus::bench {
namespace {

void check(VkResult result, const char* what) {
    if (result != VK_SUCCESS) throw std::runtime_error(fmt::format("raw Vulkan: {} failed ({})", what, int(result)));
}

struct HostBuffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    void* mapped = nullptr;
};

class RawVulkan final : public Environment {
public:
    // Picks the physical device the RHI picked (by name), so both sides run on the same driver.
    explicit RawVulkan(const std::string& deviceName);
    ~RawVulkan() override;

    // Which command pool the next frames record into: one with the driver's own host memory (what
    // an application without an RHI usually has), or one whose host memory comes from the RHI's
    // CommandMemory (an explanatory run: the RHI's recording with the allocator's effect removed).
    void useCommandMemory(bool recycled) {
        m_pool = m_pools[recycled];
        m_commands = m_commandBuffers[recycled];
    }
    // How the next frames draw: as an application would, or with the RHI's choices that reach the
    // driver (RawVulkanDraws::RhiChoices, which also records into the RHI's command memory).
    void recordAs(RawVulkanDraws how) {
        m_rhiChoices = how == RawVulkanDraws::RhiChoices;
        m_nullDriver = how == RawVulkanDraws::NullDriver;
        useCommandMemory(how == RawVulkanDraws::CommandMemory || how == RawVulkanDraws::RhiChoices);
    }
    // The NullDriver kinds' per-operation calls: what NullVulkanDriver and NullVulkanDispatchDriver
    // point them at.
    PFN_vkCmdBindDescriptorSets nullBind = nullptr;
    PFN_vkCmdDraw nullDraw = nullptr;
    PFN_vkCmdDispatch nullDispatch = nullptr;
    void submitDraws(DrawSlices slices = DrawSlices::PerDrawSets);
    void submitDispatches(RawVulkanDispatches how = RawVulkanDispatches::Plain);
    void wait() { check(vkWaitForFences(m_device, 1, &m_fence, VK_TRUE, UINT64_MAX), "vkWaitForFences"); }
    void checkDraws();
    void checkDispatches();

private:
    void createDevice(const std::string& deviceName);
    HostBuffer createHostBuffer(VkDeviceSize size, VkBufferUsageFlags usage);
    uint32_t memoryType(uint32_t allowedTypes, VkMemoryPropertyFlags flags) const;
    VkShaderModule createShaderModule(const char* name);
    void createTarget();
    void createDrawPipeline();
    void createComputePipeline();
    std::vector<VkDescriptorSet> allocateSets(VkDescriptorSetLayout layout, VkDescriptorType type, VkBuffer buffer);
    void beginFrame();
    void submitFrame();

    VkInstance m_instance = VK_NULL_HANDLE;
    VkPhysicalDevice m_physicalDevice = VK_NULL_HANDLE;
    VkDevice m_device = VK_NULL_HANDLE;
    VkQueue m_queue = VK_NULL_HANDLE;
    uint32_t m_queueFamily = 0;
    rhi::vulkan::CommandMemory m_commandMemory;
    VkCommandPool m_pools[2] = {};            // [0] driver memory, [1] m_commandMemory
    VkCommandBuffer m_commandBuffers[2] = {};
    VkCommandPool m_pool = VK_NULL_HANDLE;    // the one in use
    VkCommandBuffer m_commands = VK_NULL_HANDLE;
    VkFence m_fence = VK_NULL_HANDLE;
    VkDescriptorPool m_descriptorPool = VK_NULL_HANDLE;

    VkImage m_target = VK_NULL_HANDLE;
    VkDeviceMemory m_targetMemory = VK_NULL_HANDLE;
    VkImageView m_targetView = VK_NULL_HANDLE;
    HostBuffer m_vertices, m_drawParameters, m_readback;
    VkDescriptorSetLayout m_drawSetLayout = VK_NULL_HANDLE;
    VkPipelineLayout m_drawLayout = VK_NULL_HANDLE;
    VkPipeline m_drawPipeline = VK_NULL_HANDLE;
    // RawVulkanDraws::RhiChoices: the RHI's pipeline layout (set 0 and three empty set layouts,
    // vulkan_pipeline.cpp), a pipeline made with it, and command buffers begun without
    // ONE_TIME_SUBMIT (an RHI command list may be executed again).
    bool m_rhiChoices = false;
    bool m_nullDriver = false;
    VkDescriptorSetLayout m_emptySetLayout = VK_NULL_HANDLE;
    VkPipelineLayout m_drawLayoutAsRhi = VK_NULL_HANDLE;
    VkPipeline m_drawPipelineAsRhi = VK_NULL_HANDLE;
    std::vector<VkDescriptorSet> m_drawSets;
    // DrawSlices::DynamicOffsets: one set whose UNIFORM_BUFFER_DYNAMIC window moves per draw (as an
    // application would have it: one set layout, its pipeline layout and pipeline).
    VkDescriptorSetLayout m_dynamicSetLayout = VK_NULL_HANDLE;
    VkPipelineLayout m_dynamicLayout = VK_NULL_HANDLE;
    VkPipeline m_dynamicPipeline = VK_NULL_HANDLE;
    VkDescriptorSet m_dynamicSet = VK_NULL_HANDLE;

    HostBuffer m_counters;
    VkDescriptorSetLayout m_counterSetLayout = VK_NULL_HANDLE;
    VkPipelineLayout m_computeLayout = VK_NULL_HANDLE;
    VkPipeline m_computePipeline = VK_NULL_HANDLE;
    VkPipelineLayout m_computeLayoutAsRhi = VK_NULL_HANDLE;   // as m_drawLayoutAsRhi
    VkPipeline m_computePipelineAsRhi = VK_NULL_HANDLE;
    std::vector<VkDescriptorSet> m_counterSets;
    uint32_t m_dispatchFrames = 0;
};

RawVulkan::RawVulkan(const std::string& deviceName) {
    createDevice(deviceName);

    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.queueFamilyIndex = m_queueFamily;
    for (int recycled : {0, 1}) {
        check(vkCreateCommandPool(m_device, &poolInfo, recycled ? m_commandMemory.callbacks() : nullptr,
                                  &m_pools[recycled]),
              "vkCreateCommandPool");
        VkCommandBufferAllocateInfo allocInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        allocInfo.commandPool = m_pools[recycled];
        allocInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        allocInfo.commandBufferCount = 1;
        check(vkAllocateCommandBuffers(m_device, &allocInfo, &m_commandBuffers[recycled]), "vkAllocateCommandBuffers");
    }
    useCommandMemory(false);
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    check(vkCreateFence(m_device, &fenceInfo, nullptr, &m_fence), "vkCreateFence");

    const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, opsPerFrame()},
                                          {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, opsPerFrame()},
                                          {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1}};
    VkDescriptorPoolCreateInfo descriptorPoolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    descriptorPoolInfo.maxSets = 2 * opsPerFrame() + 1;
    descriptorPoolInfo.poolSizeCount = 3;
    descriptorPoolInfo.pPoolSizes = sizes;
    check(vkCreateDescriptorPool(m_device, &descriptorPoolInfo, nullptr, &m_descriptorPool), "vkCreateDescriptorPool");

    createTarget();
    createDrawPipeline();
    createComputePipeline();

    // One untimed frame of each kind, checked, as on the RHI side.
    for (const RawVulkanDraws how : {RawVulkanDraws::RhiChoices, RawVulkanDraws::Plain}) {
        recordAs(how);
        submitDraws();
        wait();
        checkDraws();
    }
    submitDraws(DrawSlices::DynamicOffsets);
    wait();
    checkDraws();
    submitDispatches();
    wait();
    checkDispatches();
}

RawVulkan::~RawVulkan() {
    if (!m_device) {
        if (m_instance) vkDestroyInstance(m_instance, nullptr);
        return;
    }
    vkDeviceWaitIdle(m_device);
    for (HostBuffer* b : {&m_vertices, &m_drawParameters, &m_readback, &m_counters}) {
        vkDestroyBuffer(m_device, b->buffer, nullptr);
        vkFreeMemory(m_device, b->memory, nullptr);
    }
    vkDestroyPipeline(m_device, m_drawPipeline, nullptr);
    vkDestroyPipeline(m_device, m_dynamicPipeline, nullptr);
    vkDestroyPipelineLayout(m_device, m_dynamicLayout, nullptr);
    vkDestroyDescriptorSetLayout(m_device, m_dynamicSetLayout, nullptr);
    vkDestroyPipeline(m_device, m_drawPipelineAsRhi, nullptr);
    vkDestroyPipelineLayout(m_device, m_drawLayoutAsRhi, nullptr);
    vkDestroyDescriptorSetLayout(m_device, m_emptySetLayout, nullptr);
    vkDestroyPipeline(m_device, m_computePipeline, nullptr);
    vkDestroyPipeline(m_device, m_computePipelineAsRhi, nullptr);
    vkDestroyPipelineLayout(m_device, m_computeLayoutAsRhi, nullptr);
    vkDestroyPipelineLayout(m_device, m_drawLayout, nullptr);
    vkDestroyPipelineLayout(m_device, m_computeLayout, nullptr);
    vkDestroyDescriptorSetLayout(m_device, m_drawSetLayout, nullptr);
    vkDestroyDescriptorSetLayout(m_device, m_counterSetLayout, nullptr);
    vkDestroyDescriptorPool(m_device, m_descriptorPool, nullptr);
    vkDestroyImageView(m_device, m_targetView, nullptr);
    vkDestroyImage(m_device, m_target, nullptr);
    vkFreeMemory(m_device, m_targetMemory, nullptr);
    vkDestroyFence(m_device, m_fence, nullptr);
    vkDestroyCommandPool(m_device, m_pools[0], nullptr);
    if (m_pools[1]) vkDestroyCommandPool(m_device, m_pools[1], m_commandMemory.callbacks());
    vkDestroyDevice(m_device, nullptr);
    vkDestroyInstance(m_instance, nullptr);
}

void RawVulkan::createDevice(const std::string& deviceName) {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "janus_bench_rhi (raw Vulkan)";
    app.apiVersion = VK_API_VERSION_1_3;
    VkInstanceCreateInfo instanceInfo{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    instanceInfo.pApplicationInfo = &app;
    // Without a debug messenger the layer prints its messages to stdout; JANUS_BENCH_VALIDATE is
    // for checking the benchmark by eye, never for timing.
    const char* layer = "VK_LAYER_KHRONOS_validation";
    if (validationRequested()) {
        instanceInfo.enabledLayerCount = 1;
        instanceInfo.ppEnabledLayerNames = &layer;
    }
    check(vkCreateInstance(&instanceInfo, nullptr, &m_instance), "vkCreateInstance");

    uint32_t count = 0;
    vkEnumeratePhysicalDevices(m_instance, &count, nullptr);
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(m_instance, &count, devices.data());
    for (VkPhysicalDevice candidate : devices) {
        VkPhysicalDeviceProperties properties;
        vkGetPhysicalDeviceProperties(candidate, &properties);
        if (deviceName == properties.deviceName && properties.apiVersion >= VK_API_VERSION_1_3) m_physicalDevice = candidate;
    }
    if (!m_physicalDevice)
        throw std::runtime_error(fmt::format("raw Vulkan: no Vulkan 1.3 device named '{}' (the RHI's device)", deviceName));

    vkGetPhysicalDeviceQueueFamilyProperties(m_physicalDevice, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(m_physicalDevice, &count, families.data());
    constexpr VkQueueFlags kNeeded = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    while (m_queueFamily < count && (families[m_queueFamily].queueFlags & kNeeded) != kNeeded) ++m_queueFamily;
    if (m_queueFamily == count) throw std::runtime_error("raw Vulkan: no graphics + compute queue family");

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queueInfo.queueFamilyIndex = m_queueFamily;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;
    VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    features13.dynamicRendering = VK_TRUE;
    VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    deviceInfo.pNext = &features13;
    deviceInfo.queueCreateInfoCount = 1;
    deviceInfo.pQueueCreateInfos = &queueInfo;
    check(vkCreateDevice(m_physicalDevice, &deviceInfo, nullptr, &m_device), "vkCreateDevice");
    vkGetDeviceQueue(m_device, m_queueFamily, 0, &m_queue);
}

uint32_t RawVulkan::memoryType(uint32_t allowedTypes, VkMemoryPropertyFlags flags) const {
    VkPhysicalDeviceMemoryProperties properties;
    vkGetPhysicalDeviceMemoryProperties(m_physicalDevice, &properties);
    for (uint32_t i = 0; i < properties.memoryTypeCount; ++i)
        if ((allowedTypes & (1u << i)) && (properties.memoryTypes[i].propertyFlags & flags) == flags) return i;
    throw std::runtime_error("raw Vulkan: no suitable memory type");
}

HostBuffer RawVulkan::createHostBuffer(VkDeviceSize size, VkBufferUsageFlags usage) {
    HostBuffer result;
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = size;
    info.usage = usage;
    check(vkCreateBuffer(m_device, &info, nullptr, &result.buffer), "vkCreateBuffer");
    VkMemoryRequirements requirements;
    vkGetBufferMemoryRequirements(m_device, result.buffer, &requirements);
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = requirements.size;
    alloc.memoryTypeIndex = memoryType(requirements.memoryTypeBits,
                                       VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    check(vkAllocateMemory(m_device, &alloc, nullptr, &result.memory), "vkAllocateMemory");
    check(vkBindBufferMemory(m_device, result.buffer, result.memory, 0), "vkBindBufferMemory");
    check(vkMapMemory(m_device, result.memory, 0, VK_WHOLE_SIZE, 0, &result.mapped), "vkMapMemory");
    return result;
}

VkShaderModule RawVulkan::createShaderModule(const char* name) {
    const std::span<const uint32_t> spirv = shaders::get(name);
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = spirv.size_bytes();
    info.pCode = spirv.data();
    VkShaderModule module = VK_NULL_HANDLE;
    check(vkCreateShaderModule(m_device, &info, nullptr, &module), "vkCreateShaderModule");
    return module;
}

void RawVulkan::createTarget() {
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = VK_FORMAT_R8G8B8A8_UNORM;
    info.extent = {kTargetSize, kTargetSize, 1};
    info.mipLevels = 1;
    info.arrayLayers = 1;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    check(vkCreateImage(m_device, &info, nullptr, &m_target), "vkCreateImage");
    VkMemoryRequirements requirements;
    vkGetImageMemoryRequirements(m_device, m_target, &requirements);
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = requirements.size;
    alloc.memoryTypeIndex = memoryType(requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    check(vkAllocateMemory(m_device, &alloc, nullptr, &m_targetMemory), "vkAllocateMemory");
    check(vkBindImageMemory(m_device, m_target, m_targetMemory, 0), "vkBindImageMemory");
    VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    viewInfo.image = m_target;
    viewInfo.viewType = VK_IMAGE_VIEW_TYPE_2D;
    viewInfo.format = info.format;
    viewInfo.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    check(vkCreateImageView(m_device, &viewInfo, nullptr, &m_targetView), "vkCreateImageView");
    m_readback = createHostBuffer(kTargetSize * kTargetSize * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
}

std::vector<VkDescriptorSet> RawVulkan::allocateSets(VkDescriptorSetLayout layout, VkDescriptorType type,
                                                     VkBuffer buffer) {
    const std::vector<VkDescriptorSetLayout> layouts(opsPerFrame(), layout);
    std::vector<VkDescriptorSet> sets(opsPerFrame());
    VkDescriptorSetAllocateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    info.descriptorPool = m_descriptorPool;
    info.descriptorSetCount = opsPerFrame();
    info.pSetLayouts = layouts.data();
    check(vkAllocateDescriptorSets(m_device, &info, sets.data()), "vkAllocateDescriptorSets");
    std::vector<VkDescriptorBufferInfo> buffers(opsPerFrame());
    std::vector<VkWriteDescriptorSet> writes(opsPerFrame());
    for (uint32_t i = 0; i < opsPerFrame(); ++i) {
        buffers[i] = {buffer, i * kSliceBytes, kSliceBytes};
        writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        writes[i].dstSet = sets[i];
        writes[i].dstBinding = 0;
        writes[i].descriptorCount = 1;
        writes[i].descriptorType = type;
        writes[i].pBufferInfo = &buffers[i];
    }
    vkUpdateDescriptorSets(m_device, opsPerFrame(), writes.data(), 0, nullptr);
    return sets;
}

void RawVulkan::createDrawPipeline() {
    m_vertices = createHostBuffer(sizeof(kTriangle), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    std::memcpy(m_vertices.mapped, kTriangle.data(), sizeof(kTriangle));
    m_drawParameters = createHostBuffer(slicedBufferBytes(), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
    const std::vector<std::byte> parameters = drawParameterData();
    std::memcpy(m_drawParameters.mapped, parameters.data(), parameters.size());

    VkDescriptorSetLayoutBinding binding{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr};
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.bindingCount = 1;
    setInfo.pBindings = &binding;
    check(vkCreateDescriptorSetLayout(m_device, &setInfo, nullptr, &m_drawSetLayout), "vkCreateDescriptorSetLayout");
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.setLayoutCount = 1;
    layoutInfo.pSetLayouts = &m_drawSetLayout;
    check(vkCreatePipelineLayout(m_device, &layoutInfo, nullptr, &m_drawLayout), "vkCreatePipelineLayout");
    VkDescriptorSetLayoutCreateInfo emptyInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    check(vkCreateDescriptorSetLayout(m_device, &emptyInfo, nullptr, &m_emptySetLayout), "vkCreateDescriptorSetLayout");
    const VkDescriptorSetLayout rhiLayouts[] = {m_drawSetLayout, m_emptySetLayout, m_emptySetLayout, m_emptySetLayout};
    layoutInfo.setLayoutCount = uint32_t(std::size(rhiLayouts));
    layoutInfo.pSetLayouts = rhiLayouts;
    check(vkCreatePipelineLayout(m_device, &layoutInfo, nullptr, &m_drawLayoutAsRhi), "vkCreatePipelineLayout");
    m_drawSets = allocateSets(m_drawSetLayout, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, m_drawParameters.buffer);

    VkDescriptorSetLayoutBinding dynamicBinding{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1,
                                                VK_SHADER_STAGE_FRAGMENT_BIT, nullptr};
    setInfo.pBindings = &dynamicBinding;
    check(vkCreateDescriptorSetLayout(m_device, &setInfo, nullptr, &m_dynamicSetLayout), "vkCreateDescriptorSetLayout");
    layoutInfo.setLayoutCount = 1;
    layoutInfo.pSetLayouts = &m_dynamicSetLayout;
    check(vkCreatePipelineLayout(m_device, &layoutInfo, nullptr, &m_dynamicLayout), "vkCreatePipelineLayout");
    VkDescriptorSetAllocateInfo allocInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    allocInfo.descriptorPool = m_descriptorPool;
    allocInfo.descriptorSetCount = 1;
    allocInfo.pSetLayouts = &m_dynamicSetLayout;
    check(vkAllocateDescriptorSets(m_device, &allocInfo, &m_dynamicSet), "vkAllocateDescriptorSets");
    const VkDescriptorBufferInfo window{m_drawParameters.buffer, 0, kSliceBytes};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = m_dynamicSet;
    write.descriptorCount = 1;
    write.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC;
    write.pBufferInfo = &window;
    vkUpdateDescriptorSets(m_device, 1, &write, 0, nullptr);

    VkShaderModule vertex = createShaderModule("bench_triangle_vert");
    VkShaderModule fragment = createShaderModule("bench_uniform_color_frag");
    VkPipelineShaderStageCreateInfo stages[2] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                                 {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
    stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
    stages[0].module = vertex;
    stages[0].pName = "main";
    stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
    stages[1].module = fragment;
    stages[1].pName = "main";

    const VkVertexInputBindingDescription vertexBinding{0, sizeof(float) * 2, VK_VERTEX_INPUT_RATE_VERTEX};
    const VkVertexInputAttributeDescription attribute{0, 0, VK_FORMAT_R32G32_SFLOAT, 0};
    VkPipelineVertexInputStateCreateInfo vertexInput{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    vertexInput.vertexBindingDescriptionCount = 1;
    vertexInput.pVertexBindingDescriptions = &vertexBinding;
    vertexInput.vertexAttributeDescriptionCount = 1;
    vertexInput.pVertexAttributeDescriptions = &attribute;
    VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;
    raster.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    VkPipelineColorBlendAttachmentState blendAttachment{};
    blendAttachment.colorWriteMask = 0xF;
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = 1;
    blend.pAttachments = &blendAttachment;
    const VkDynamicState dynamicStates[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dynamic.dynamicStateCount = 2;
    dynamic.pDynamicStates = dynamicStates;
    const VkFormat colorFormat = VK_FORMAT_R8G8B8A8_UNORM;
    VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachmentFormats = &colorFormat;

    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    info.pNext = &rendering;
    info.stageCount = 2;
    info.pStages = stages;
    info.pVertexInputState = &vertexInput;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = m_drawLayout;
    VkResult result = vkCreateGraphicsPipelines(m_device, VK_NULL_HANDLE, 1, &info, nullptr, &m_drawPipeline);
    if (result == VK_SUCCESS) {
        info.layout = m_drawLayoutAsRhi;
        result = vkCreateGraphicsPipelines(m_device, VK_NULL_HANDLE, 1, &info, nullptr, &m_drawPipelineAsRhi);
    }
    if (result == VK_SUCCESS) {
        info.layout = m_dynamicLayout;
        result = vkCreateGraphicsPipelines(m_device, VK_NULL_HANDLE, 1, &info, nullptr, &m_dynamicPipeline);
    }
    vkDestroyShaderModule(m_device, vertex, nullptr);
    vkDestroyShaderModule(m_device, fragment, nullptr);
    check(result, "vkCreateGraphicsPipelines");
}

void RawVulkan::createComputePipeline() {
    m_counters = createHostBuffer(slicedBufferBytes(), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    std::memset(m_counters.mapped, 0, slicedBufferBytes());

    VkDescriptorSetLayoutBinding binding{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.bindingCount = 1;
    setInfo.pBindings = &binding;
    check(vkCreateDescriptorSetLayout(m_device, &setInfo, nullptr, &m_counterSetLayout), "vkCreateDescriptorSetLayout");
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.setLayoutCount = 1;
    layoutInfo.pSetLayouts = &m_counterSetLayout;
    check(vkCreatePipelineLayout(m_device, &layoutInfo, nullptr, &m_computeLayout), "vkCreatePipelineLayout");
    const VkDescriptorSetLayout rhiLayouts[] = {m_counterSetLayout, m_emptySetLayout, m_emptySetLayout, m_emptySetLayout};
    layoutInfo.setLayoutCount = uint32_t(std::size(rhiLayouts));
    layoutInfo.pSetLayouts = rhiLayouts;
    check(vkCreatePipelineLayout(m_device, &layoutInfo, nullptr, &m_computeLayoutAsRhi), "vkCreatePipelineLayout");
    m_counterSets = allocateSets(m_counterSetLayout, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, m_counters.buffer);

    VkShaderModule module = createShaderModule("bench_increment_comp");
    VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = module;
    info.stage.pName = "main";
    info.layout = m_computeLayout;
    VkResult result = vkCreateComputePipelines(m_device, VK_NULL_HANDLE, 1, &info, nullptr, &m_computePipeline);
    if (result == VK_SUCCESS) {
        info.layout = m_computeLayoutAsRhi;
        result = vkCreateComputePipelines(m_device, VK_NULL_HANDLE, 1, &info, nullptr, &m_computePipelineAsRhi);
    }
    vkDestroyShaderModule(m_device, module, nullptr);
    check(result, "vkCreateComputePipelines");
}

void memoryBarrier(VkCommandBuffer commands, VkPipelineStageFlags from, VkAccessFlags fromAccess,
                   VkPipelineStageFlags to, VkAccessFlags toAccess) {
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = fromAccess;
    barrier.dstAccessMask = toAccess;
    vkCmdPipelineBarrier(commands, from, to, 0, 1, &barrier, 0, nullptr, 0, nullptr);
}

void RawVulkan::beginFrame() {
    check(vkResetCommandPool(m_device, m_pool, 0), "vkResetCommandPool");
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = m_rhiChoices ? 0 : VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(m_commands, &begin), "vkBeginCommandBuffer");
}

void RawVulkan::submitFrame() {
    // The host reads results after the fence; same as the RHI's end-of-list barrier.
    memoryBarrier(m_commands, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                  VK_ACCESS_HOST_READ_BIT);
    check(vkEndCommandBuffer(m_commands), "vkEndCommandBuffer");
    check(vkResetFences(m_device, 1, &m_fence), "vkResetFences");
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &m_commands;
    check(vkQueueSubmit(m_queue, 1, &submit, m_fence), "vkQueueSubmit");
}

void RawVulkan::submitDraws(DrawSlices slices) {
    beginFrame();
    // The target stays in GENERAL (as in the RHI); this moves it there from UNDEFINED and orders
    // this frame's writes after the previous frame's.
    VkImageMemoryBarrier toGeneral{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    toGeneral.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT;
    toGeneral.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    toGeneral.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    toGeneral.newLayout = VK_IMAGE_LAYOUT_GENERAL;
    toGeneral.srcQueueFamilyIndex = toGeneral.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    toGeneral.image = m_target;
    toGeneral.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdPipelineBarrier(m_commands, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0, 0, nullptr, 0, nullptr, 1, &toGeneral);

    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = m_targetView;
    color.imageLayout = VK_IMAGE_LAYOUT_GENERAL;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = {{0, 0}, {kTargetSize, kTargetSize}};
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachments = &color;
    vkCmdBeginRendering(m_commands, &rendering);
    const VkViewport viewport{0, 0, float(kTargetSize), float(kTargetSize), 0, 1};
    vkCmdSetViewport(m_commands, 0, 1, &viewport);
    vkCmdSetScissor(m_commands, 0, 1, &rendering.renderArea);
    const VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(m_commands, 0, 1, &m_vertices.buffer, &offset);
    if (slices == DrawSlices::DynamicOffsets) {   // one set, its window moved per draw
        vkCmdBindPipeline(m_commands, VK_PIPELINE_BIND_POINT_GRAPHICS, m_dynamicPipeline);
        // The real driver's calls made directly, as an application makes them (like the loops below).
        if (m_nullDriver) {
            for (uint32_t i = 0; i < opsPerFrame(); ++i) {
                const uint32_t slice = uint32_t(i * kSliceBytes);
                nullBind(m_commands, VK_PIPELINE_BIND_POINT_GRAPHICS, m_dynamicLayout, 0, 1, &m_dynamicSet, 1, &slice);
                nullDraw(m_commands, 3, 1, 0, 0);
            }
        } else {
            for (uint32_t i = 0; i < opsPerFrame(); ++i) {
                const uint32_t slice = uint32_t(i * kSliceBytes);
                vkCmdBindDescriptorSets(m_commands, VK_PIPELINE_BIND_POINT_GRAPHICS, m_dynamicLayout, 0, 1, &m_dynamicSet,
                                        1, &slice);
                vkCmdDraw(m_commands, 3, 1, 0, 0);
            }
        }
        vkCmdEndRendering(m_commands);
        submitFrame();
        return;
    }
    vkCmdBindPipeline(m_commands, VK_PIPELINE_BIND_POINT_GRAPHICS, m_rhiChoices ? m_drawPipelineAsRhi : m_drawPipeline);
    const VkPipelineLayout layout = m_rhiChoices ? m_drawLayoutAsRhi : m_drawLayout;   // set 0 is the same in both
    if (m_nullDriver) {
        for (VkDescriptorSet set : m_drawSets) {
            nullBind(m_commands, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, 1, &set, 0, nullptr);
            nullDraw(m_commands, 3, 1, 0, 0);
        }
    } else {
        for (VkDescriptorSet set : m_drawSets) {
            vkCmdBindDescriptorSets(m_commands, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, 1, &set, 0, nullptr);
            vkCmdDraw(m_commands, 3, 1, 0, 0);
        }
    }
    vkCmdEndRendering(m_commands);
    submitFrame();
}

void RawVulkan::submitDispatches(RawVulkanDispatches how) {
    beginFrame();
    // Each dispatch writes its own counter, so dispatches within a frame need no barrier; this one
    // orders the frame after the previous frame's host reads.
    memoryBarrier(m_commands, VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT | VK_ACCESS_HOST_WRITE_BIT,
                  VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    vkCmdBindPipeline(m_commands, VK_PIPELINE_BIND_POINT_COMPUTE, m_rhiChoices ? m_computePipelineAsRhi : m_computePipeline);
    const VkPipelineLayout layout = m_rhiChoices ? m_computeLayoutAsRhi : m_computeLayout;   // set 0 is the same in both
    if (how == RawVulkanDispatches::NullDriver) {
        for (VkDescriptorSet set : m_counterSets) {
            nullBind(m_commands, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &set, 0, nullptr);
            nullDispatch(m_commands, 1, 1, 1);
        }
        submitFrame();
        return;   // nothing was dispatched: the counters stay
    }
    for (VkDescriptorSet set : m_counterSets) {
        vkCmdBindDescriptorSets(m_commands, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &set, 0, nullptr);
        if (how == RawVulkanDispatches::FullBarriers)
            memoryBarrier(m_commands, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT,
                          VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT);
        vkCmdDispatch(m_commands, 1, 1, 1);
    }
    submitFrame();
    ++m_dispatchFrames;
}

void RawVulkan::checkDraws() {
    beginFrame();
    memoryBarrier(m_commands, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                  VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {kTargetSize, kTargetSize, 1};
    vkCmdCopyImageToBuffer(m_commands, m_target, VK_IMAGE_LAYOUT_GENERAL, m_readback.buffer, 1, &region);
    submitFrame();
    wait();
    requireLastDrawColor(m_readback.mapped, "raw Vulkan");
}

void RawVulkan::checkDispatches() {
    for (uint32_t i = 0; i < opsPerFrame(); ++i) {
        uint32_t value = 0;
        std::memcpy(&value, static_cast<const std::byte*>(m_counters.mapped) + i * kSliceBytes, sizeof(value));
        if (value != m_dispatchFrames)
            throw WrongResult(fmt::format("raw Vulkan: counter {} is {} after {} dispatch frames", i, value,
                                          m_dispatchFrames));
    }
}

RawVulkan& rawVulkan() {
    // The RHI scene comes first: it names the device, and its failure explains a missing driver.
    const std::string deviceName = rhiScene(rhi::Backend::Vulkan).device().info().deviceName;
    return sharedEnvironment<RawVulkan>(deviceName);
}

}  // namespace

void rawVulkanDraws(benchmark::State& state, RawVulkanDraws how, DrawSlices slices) {
    runGuarded(state, [&] {
        RawVulkan& raw = rawVulkan();
        raw.recordAs(how);
        if (how == RawVulkanDraws::NullDriver) {
            {
                const NullVulkanDriver driver = nullVulkanDriver(raw.nullBind, raw.nullDraw, slices);
                runFrames(state, [&] { raw.submitDraws(slices); }, [&] { raw.wait(); });
                driver.requireFrames(uint64_t(state.iterations()), "raw vulkan");
            }
            raw.recordAs(RawVulkanDraws::Plain);   // and the real driver still draws
            raw.submitDraws(slices);
            raw.wait();
        } else {
            runFrames(state, [&] { raw.submitDraws(slices); }, [&] { raw.wait(); });
        }
        raw.checkDraws();
    });
}

FrameSide rawVulkanSide(Work work) {
    RawVulkan& raw = rawVulkan();
    raw.recordAs(RawVulkanDraws::Plain);
    return frameSideOf(raw, work, [&raw] { raw.wait(); });
}

void rawVulkanDispatches(benchmark::State& state, RawVulkanDispatches how) {
    runGuarded(state, [&] {
        RawVulkan& raw = rawVulkan();
        // The recording choices are the draws' (RhiChoices: command memory, reusable command
        // buffers, and here the RHI's compute pipeline layout).
        raw.recordAs(how == RawVulkanDispatches::RhiChoices      ? RawVulkanDraws::RhiChoices
                     : how == RawVulkanDispatches::CommandMemory ? RawVulkanDraws::CommandMemory
                                                                 : RawVulkanDraws::Plain);
        if (how == RawVulkanDispatches::NullDriver) {
            {
                const NullVulkanDispatchDriver driver = nullVulkanDispatchDriver(raw.nullBind, raw.nullDispatch);
                runFrames(state, [&] { raw.submitDispatches(how); }, [&] { raw.wait(); });
                driver.requireFrames(uint64_t(state.iterations()), "raw vulkan");
            }
            raw.submitDispatches();   // and the real driver still dispatches
            raw.wait();
        } else {
            runFrames(state, [&] { raw.submitDispatches(how); }, [&] { raw.wait(); });
        }
        raw.checkDispatches();
    });
}

}  // namespace janus::bench
