// How many samples per pixel the main view gets (docs/LIGHTING.md, "Anti-aliasing").
#pragma once

#include <cstdint>

#include <nlohmann/json.hpp>

namespace janus::renderer {

// RenderSettings::msaaSamples when given (not 0), else the scene file's quality key "msaa" (1, 2,
// 4, 8 or 16; anything else is a RendererError naming the key), else 1. Whether the device allows
// the count is checked when the renderer is made.
uint32_t resolveMsaaSamples(uint32_t given, const nlohmann::json& quality);

}  // namespace janus::renderer
