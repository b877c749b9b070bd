// Instance, physical device choice, logical device, capabilities and the IDevice itself.
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <string_view>
#include <utility>

#include "vulkan_backend.h"

namespace janus::rhi::vulkan {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

VKAPI_ATTR VkBool32 VKAPI_CALL onDebugMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                               VkDebugUtilsMessageTypeFlagsEXT types,
                                               const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    auto* context = static_cast<Context*>(user);
    // Called from inside the loader and the layer (any Vulkan call, vkDestroy* in destructors
    // too): nothing may unwind through them, so a throwing user callback stops here.
    try {
        DebugMessage message;
        // As the GL policy (gl_debug_policy.cpp): errors fail; a performance warning is counted apart.
        const bool error = (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) != 0;
        const bool performance = (types & VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT) != 0 &&
                                 (types & VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT) == 0;
        message.severity = error ? MessageSeverity::Error : performance ? MessageSeverity::Performance : MessageSeverity::Warning;
        message.text = fmt::format("[{}] {}", data->pMessageIdName ? data->pMessageIdName : "vulkan",
                                   data->pMessage ? data->pMessage : "");
        context->addMessage(std::move(message));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "janus: vulkan: the debug message callback threw (%s); the message is still collected\n",
                     e.what());
    } catch (...) {
        std::fprintf(stderr, "janus: vulkan: the debug message callback threw; the message is still collected\n");
    }
    return VK_FALSE;   // never abort the call: the RHI reports, the test decides
}

VkDebugUtilsMessengerCreateInfoEXT messengerInfo(Context* context) {
    VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    info.pfnUserCallback = onDebugMessage;
    info.pUserData = context;
    return info;
}

bool hasInstanceLayer(const char* name) {
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    return std::any_of(layers.begin(), layers.end(), [&](const auto& l) { return std::strcmp(l.layerName, name) == 0; });
}

bool hasInstanceExtension(const char* name) {
    uint32_t count = 0;
    vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr);
    std::vector<VkExtensionProperties> extensions(count);
    vkEnumerateInstanceExtensionProperties(nullptr, &count, extensions.data());
    return std::any_of(extensions.begin(), extensions.end(),
                       [&](const auto& e) { return std::strcmp(e.extensionName, name) == 0; });
}

bool hasDeviceExtension(VkPhysicalDevice gpu, const char* name) {
    uint32_t count = 0;
    vkEnumerateDeviceExtensionProperties(gpu, nullptr, &count, nullptr);
    std::vector<VkExtensionProperties> extensions(count);
    vkEnumerateDeviceExtensionProperties(gpu, nullptr, &count, extensions.data());
    return std::any_of(extensions.begin(), extensions.end(),
                       [&](const auto& e) { return std::strcmp(e.extensionName, name) == 0; });
}

std::string versionString(uint32_t v) {
    return fmt::format("{}.{}.{}", VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v), VK_API_VERSION_PATCH(v));
}

int deviceTypeRank(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
        default: return 0;
    }
}

void createInstance(Context& ctx, const DeviceDesc& desc) {
    uint32_t loaderVersion = VK_API_VERSION_1_0;
    vkEnumerateInstanceVersion(&loaderVersion);
    if (loaderVersion < VK_API_VERSION_1_2)
        throw Error(ErrorCode::BackendUnavailable,
                    fmt::format("the Vulkan loader supports only {}; Janus needs Vulkan 1.2 (update libvulkan1)",
                                versionString(loaderVersion)));

    std::vector<const char*> layers;
    std::vector<const char*> extensions;
    if (desc.enableValidation) {
        if (!hasInstanceLayer(kValidationLayer))
            throw Error(ErrorCode::BackendUnavailable,
                        fmt::format("validation was requested but the layer {} is not installed; install the "
                                    "Debian package vulkan-validationlayers or turn validation off",
                                    kValidationLayer));
        layers.push_back(kValidationLayer);
    }
    ctx.debugUtils = hasInstanceExtension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (desc.enableValidation && !ctx.debugUtils)
        throw Error(ErrorCode::BackendUnavailable,
                    "validation was requested but VK_EXT_debug_utils is missing, so messages cannot be collected");
    if (ctx.debugUtils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (desc.enableSynchronizationValidation) extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "janus";
    app.pEngineName = "janus";
    app.apiVersion = std::min(loaderVersion, uint32_t(VK_API_VERSION_1_3));

    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    info.enabledLayerCount = uint32_t(layers.size());
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    // Chained so messages about instance creation and destruction are collected too.
    VkDebugUtilsMessengerCreateInfoEXT debugInfo = messengerInfo(&ctx);
    if (desc.enableValidation) info.pNext = &debugInfo;
    // VK_EXT_validation_features is an instance extension of the layer itself (the Debian
    // 1.3.239 layer predates VK_EXT_layer_settings).
    const VkValidationFeatureEnableEXT synchronization = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = &synchronization;
    if (desc.enableSynchronizationValidation) {
        features.pNext = info.pNext;
        info.pNext = &features;
    }

    VkResult result = vkCreateInstance(&info, nullptr, &ctx.instance);
    if (result != VK_SUCCESS)
        throw Error(ErrorCode::BackendUnavailable,
                    fmt::format("vkCreateInstance failed with {}; is a Vulkan driver (mesa-vulkan-drivers) installed?",
                                resultName(result)));

    if (ctx.debugUtils) {
        ctx.createMessenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(ctx.instance, "vkCreateDebugUtilsMessengerEXT"));
        ctx.destroyMessenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(ctx.instance, "vkDestroyDebugUtilsMessengerEXT"));
        ctx.cmdBeginDebugLabel = reinterpret_cast<PFN_vkCmdBeginDebugUtilsLabelEXT>(
            vkGetInstanceProcAddr(ctx.instance, "vkCmdBeginDebugUtilsLabelEXT"));
        ctx.cmdEndDebugLabel = reinterpret_cast<PFN_vkCmdEndDebugUtilsLabelEXT>(
            vkGetInstanceProcAddr(ctx.instance, "vkCmdEndDebugUtilsLabelEXT"));
        ctx.setDebugObjectName = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
            vkGetInstanceProcAddr(ctx.instance, "vkSetDebugUtilsObjectNameEXT"));
    }
    if (desc.enableValidation) {
        check(ctx.createMessenger(ctx.instance, &debugInfo, nullptr, &ctx.messenger), ErrorCode::BackendUnavailable,
              "vkCreateDebugUtilsMessengerEXT");
    }
}

// Picks the most capable Vulkan 1.2+ device with a graphics + compute queue.
void pickPhysicalDevice(Context& ctx) {
    uint32_t count = 0;
    vkEnumeratePhysicalDevices(ctx.instance, &count, nullptr);
    std::vector<VkPhysicalDevice> gpus(count);
    vkEnumeratePhysicalDevices(ctx.instance, &count, gpus.data());
    std::string rejected;
    int bestRank = -1;
    for (VkPhysicalDevice gpu : gpus) {
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(gpu, &props);
        if (props.apiVersion < VK_API_VERSION_1_2) {
            rejected += fmt::format(" {} (Vulkan {} < 1.2);", props.deviceName, versionString(props.apiVersion));
            continue;
        }
        if (props.apiVersion < VK_API_VERSION_1_3 && !hasDeviceExtension(gpu, VK_KHR_DYNAMIC_RENDERING_EXTENSION_NAME)) {
            rejected += fmt::format(" {} (no dynamic rendering);", props.deviceName);
            continue;
        }
        uint32_t familyCount = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(gpu, &familyCount, nullptr);
        std::vector<VkQueueFamilyProperties> families(familyCount);
        vkGetPhysicalDeviceQueueFamilyProperties(gpu, &familyCount, families.data());
        for (uint32_t f = 0; f < familyCount; ++f) {
            constexpr VkQueueFlags kNeeded = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
            if ((families[f].queueFlags & kNeeded) != kNeeded) continue;
            int rank = deviceTypeRank(props.deviceType);
            if (rank > bestRank) {
                bestRank = rank;
                ctx.physicalDevice = gpu;
                ctx.queueFamily = f;
                ctx.timestampValidBits = families[f].timestampValidBits;
            }
            break;
        }
        if (ctx.physicalDevice != gpu && bestRank < 0)
            rejected += fmt::format(" {} (no graphics+compute queue);", props.deviceName);
    }
    if (!ctx.physicalDevice)
        throw Error(ErrorCode::BackendUnavailable,
                    fmt::format("no usable Vulkan 1.2 device found ({} device(s):{}); install mesa-vulkan-drivers "
                                "for lavapipe",
                                count, rejected.empty() ? " none" : rejected));
    vkGetPhysicalDeviceProperties(ctx.physicalDevice, &ctx.properties);
    vkGetPhysicalDeviceMemoryProperties(ctx.physicalDevice, &ctx.memoryProperties);
    ctx.apiVersion = std::min(ctx.properties.apiVersion, uint32_t(VK_API_VERSION_1_3));
}

// Whether command pools get the lists' CommandMemory allocation callbacks: yes unless
// JANUS_VULKAN_COMMAND_MEMORY says off (for measuring; "on" or "1" forces them too). They pay
// where the driver allocates every recorded command through the host allocator: lavapipe does
// (three mallocs per bind + dispatch), and its draws and dispatches got 2-4x cheaper with them.
// On NVIDIA (H200, driver 580) four processes gave no clear answer either way: raw draws into
// the callbacks took 66, 92, 94 and 61 ns against 55, 70, 94 and 83 ns without, so they stay
// on everywhere (docs/BENCHMARKS.md, "NVIDIA H200").
bool useCommandMemory() {
    const char* forced = std::getenv("JANUS_VULKAN_COMMAND_MEMORY");
    if (!forced || !*forced) return true;
    const std::string_view value(forced);
    if (value == "on" || value == "1") return true;
    if (value == "off" || value == "0") return false;
    throw Error(ErrorCode::BackendUnavailable,
                fmt::format("JANUS_VULKAN_COMMAND_MEMORY='{}' is not on or off; set one of those or unset it", value));
}

void createLogicalDevice(Context& ctx) {
    VkPhysicalDeviceFeatures supported{};
    vkGetPhysicalDeviceFeatures(ctx.physicalDevice, &supported);
    // Everything the device offers except robust access, which costs speed and hides bugs.
    ctx.enabledFeatures = supported;
    ctx.enabledFeatures.robustBufferAccess = VK_FALSE;

    const bool core13 = ctx.apiVersion >= VK_API_VERSION_1_3;
    VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    features13.dynamicRendering = VK_TRUE;
    VkPhysicalDeviceDynamicRenderingFeaturesKHR dynamicRendering{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DYNAMIC_RENDERING_FEATURES_KHR};
    dynamicRendering.dynamicRendering = VK_TRUE;
    std::vector<const char*> extensions;
    if (!core13) extensions.push_back(VK_KHR_DYNAMIC_RENDERING_EXTENSION_NAME);

    // Bresenham (diamond-exit) lines where the driver has them: GL rasterises lines that way.
    uint32_t extensionCount = 0;
    vkEnumerateDeviceExtensionProperties(ctx.physicalDevice, nullptr, &extensionCount, nullptr);
    std::vector<VkExtensionProperties> available(extensionCount);
    vkEnumerateDeviceExtensionProperties(ctx.physicalDevice, nullptr, &extensionCount, available.data());
    const bool hasLineRasterization = std::any_of(available.begin(), available.end(), [](const VkExtensionProperties& e) {
        return std::string_view(e.extensionName) == VK_EXT_LINE_RASTERIZATION_EXTENSION_NAME;
    });
    VkPhysicalDeviceLineRasterizationFeaturesEXT lineFeatures{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_LINE_RASTERIZATION_FEATURES_EXT};
    if (hasLineRasterization) {
        VkPhysicalDeviceFeatures2 features2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
        features2.pNext = &lineFeatures;
        vkGetPhysicalDeviceFeatures2(ctx.physicalDevice, &features2);
    }
    ctx.bresenhamLines = hasLineRasterization && lineFeatures.bresenhamLines;
    VkPhysicalDeviceLineRasterizationFeaturesEXT enabledLineFeatures{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_LINE_RASTERIZATION_FEATURES_EXT};
    enabledLineFeatures.bresenhamLines = VK_TRUE;
    if (ctx.bresenhamLines) extensions.push_back(VK_EXT_LINE_RASTERIZATION_EXTENSION_NAME);

    float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queueInfo.queueFamilyIndex = ctx.queueFamily;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;

    VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    info.pNext = core13 ? static_cast<void*>(&features13) : static_cast<void*>(&dynamicRendering);
    if (ctx.bresenhamLines) {
        enabledLineFeatures.pNext = const_cast<void*>(info.pNext);
        info.pNext = &enabledLineFeatures;
    }
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &queueInfo;
    info.enabledExtensionCount = uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    info.pEnabledFeatures = &ctx.enabledFeatures;
    check(vkCreateDevice(ctx.physicalDevice, &info, nullptr, &ctx.device), ErrorCode::BackendUnavailable,
          fmt::format("vkCreateDevice on {}", ctx.properties.deviceName));
    vkGetDeviceQueue(ctx.device, ctx.queueFamily, 0, &ctx.queue);

    auto load = [&](const char* core, const char* khr) {
        PFN_vkVoidFunction fn = vkGetDeviceProcAddr(ctx.device, core13 ? core : khr);
        if (!fn) throw Error(ErrorCode::BackendUnavailable, fmt::format("the driver does not export {}", core));
        return fn;
    };
    ctx.cmdBeginRendering = reinterpret_cast<PFN_vkCmdBeginRendering>(load("vkCmdBeginRendering", "vkCmdBeginRenderingKHR"));
    ctx.cmdEndRendering = reinterpret_cast<PFN_vkCmdEndRendering>(load("vkCmdEndRendering", "vkCmdEndRenderingKHR"));
    auto loadCore = [&](const char* name) {
        PFN_vkVoidFunction fn = vkGetDeviceProcAddr(ctx.device, name);
        if (!fn) throw Error(ErrorCode::BackendUnavailable, fmt::format("the driver does not export {}", name));
        return fn;
    };
    ctx.cmdBindPipeline = reinterpret_cast<PFN_vkCmdBindPipeline>(loadCore("vkCmdBindPipeline"));
    ctx.cmdBindDescriptorSets = reinterpret_cast<PFN_vkCmdBindDescriptorSets>(loadCore("vkCmdBindDescriptorSets"));
    ctx.cmdBindVertexBuffers = reinterpret_cast<PFN_vkCmdBindVertexBuffers>(loadCore("vkCmdBindVertexBuffers"));
    ctx.cmdBindIndexBuffer = reinterpret_cast<PFN_vkCmdBindIndexBuffer>(loadCore("vkCmdBindIndexBuffer"));
    ctx.cmdDraw = reinterpret_cast<PFN_vkCmdDraw>(loadCore("vkCmdDraw"));
    ctx.cmdDrawIndexed = reinterpret_cast<PFN_vkCmdDrawIndexed>(loadCore("vkCmdDrawIndexed"));
    ctx.cmdDispatch = reinterpret_cast<PFN_vkCmdDispatch>(loadCore("vkCmdDispatch"));

    VkPhysicalDeviceMaintenance3Properties maintenance3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
    VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    props2.pNext = &maintenance3;
    vkGetPhysicalDeviceProperties2(ctx.physicalDevice, &props2);
    ctx.maxMemoryAllocationSize = maintenance3.maxMemoryAllocationSize;

    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
    poolInfo.queueFamilyIndex = ctx.queueFamily;
    check(vkCreateCommandPool(ctx.device, &poolInfo, nullptr, &ctx.immediatePool), ErrorCode::BackendUnavailable,
          "vkCreateCommandPool");
    VkCommandBufferAllocateInfo allocInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    allocInfo.commandPool = ctx.immediatePool;
    allocInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    allocInfo.commandBufferCount = 1;
    check(vkAllocateCommandBuffers(ctx.device, &allocInfo, &ctx.immediateCommands), ErrorCode::BackendUnavailable,
          "vkAllocateCommandBuffers");
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    check(vkCreateFence(ctx.device, &fenceInfo, nullptr, &ctx.immediateFence), ErrorCode::BackendUnavailable,
          "vkCreateFence");
}

DeviceInfo describe(const Context& ctx) {
    DeviceInfo info;
    info.backend = Backend::Vulkan;
    info.apiVersion = "Vulkan " + versionString(ctx.properties.apiVersion);
    info.deviceName = ctx.properties.deviceName;
    VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    props2.pNext = &driver;
    vkGetPhysicalDeviceProperties2(ctx.physicalDevice, &props2);
    info.driverInfo = fmt::format("{} {}", driver.driverName, driver.driverInfo);
    info.platform = "headless";
    info.shadingLanguage = ctx.apiVersion >= VK_API_VERSION_1_3 ? "SPIR-V 1.6" : "SPIR-V 1.5";
    return info;
}

bool hasFormatFeatures(const Context& ctx, Format format, VkFormatFeatureFlags features) {
    return (ctx.formatProperties(format).optimalTilingFeatures & features) == features;
}

Capabilities queryCapabilities(const Context& ctx) {
    Capabilities caps;
    const VkPhysicalDeviceLimits& l = ctx.properties.limits;
    caps.compute = true;   // the chosen queue family has VK_QUEUE_COMPUTE_BIT
    caps.storageBuffers = true;   // core Vulkan; maxStorageBufferRange is at least 2^27
    caps.storageImages = hasFormatFeatures(ctx, Format::RGBA8_UNORM, VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT) &&
                         hasFormatFeatures(ctx, Format::RGBA16_FLOAT, VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT);
    caps.renderToCubeFaceMip = true;   // a 2D view of any layer and level is core Vulkan
    VkImageFormatProperties volume{};
    caps.renderToVolumeSlice =
        vkGetPhysicalDeviceImageFormatProperties(
            ctx.physicalDevice, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_TYPE_3D, VK_IMAGE_TILING_OPTIMAL,
            VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
            VK_IMAGE_CREATE_2D_ARRAY_COMPATIBLE_BIT, &volume) == VK_SUCCESS;
    caps.floatRenderTargets = true;
    for (Format f : {Format::RGBA16_FLOAT, Format::RGBA32_FLOAT, Format::R11G11B10_FLOAT, Format::R32_FLOAT})
        caps.floatRenderTargets =
            caps.floatRenderTargets && hasFormatFeatures(ctx, f, VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT);
    caps.floatBlend = hasFormatFeatures(ctx, Format::RGBA32_FLOAT, VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BLEND_BIT) &&
                      hasFormatFeatures(ctx, Format::R32_FLOAT, VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BLEND_BIT);
    caps.timestampQueries = ctx.timestampValidBits > 0 && l.timestampComputeAndGraphics;
    caps.independentBlend = ctx.enabledFeatures.independentBlend;
    caps.cubeArrays = ctx.enabledFeatures.imageCubeArray;   // enabled whenever the device has it
    caps.textureViews = true;   // VkImageView of any layer range / compatible type is core Vulkan
    // What Vulkan leaves to the application (queue submission, descriptor pools, the caches of
    // layouts and views) is locked here; everything else is per command list or immutable.
    caps.concurrentDeviceCalls = true;

    Limits& limits = caps.limits;
    limits.maxTextureSize2D = l.maxImageDimension2D;
    limits.maxTextureSize3D = l.maxImageDimension3D;
    limits.maxTextureSizeCube = l.maxImageDimensionCube;
    limits.maxTextureArrayLayers = l.maxImageArrayLayers;
    limits.maxColorAttachments = l.maxColorAttachments;
    limits.maxUniformBufferRange = l.maxUniformBufferRange;
    limits.maxStorageBufferRange = caps.storageBuffers ? l.maxStorageBufferRange : 0;
    for (int i = 0; i < 3; ++i) {
        limits.maxComputeWorkGroupCount[i] = l.maxComputeWorkGroupCount[i];
        limits.maxComputeWorkGroupSize[i] = l.maxComputeWorkGroupSize[i];
    }
    limits.maxComputeWorkGroupInvocations = l.maxComputeWorkGroupInvocations;
    limits.uniformBufferOffsetAlignment = uint32_t(l.minUniformBufferOffsetAlignment);
    limits.storageBufferOffsetAlignment = uint32_t(l.minStorageBufferOffsetAlignment);
    limits.maxBufferSize = ctx.maxMemoryAllocationSize;
    limits.maxVertexBuffers = l.maxVertexInputBindings;
    limits.maxVertexAttributes = l.maxVertexInputAttributes;
    limits.maxVertexStride = l.maxVertexInputBindingStride;
    limits.maxViewportSize = std::min(l.maxViewportDimensions[0], l.maxViewportDimensions[1]);
    limits.viewportBoundsRange = {l.viewportBoundsRange[0], l.viewportBoundsRange[1]};
    limits.maxSamplerAnisotropy = ctx.enabledFeatures.samplerAnisotropy ? l.maxSamplerAnisotropy : 1.0f;
    caps.conventions = Conventions{true, true};
    return caps;
}

// The format table: optimal-tiling features (every image is optimally tiled).
std::vector<FormatCapabilities> queryFormatCapabilities(const Context& ctx, const Capabilities& caps) {
    std::vector<FormatCapabilities> table(allFormats().size() + 1);
    for (const FormatInfo& info : allFormats()) {
        const VkFormatFeatureFlags f = ctx.formatProperties(info.format).optimalTilingFeatures;
        const bool depth = info.kind == FormatKind::Depth;
        auto has = [&](VkFormatFeatureFlags bits) { return (f & bits) == bits; };
        FormatCapabilities& c = table[size_t(info.format)];
        c.set(FormatCapability::Sampled, has(VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT));
        c.set(FormatCapability::Filterable,
              has(VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT));
        // Linear filtering with compareEnable needs no FILTER_LINEAR bit (VUID-vkCmdDraw-magFilter-04553
        // applies to compareEnable == VK_FALSE only); a sampled depth format compares.
        c.set(FormatCapability::CompareFilterable, depth && has(VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT));
        c.set(FormatCapability::RenderTarget, has(depth ? VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT
                                                        : VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT));
        c.set(FormatCapability::Blendable, !depth && has(VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BLEND_BIT));
        // Never a depth format, whatever the driver offers (NVIDIA offers D32_SFLOAT): no GLSL
        // image format qualifier names one, and GL has no depth image load/store.
        c.set(FormatCapability::Storage, !depth && caps.storageImages && has(VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT));
        c.set(FormatCapability::Copyable, has(VK_FORMAT_FEATURE_TRANSFER_SRC_BIT | VK_FORMAT_FEATURE_TRANSFER_DST_BIT));
        // generateMips blits each level from the one above with linear filtering.
        c.set(FormatCapability::GenerateMips,
              !depth && has(VK_FORMAT_FEATURE_BLIT_SRC_BIT | VK_FORMAT_FEATURE_BLIT_DST_BIT |
                            VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT));
        // Multisampling: what a 2D render target of the format can have (Texture's own usage) and
        // a framebuffer takes. Integer formats stay single-sampled: their resolve is one sample,
        // not an average, and GLES 3.0 has no multisampled integer targets at all.
        c.sampleCounts = VK_SAMPLE_COUNT_1_BIT;
        if (c.has(FormatCapability::RenderTarget) && info.kind != FormatKind::UInt) {
            VkImageFormatProperties image{};
            const VkImageUsageFlags usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                                            (depth ? VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT
                                                   : VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT);
            if (vkGetPhysicalDeviceImageFormatProperties(ctx.physicalDevice, toVkFormat(info.format), VK_IMAGE_TYPE_2D,
                                                         VK_IMAGE_TILING_OPTIMAL, usage, 0, &image) == VK_SUCCESS) {
                const VkPhysicalDeviceLimits& limits = ctx.properties.limits;
                c.sampleCounts = image.sampleCounts &
                                 (depth ? limits.framebufferDepthSampleCounts : limits.framebufferColorSampleCounts) &
                                 (VK_SAMPLE_COUNT_1_BIT | VK_SAMPLE_COUNT_2_BIT | VK_SAMPLE_COUNT_4_BIT |
                                  VK_SAMPLE_COUNT_8_BIT | VK_SAMPLE_COUNT_16_BIT);
                c.sampleCounts |= VK_SAMPLE_COUNT_1_BIT;
            }
        }
    }
    return table;
}

class Device final : public IDevice {
public:
    explicit Device(const DeviceDesc& desc) : m_context(std::make_shared<Context>()), m_validation(desc.enableValidation) {
        m_context->messageCallback = desc.messageCallback;
        createInstance(*m_context, desc);
        pickPhysicalDevice(*m_context);
        m_context->commandMemory = useCommandMemory();
        createLogicalDevice(*m_context);
        DeviceProperties properties;
        properties.info = describe(*m_context);
        properties.capabilities = queryCapabilities(*m_context);
        properties.formats = queryFormatCapabilities(*m_context, properties.capabilities);
        properties.validation = desc.enableValidation;
        setProperties(std::move(properties));
    }

    ~Device() override {
        if (m_context->device) vkDeviceWaitIdle(m_context->device);
    }

    // Descriptions arrive validated (rhi/src/validation.cpp).
    BufferHandle createBufferImpl(const BufferDesc& desc) override { return std::make_shared<Buffer>(m_context, desc); }
    TextureHandle createTextureImpl(const TextureDesc& desc) override {
        return std::make_shared<Texture>(m_context, desc);
    }
    SamplerHandle createSamplerImpl(const SamplerDesc& desc) override {
        return std::make_shared<Sampler>(m_context, desc);
    }
    ShaderHandle createShaderImpl(const ShaderDesc& desc) override { return std::make_shared<Shader>(m_context, desc); }
    PipelineHandle createGraphicsPipelineImpl(const GraphicsPipelineDesc& desc) override {
        return std::make_shared<Pipeline>(m_context, desc);
    }
    PipelineHandle createComputePipelineImpl(const ComputePipelineDesc& desc) override {
        return std::make_shared<Pipeline>(m_context, desc);
    }
    BindingSetHandle createBindingSetImpl(const BindingSetDesc& desc) override {
        return std::make_shared<BindingSet>(m_context, desc);
    }
    TimerQueryHandle createTimerQueryImpl() override { return std::make_shared<TimerQuery>(m_context); }
    CommandListHandle createCommandListImpl() override { return std::make_shared<CommandList>(m_context); }

    void executeImpl(const CommandListHandle& commandList) override {
        native<CommandList>(commandList, "execute(): the command list", m_context.get())->submit();
    }
    void waitIdle() override { m_context->waitIdle(); }
    // Nothing is tied to a thread: the queue, descriptor pools and caches take locks of their own.
    void detachFromThread() override {}

    void writeBufferImpl(const BufferHandle& buffer, const void* data, uint64_t size, uint64_t offset) override {
        auto* dst = native<Buffer>(buffer, "writeBuffer(): the buffer", m_context.get());
        StagingBuffer staging(m_context, size);
        std::memcpy(staging.mapped, data, size);
        m_context->submitAndWait([&](VkCommandBuffer cmd) {
            VkBufferCopy region{0, offset, size};
            vkCmdCopyBuffer(cmd, staging.buffer, dst->buffer, 1, &region);
        });
    }

    std::vector<std::byte> readBufferImpl(const BufferHandle& buffer, uint64_t offset, uint64_t size) override {
        auto* src = native<Buffer>(buffer, "readBuffer(): the buffer", m_context.get());
        StagingBuffer staging(m_context, size);
        m_context->submitAndWait([&](VkCommandBuffer cmd) {
            VkBufferCopy region{offset, 0, size};
            vkCmdCopyBuffer(cmd, src->buffer, staging.buffer, 1, &region);
        });
        return {staging.mapped, staging.mapped + size};
    }

    void writeTextureImpl(const TextureHandle& texture, TextureSubresource sub, const void* data, uint64_t size) override {
        auto* dst = native<Texture>(texture, "writeTexture(): the texture", m_context.get());
        StagingBuffer staging(m_context, size);
        std::memcpy(staging.mapped, data, size);
        m_context->submitAndWait([&](VkCommandBuffer cmd) {
            VkBufferImageCopy region{};
            region.imageSubresource = dst->copyLayers(sub);
            region.imageOffset = dst->copyOffset(sub);
            region.imageExtent = dst->copyExtent(sub);
            vkCmdCopyBufferToImage(cmd, staging.buffer, dst->image, VK_IMAGE_LAYOUT_GENERAL, 1, &region);
        });
    }

    std::vector<std::byte> readTextureImpl(const TextureHandle& texture, TextureSubresource sub) override {
        auto* src = native<Texture>(texture, "readTexture(): the texture", m_context.get());
        const uint64_t size = src->subresourceSize(sub.mipLevel);
        StagingBuffer staging(m_context, size);
        m_context->submitAndWait([&](VkCommandBuffer cmd) {
            VkBufferImageCopy region{};
            region.imageSubresource = src->copyLayers(sub);
            region.imageOffset = src->copyOffset(sub);
            region.imageExtent = src->copyExtent(sub);
            vkCmdCopyImageToBuffer(cmd, src->image, VK_IMAGE_LAYOUT_GENERAL, staging.buffer, 1, &region);
        });
        return {staging.mapped, staging.mapped + size};
    }

    std::optional<double> timerSeconds(const TimerQueryHandle& timer) override {
        auto* query = native<TimerQuery>(timer, "timerSeconds(): the timer", m_context.get());
        if (!query->submitted) return std::nullopt;
        uint64_t stamps[2] = {};
        check(vkGetQueryPoolResults(m_context->device, query->pool, 0, 2, sizeof(stamps), stamps, sizeof(uint64_t),
                                    VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
              ErrorCode::DeviceLost, "vkGetQueryPoolResults");
        const uint64_t mask = m_context->timestampValidBits >= 64 ? ~0ull : (1ull << m_context->timestampValidBits) - 1;
        const uint64_t ticks = ((stamps[1] & mask) - (stamps[0] & mask)) & mask;
        return double(ticks) * double(m_context->properties.limits.timestampPeriod) * 1e-9;
    }

    std::vector<DebugMessage> takeDebugMessages() override {
        std::lock_guard lock(m_context->messageMutex);
        return std::exchange(m_context->messages, {});
    }

    void collectFrontMessage(const DebugMessage& message) override { m_context->addMessage(message); }

    std::vector<DebugMessage> takePerformanceMessages() override {
        std::lock_guard lock(m_context->messageMutex);
        return std::exchange(m_context->performanceMessages, {});
    }

    void insertPerformanceMessageForTesting(const std::string& text) override {
        if (!m_validation) return;   // no messenger to receive it
        auto submit = reinterpret_cast<PFN_vkSubmitDebugUtilsMessageEXT>(
            vkGetInstanceProcAddr(m_context->instance, "vkSubmitDebugUtilsMessageEXT"));
        if (!submit) return;
        VkDebugUtilsMessengerCallbackDataEXT data{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CALLBACK_DATA_EXT};
        data.pMessageIdName = "janus-test";
        data.pMessage = text.c_str();
        submit(m_context->instance, VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT, VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
               &data);
    }

    void provokeValidationErrorForTesting() override {
        // Without the layer nothing would report it, and an invalid call is undefined behaviour.
        if (!m_validation) return;
        // fenceCount must be > 0 (VUID-vkResetFences-fenceCount-arraylength). The layer reports it
        // and a driver resetting zero fences does nothing, so this cannot crash.
        vkResetFences(m_context->device, 0, nullptr);
    }

    Context& context() { return *m_context; }

private:
    ContextPtr m_context;
    bool m_validation = false;
};

}  // namespace

std::unique_ptr<IDevice> createDevice(const DeviceDesc& desc) { return std::make_unique<Device>(desc); }

Context* contextOf(IDevice& device) {
    auto* vulkan = dynamic_cast<Device*>(&device);
    return vulkan ? &vulkan->context() : nullptr;
}

}  // namespace janus::rhi::vulkan
