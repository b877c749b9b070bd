#include "msaa/msaa_settings.h"

#include <fmt/format.h>

#include "janus/renderer/settings.h"

namespace janus::renderer {

uint32_t resolveMsaaSamples(uint32_t given, const nlohmann::json& quality) {
    if (given != 0) return given;
    if (!quality.is_object() || !quality.contains("msaa")) return 1;
    const nlohmann::json& value = quality.at("msaa");
    if (value.is_number_integer() && value.get<int64_t>() > 0 && isMsaaSampleCount(uint64_t(value.get<int64_t>())))
        return uint32_t(value.get<int64_t>());
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

}  // namespace janus::renderer
