#include "msaa/msaa_settings.h"

#include <fmt/format.h>

#include "janus/renderer/settings.h"

namespace janus::renderer {

uint32_t resolveMsaaSamples(uint32_t given, const nlohmann::json& quality) {
    if (given != 0) return given;
    if (!quality.is_object() || !quality.contains("msaa")) return 1;
    const nlohmann::json& value = quality.at("msaa");
    if (value.is_number_integer())
        for (int64_t count : {1, 2, 4, 8, 16})
            if (value.get<int64_t>() == count) return uint32_t(count);
    throw RendererError(fmt::format("scene quality key 'msaa' must be 1, 2, 4, 8 or 16 (samples per pixel), not {}", value.dump()));
}

bool resolveAlphaToCoverage(std::optional<bool> given, const nlohmann::json& quality) {
    if (given) return *given;
    if (!quality.is_object() || !quality.contains("alphaToCoverage")) return true;
    const nlohmann::json& value = quality.at("alphaToCoverage");
    if (!value.is_boolean())
        throw RendererError(fmt::format("scene quality key 'alphaToCoverage' must be true or false, not {}", value.dump()));
    return value.get<bool>();
}

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
