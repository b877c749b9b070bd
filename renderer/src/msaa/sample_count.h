// Whether a device can render with a sample count (internal to the renderer; the loader's
// msaa_settings.h stays free of RHI headers).
#pragma once

#include <cstdint>
#include <string_view>

#include "janus/rhi/rhi.h"

namespace janus::renderer {

// A RendererError, "<setting> <samples> is not possible on this ... device", unless the device
// allows `samples` per pixel for render targets of both formats; it names the counts it does allow.
void requireSampleCount(const rhi::IDevice& device, uint32_t samples, rhi::Format color, rhi::Format depth, std::string_view setting);

}  // namespace janus::renderer
