#include "msaa/sample_count.h"

#include <fmt/format.h>

#include "janus/renderer/settings.h"

namespace janus::renderer {

void requireSampleCount(const rhi::IDevice& device, uint32_t samples, rhi::Format color, rhi::Format depth, std::string_view setting) {
    if (samples == 1) return;
    const rhi::FormatCapabilities colorCaps = device.formatCapabilities(color);
    const rhi::FormatCapabilities depthCaps = device.formatCapabilities(depth);
    if (colorCaps.supportsSampleCount(samples) && depthCaps.supportsSampleCount(samples)) return;
    throw RendererError(fmt::format("{} {} is not possible on this {} device: its {} and {} render targets allow {} samples per pixel",
                                    setting, samples, rhi::toString(device.info().backend), rhi::toString(color),
                                    rhi::toString(depth),
                                    rhi::FormatCapabilities::sampleCountText(colorCaps.sampleCounts & depthCaps.sampleCounts)));
}

}  // namespace janus::renderer
