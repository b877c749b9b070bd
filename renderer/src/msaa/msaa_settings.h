// How many samples per pixel the main view gets (docs/LIGHTING.md, "Anti-aliasing").
#pragma once

#include <cstdint>
#include <optional>

#include <nlohmann/json.hpp>

namespace janus::renderer {

// 1, 2, 4, 8 or 16: the sample counts a setting may ask for (whether the device allows one is
// msaa/sample_count.h's question).
constexpr bool isMsaaSampleCount(uint64_t samples) { return samples >= 1 && samples <= 16 && (samples & (samples - 1)) == 0; }

// RenderSettings::msaaSamples when given (not 0), else the scene file's quality key "msaa" (1, 2,
// 4, 8 or 16; anything else is a RendererError naming the key), else 1. Whether the device allows
// the count is checked when the renderer is made.
uint32_t resolveMsaaSamples(uint32_t given, const nlohmann::json& quality);
// RenderSettings::alphaToCoverage when given, else the scene file's quality key "alphaToCoverage"
// (true or false; anything else is a RendererError naming the key), else true.
bool resolveAlphaToCoverage(std::optional<bool> given, const nlohmann::json& quality);

}  // namespace janus::renderer
