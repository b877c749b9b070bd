// Lighting settings resolved for one renderer: RenderSettings.lighting, else the scene file's
// "quality" keys, else the defaults below (docs/SCENES.md, docs/LIGHTING.md).
#pragma once

#include <cstdint>
#include <string_view>

#include <nlohmann/json.hpp>

#include "janus/renderer/settings.h"

namespace janus::renderer {

constexpr uint32_t kMaxDirectionalLights = 4;   // must match forward_common.glsl

constexpr uint32_t kDefaultTileSize = 16;
constexpr float kDefaultIntensityCutoff = 0.01f;
// LightCulling::Auto loops fewer local lights than this directly. `janus bench forward` on a quiet
// machine (docs/BENCHMARKS.md) finds a tiled mode faster than naive on all four configurations
// from 8 lights (1.2-1.9x) and about even at 0; below 8 the prepass and culling cost what they save.
constexpr uint32_t kDefaultAutoTiledThreshold = 8;
constexpr uint32_t kDefaultShadowMapSize = 1024;

// LightingSettings after RenderSettings -> scene quality -> defaults.
struct ResolvedLighting {
    LightCulling culling = LightCulling::Auto;
    uint32_t tileSize = kDefaultTileSize;
    uint32_t maxLightsPerTile = kAutoMaxLightsPerTile;   // LocalLights sizes an automatic one
    float intensityCutoff = kDefaultIntensityCutoff;
    uint32_t autoTiledThreshold = kDefaultAutoTiledThreshold;
    bool shadows = true;
    uint32_t shadowMapSize = kDefaultShadowMapSize;
};

// Throws RendererError for values out of range or of the wrong JSON type, naming the key.
ResolvedLighting resolveLighting(const LightingSettings& given, const nlohmann::json& quality);

// The scene file's "quality" keys the renderer reads (those resolveLighting does, and "msaa" and
// "alphaToCoverage": msaa/msaa_settings.h).
inline constexpr std::string_view kQualityKeys[] = {"lightCulling", "tileSize", "maxLightsPerTile", "intensityCutoff",
                                                    "autoTiledThreshold", "shadows", "shadowMapSize", "msaa",
                                                    "alphaToCoverage"};

}  // namespace janus::renderer
