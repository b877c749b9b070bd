// Placeholder until the Vulkan backend lands.
#include "janus/rhi/backends.h"

namespace janus::rhi::vulkan {
std::unique_ptr<IDevice> createDevice(const DeviceDesc&) {
    throw Error(ErrorCode::BackendUnavailable, "the Vulkan backend is not built yet");
}
}  // namespace janus::rhi::vulkan
