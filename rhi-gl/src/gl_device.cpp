// Placeholder until the GL backend lands.
#include "janus/rhi/backends.h"

namespace janus::rhi::gl {
std::unique_ptr<IDevice> createDevice(const DeviceDesc&) {
    throw Error(ErrorCode::BackendUnavailable, "the GL backend is not built yet");
}
}  // namespace janus::rhi::gl
