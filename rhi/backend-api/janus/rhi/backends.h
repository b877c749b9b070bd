// Entry points each backend implements; only the device factory calls them.
#pragma once

#include <memory>

#include "janus/rhi/rhi.h"

namespace janus::rhi::vulkan {
// Throws Error(BackendUnavailable) when no Vulkan 1.2 device can start.
std::unique_ptr<IDevice> createDevice(const DeviceDesc& desc);
}  // namespace janus::rhi::vulkan

namespace janus::rhi::gl {
// desc.backend is GL (4.3 core) or GLES (3.0); desc.glPlatform picks EGL (its display from
// JANUS_EGL_PLATFORM / JANUS_EGL_DEVICE, else the first that works) or OSMesa (loaded at run time).
std::unique_ptr<IDevice> createDevice(const DeviceDesc& desc);
// rhi::listEglDevices.
std::vector<EglDeviceListing> listEglDevices();
}  // namespace janus::rhi::gl
