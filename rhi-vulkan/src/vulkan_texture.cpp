// Images, their views, and samplers. Uploads and readbacks live in the device and command list.
#include <fmt/format.h>

#include <algorithm>

#include "vulkan_backend.h"

namespace janus::rhi::vulkan {
namespace {

[[noreturn]] void invalid(const TextureDesc& desc, const std::string& problem) {
    throw Error(ErrorCode::InvalidDescription, fmt::format("TextureDesc of '{}' ({} {}x{}x{}, {}): {}", desc.debugName,
                                                           toString(desc.dimension), desc.width, desc.height,
                                                           desc.depth, toString(desc.format), problem));
}

VkImageUsageFlags imageUsage(const TextureDesc& desc) {
    VkImageUsageFlags usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    if (any(desc.usage, TextureUsage::Sampled)) usage |= VK_IMAGE_USAGE_SAMPLED_BIT;
    if (any(desc.usage, TextureUsage::Storage)) usage |= VK_IMAGE_USAGE_STORAGE_BIT;
    if (any(desc.usage, TextureUsage::RenderTarget))
        usage |= isDepthFormat(desc.format) ? VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT
                                            : VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    return usage;
}

std::string usageNames(VkImageUsageFlags usage) {
    std::string names;
    auto add = [&](VkImageUsageFlags bit, const char* name) {
        if (usage & bit) names += names.empty() ? name : std::string("|") + name;
    };
    add(VK_IMAGE_USAGE_SAMPLED_BIT, "Sampled");
    add(VK_IMAGE_USAGE_STORAGE_BIT, "Storage");
    add(VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, "RenderTarget");
    return names;
}

VkFilter toVkFilter(Filter f) { return f == Filter::Nearest ? VK_FILTER_NEAREST : VK_FILTER_LINEAR; }

VkSamplerAddressMode toVkAddress(AddressMode m) {
    switch (m) {
        case AddressMode::Repeat: return VK_SAMPLER_ADDRESS_MODE_REPEAT;
        case AddressMode::MirroredRepeat: return VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT;
        case AddressMode::ClampToEdge: return VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    }
    return VK_SAMPLER_ADDRESS_MODE_REPEAT;
}

}  // namespace

// `desc` is validated (rhi/src/validation.cpp), mipLevels resolved. What is left to check here is
// what only the driver knows: whether this combination of format, kind, usage and size exists.
Texture::Texture(ContextPtr context, const TextureDesc& desc) : m_context(std::move(context)), m_desc(desc) {
    format = toVkFormat(m_desc.format);
    aspect = aspectOf(m_desc.format);

    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = m_desc.dimension == TextureDimension::Texture3D ? VK_IMAGE_TYPE_3D : VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {m_desc.width, m_desc.height, m_desc.dimension == TextureDimension::Texture3D ? m_desc.depth : 1};
    info.mipLevels = m_desc.mipLevels;
    info.arrayLayers = arrayLayers();
    info.samples = VkSampleCountFlagBits(m_desc.sampleCount);   // validated: a count the format table allows
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = imageUsage(m_desc);
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    if (m_desc.dimension == TextureDimension::TextureCube || m_desc.dimension == TextureDimension::TextureCubeArray)
        info.flags |= VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT;
    // Lets one slice of a volume be a 2D colour attachment (RenderToVolumeSlice).
    if (m_desc.dimension == TextureDimension::Texture3D && any(m_desc.usage, TextureUsage::RenderTarget))
        info.flags |= VK_IMAGE_CREATE_2D_ARRAY_COMPATIBLE_BIT;

    VkImageFormatProperties supported{};
    VkResult support = vkGetPhysicalDeviceImageFormatProperties(m_context->physicalDevice, format, info.imageType,
                                                                info.tiling, info.usage, info.flags, &supported);
    if (support != VK_SUCCESS)
        invalid(m_desc, fmt::format("this device cannot use {} {} textures as {}; drop that usage or pick "
                                    "another format", toString(m_desc.format), toString(m_desc.dimension),
                                    usageNames(info.usage)));
    if (info.extent.width > supported.maxExtent.width || info.extent.height > supported.maxExtent.height ||
        info.extent.depth > supported.maxExtent.depth)
        invalid(m_desc, fmt::format("the device's largest texture of this kind is {}x{}x{}", supported.maxExtent.width,
                                    supported.maxExtent.height, supported.maxExtent.depth));
    if (!(supported.sampleCounts & info.samples))
        invalid(m_desc, fmt::format("the device cannot make {} textures with {} samples", toString(m_desc.format),
                                    m_desc.sampleCount));
    if (info.arrayLayers > supported.maxArrayLayers)
        invalid(m_desc, fmt::format("the device allows at most {} layers for a texture of this kind",
                                    supported.maxArrayLayers));

    check(vkCreateImage(m_context->device, &info, nullptr, &image), ErrorCode::InvalidDescription,
          fmt::format("vkCreateImage for '{}'", m_desc.debugName));
    try {
        VkMemoryRequirements requirements;
        vkGetImageMemoryRequirements(m_context->device, image, &requirements);
        m_memory = m_context->allocate(requirements, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT,
                                       fmt::format("texture '{}'", m_desc.debugName));
        check(vkBindImageMemory(m_context->device, image, m_memory, 0), ErrorCode::OutOfMemory, "vkBindImageMemory");
        // Every image lives in GENERAL from now on (see docs/ARCHITECTURE.md, Barriers).
        m_context->submitAndWait([&](VkCommandBuffer cmd) {
            VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
            barrier.srcAccessMask = 0;
            barrier.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
            barrier.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
            barrier.newLayout = VK_IMAGE_LAYOUT_GENERAL;
            barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            barrier.image = image;
            barrier.subresourceRange = {aspect, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0,
                                 nullptr, 0, nullptr, 1, &barrier);
            // New textures read as zero, as on GL, so results never depend on stale memory.
            fullBarrier(cmd);
            const VkImageSubresourceRange everything{aspect, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
            if (isDepthFormat(m_desc.format)) {
                VkClearDepthStencilValue zero{0.0f, 0};
                vkCmdClearDepthStencilImage(cmd, image, VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &everything);
            } else {
                VkClearColorValue zero{};
                vkCmdClearColorImage(cmd, image, VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &everything);
            }
        });
    } catch (...) {
        if (m_memory) vkFreeMemory(m_context->device, m_memory, nullptr);
        vkDestroyImage(m_context->device, image, nullptr);
        throw;
    }
    m_context->setObjectName(VK_OBJECT_TYPE_IMAGE, uint64_t(image), m_desc.debugName);
}

Texture::~Texture() {
    for (auto& [key, view] : m_views) vkDestroyImageView(m_context->device, view, nullptr);
    vkDestroyImage(m_context->device, image, nullptr);
    vkFreeMemory(m_context->device, m_memory, nullptr);
}

VkExtent3D Texture::extent(uint32_t mip) const {
    return {mipExtent(m_desc.width, mip), mipExtent(m_desc.height, mip),
            m_desc.dimension == TextureDimension::Texture3D ? mipExtent(m_desc.depth, mip) : 1};
}

uint64_t Texture::subresourceSize(uint32_t mip) const {
    VkExtent3D e = extent(mip);
    return uint64_t(e.width) * e.height * formatInfo(m_desc.format).bytesPerPixel;
}

VkImageSubresourceLayers Texture::copyLayers(TextureSubresource sub) const {
    const bool volume = m_desc.dimension == TextureDimension::Texture3D;
    return {aspect, sub.mipLevel, volume ? 0 : sub.layer, 1};
}

VkOffset3D Texture::copyOffset(TextureSubresource sub) const {
    return {0, 0, m_desc.dimension == TextureDimension::Texture3D ? int32_t(sub.layer) : 0};
}

VkExtent3D Texture::copyExtent(TextureSubresource sub) const {
    VkExtent3D e = extent(sub.mipLevel);
    e.depth = 1;
    return e;
}

VkImageView Texture::view(VkImageViewType type, uint32_t baseMip, uint32_t mipCount, uint32_t baseLayer,
                          uint32_t layerCount, VkImageUsageFlags usage) {
    std::lock_guard lock(m_viewMutex);
    auto key = std::make_tuple(int(type), baseMip, mipCount, baseLayer, layerCount, uint32_t(usage));
    if (auto it = m_views.find(key); it != m_views.end()) return it->second;

    VkImageViewUsageCreateInfo usageInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_USAGE_CREATE_INFO};
    usageInfo.usage = usage;
    VkImageViewCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    info.pNext = &usageInfo;
    info.image = image;
    info.viewType = type;
    info.format = format;
    info.subresourceRange = {aspect, baseMip, mipCount, baseLayer, layerCount};
    VkImageView result = VK_NULL_HANDLE;
    check(vkCreateImageView(m_context->device, &info, nullptr, &result), ErrorCode::InvalidUsage,
          fmt::format("vkCreateImageView for '{}'", m_desc.debugName));
    m_views.emplace(key, result);
    return result;
}

VkImageView Texture::attachmentView(TextureSubresource sub) {
    const VkImageUsageFlags usage = isDepthFormat(m_desc.format) ? VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT
                                                                 : VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    // For a 2D_ARRAY_COMPATIBLE volume the view's array layer selects the slice at that mip.
    return view(VK_IMAGE_VIEW_TYPE_2D, sub.mipLevel, 1, sub.layer, 1, usage);
}

Sampler::Sampler(ContextPtr context, const SamplerDesc& desc) : m_context(std::move(context)), m_desc(desc) {
    VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    info.magFilter = toVkFilter(desc.magFilter);
    info.minFilter = toVkFilter(desc.minFilter);
    info.mipmapMode = desc.mipFilter == Filter::Nearest ? VK_SAMPLER_MIPMAP_MODE_NEAREST : VK_SAMPLER_MIPMAP_MODE_LINEAR;
    info.addressModeU = toVkAddress(desc.addressU);
    info.addressModeV = toVkAddress(desc.addressV);
    info.addressModeW = toVkAddress(desc.addressW);
    info.anisotropyEnable = desc.maxAnisotropy > 1.0f;
    info.maxAnisotropy = desc.maxAnisotropy;
    info.compareEnable = desc.compare.has_value();
    info.compareOp = toVkCompareOp(desc.compare.value_or(CompareOp::Always));
    info.minLod = desc.minLod;
    info.maxLod = desc.maxLod;
    info.borderColor = VK_BORDER_COLOR_FLOAT_TRANSPARENT_BLACK;
    check(vkCreateSampler(m_context->device, &info, nullptr, &sampler), ErrorCode::InvalidDescription,
          "vkCreateSampler");
}

Sampler::~Sampler() { vkDestroySampler(m_context->device, sampler, nullptr); }

}  // namespace janus::rhi::vulkan
