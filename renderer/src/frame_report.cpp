#include "janus/renderer/renderer.h"

namespace janus::renderer {

const char* toString(FeaturePath path) { return path == FeaturePath::Compute ? "compute" : "fallback"; }

std::optional<FeaturePath> parseFeaturePath(std::string_view name) {
    if (name == "compute") return FeaturePath::Compute;
    if (name == "fallback") return FeaturePath::Fallback;
    return std::nullopt;
}

nlohmann::json FrameReport::toJson() const {
    nlohmann::json passesJson = nlohmann::json::array();
    for (const PassReport& p : passes) {
        nlohmann::json j{{"name", p.name}, {"cpuMs", p.cpuMs}, {"draws", p.draws}, {"dispatches", p.dispatches}};
        j["gpuMs"] = p.gpuMs ? nlohmann::json(*p.gpuMs) : nlohmann::json(nullptr);
        passesJson.push_back(std::move(j));
    }
    return {{"backend", backend}, {"path", path}, {"width", width}, {"height", height}, {"passes", passesJson}};
}

}  // namespace janus::renderer
