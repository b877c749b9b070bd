// Lighting settings: each knob from RenderSettings, else the scene file's "quality" key, else the
// default in lighting_settings.h; then the checks that name what to change.
#include "forward/lighting_settings.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include <fmt/format.h>

#include "janus/renderer/scene.h"

namespace janus::renderer {
namespace {

// Settings: the RenderSettings value, else the scene file's "quality" key, else the default.
template <class T>
T resolveSetting(const std::optional<T>& given, const nlohmann::json& quality, const char* key, T fallback) {
    if (given) return *given;
    if (!quality.is_object() || !quality.contains(key)) return fallback;
    const nlohmann::json& value = quality.at(key);
    if constexpr (std::is_same_v<T, bool>) {
        if (value.is_boolean()) return value.get<bool>();
        throw RendererError(fmt::format("scene quality key '{}' must be true or false, not {}", key, value.dump()));
    } else if constexpr (std::is_integral_v<T>) {
        if (value.is_number_integer() && value.get<int64_t>() >= 0 && uint64_t(value.get<int64_t>()) <= std::numeric_limits<T>::max())
            return T(value.get<int64_t>());
        throw RendererError(fmt::format("scene quality key '{}' must be a non-negative integer, not {}", key, value.dump()));
    } else {
        if (value.is_number()) return T(value.get<double>());
        throw RendererError(fmt::format("scene quality key '{}' must be a number, not {}", key, value.dump()));
    }
}

}  // namespace

ResolvedLighting resolveLighting(const LightingSettings& given, const nlohmann::json& quality) {
    ResolvedLighting lighting;
    if (given.culling) {
        lighting.culling = *given.culling;
    } else if (quality.is_object() && quality.contains("lightCulling")) {
        const nlohmann::json& value = quality.at("lightCulling");
        const std::optional<LightCulling> parsed =
            value.is_string() ? parseLightCulling(value.get<std::string>()) : std::nullopt;
        if (!parsed)
            throw RendererError(fmt::format("scene quality key 'lightCulling' is {}; expected \"auto\", \"naive\", \"tiles-2d\" or "
                                            "\"tiles-depth\"",
                                            value.dump()));
        lighting.culling = *parsed;
    }
    lighting.tileSize = resolveSetting(given.tileSize, quality, "tileSize", kDefaultTileSize);
    if (given.maxLightsPerTile) {
        lighting.maxLightsPerTile = *given.maxLightsPerTile;
    } else if (quality.is_object() && quality.contains("maxLightsPerTile")) {
        // A number of lights or "auto"; 0 is the API's name for auto, not a scene file's.
        const nlohmann::json& value = quality.at("maxLightsPerTile");
        if (value == "auto") {
            lighting.maxLightsPerTile = kAutoMaxLightsPerTile;
        } else if (value.is_number_integer() && value.get<int64_t>() >= 1 && value.get<int64_t>() <= kMaxLightsPerTileLimit) {
            lighting.maxLightsPerTile = uint32_t(value.get<int64_t>());
        } else {
            throw RendererError(fmt::format("scene quality key 'maxLightsPerTile' is {}; use a whole number 1..{} or \"auto\" (the "
                                            "default: sized from the scene's lights)",
                                            value.dump(), kMaxLightsPerTileLimit));
        }
    }
    lighting.intensityCutoff = resolveSetting(given.intensityCutoff, quality, "intensityCutoff", kDefaultIntensityCutoff);
    lighting.autoTiledThreshold = resolveSetting(given.autoTiledThreshold, quality, "autoTiledThreshold", kDefaultAutoTiledThreshold);
    lighting.shadows = resolveSetting(given.shadows, quality, "shadows", true);
    lighting.shadowMapSize = resolveSetting(given.shadowMapSize, quality, "shadowMapSize", kDefaultShadowMapSize);

    const uint32_t t = lighting.tileSize;
    if (t != 16 && t != 32 && t != 64 && t != 128 && t != 256)
        throw RendererError(fmt::format("tileSize {} is not supported: use 16, 32, 64, 128 or 256 pixels", t));
    if (lighting.maxLightsPerTile > kMaxLightsPerTileLimit)
        throw RendererError(fmt::format("maxLightsPerTile {} is out of range: it must be between 1 and {}, or {} (kAutoMaxLightsPerTile; "
                                        "scene file: \"auto\") to size it from the lights",
                                        lighting.maxLightsPerTile, kMaxLightsPerTileLimit, kAutoMaxLightsPerTile));
    if (!std::isfinite(lighting.intensityCutoff) || lighting.intensityCutoff < 0.0f)
        throw RendererError(fmt::format("intensityCutoff {} is not possible: it must be a finite number >= 0 (lux)",
                                        lighting.intensityCutoff));
    if (lighting.intensityCutoff == 0.0f && (lighting.culling == LightCulling::Tiles2D || lighting.culling == LightCulling::TilesDepth))
        throw RendererError(fmt::format("intensity cut-off 0 gives lights without a range an infinite range, which only naive "
                                        "culling can render; use LightCulling::Naive (\"naive\"; janus: --culling naive) or a cut-off above 0 with {}",
                                        toString(lighting.culling)));
    return lighting;
}

uint32_t autoMaxLightsPerTile(size_t localLights, size_t tileCount, uint32_t deviceLimit) {
    const uint64_t wordsPerTile = kAutoTileListBudgetBytes / (sizeof(uint32_t) * std::max<uint64_t>(tileCount, 1));
    const uint64_t budgetCap = wordsPerTile > 0 ? wordsPerTile - 1 : 0;   // one word of each tile is its count
    const uint64_t cap = std::min<uint64_t>(
        {localLights, kMaxLightsPerTileLimit, std::max<uint64_t>(budgetCap, kAutoMaxLightsPerTileFloor), deviceLimit});
    return uint32_t(std::max<uint64_t>(cap, 1));
}

LightingSettings resolveLightingSettings(const LightingSettings& given, const Scene& scene) {
    const ResolvedLighting resolved = resolveLighting(given, scene.quality);
    LightingSettings settings;
    settings.culling = resolved.culling;
    settings.tileSize = resolved.tileSize;
    settings.maxLightsPerTile = resolved.maxLightsPerTile;
    settings.intensityCutoff = resolved.intensityCutoff;
    settings.autoTiledThreshold = resolved.autoTiledThreshold;
    settings.shadows = resolved.shadows;
    settings.shadowMapSize = resolved.shadowMapSize;
    return settings;
}

}  // namespace janus::renderer
