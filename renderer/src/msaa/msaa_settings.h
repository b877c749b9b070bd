// How many samples per pixel the main view gets (docs/LIGHTING.md, "Anti-aliasing").
#pragma once

#include <cstdint>
#include <optional>

#include <nlohmann/json.hpp>

namespace janus::renderer {

// RenderSettings::msaaSamples when given (not 0), else the scene file's quality key "msaa" (1, 2,
// 4, 8 or 16; anything else is a RendererError naming the key), else 1. Whether the device allows
// the count is checked when the renderer is made.
uint32_t resolveMsaaSamples(uint32_t given, const nlohmann::json& quality);
// RenderSettings::alphaToCoverage when given, else the scene file's quality key "alphaToCoverage"
// (true or false; anything else is a RendererError naming the key), else true.
bool resolveAlphaToCoverage(std::optional<bool> given, const nlohmann::json& quality);

}  // namespace janus::renderer
