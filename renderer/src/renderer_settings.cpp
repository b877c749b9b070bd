// Renderer settings: checkSettings (size and capabilities the path needs), resolveLighting
// (LightingSettings from RenderSettings, else the scene file's "quality" keys, else the defaults
// in renderer_impl.h) and chooseCulling (the light culling mode this scene renders with).
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include <fmt/format.h>

#include "renderer_impl.h"

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

void Renderer::Impl::checkSettings() const {
    const rhi::Capabilities& caps = device.capabilities();
    const uint32_t maxSize = caps.limits.maxTextureSize2D;
    if (settings.width == 0 || settings.height == 0 || settings.width > maxSize || settings.height > maxSize)
        throw RendererError(fmt::format("render size {}x{} is not possible on this {} device: width and height must be "
                                        "between 1 and its maximum 2D texture size {}",
                                        settings.width, settings.height, rhi::toString(device.info().backend), maxSize));
    if (!caps.floatRenderTargets)
        throw RendererError(fmt::format("the forward pass renders into RGBA16F, which needs the '{}' capability that this {} "
                                        "device lacks",
                                        rhi::toString(rhi::Capability::FloatRenderTargets), rhi::toString(device.info().backend)));
    if (settings.path == FeaturePath::Compute) {
        for (rhi::Capability cap : {rhi::Capability::Compute, rhi::Capability::StorageImages, rhi::Capability::StorageBuffers})
            if (!caps.has(cap))
                throw RendererError(fmt::format("the compute path needs the '{}' capability, which this {} device lacks; render "
                                                "with the fallback path (FeaturePath::Fallback, --path fallback)",
                                                rhi::toString(cap), rhi::toString(device.info().backend)));
    }
}

void Renderer::Impl::resolveLighting(const Scene& scene) {
    const LightingSettings& given = settings.lighting;
    const nlohmann::json& quality = scene.quality;
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
    lighting.maxLightsPerTile = resolveSetting(given.maxLightsPerTile, quality, "maxLightsPerTile", kDefaultMaxLightsPerTile);
    lighting.intensityCutoff = resolveSetting(given.intensityCutoff, quality, "intensityCutoff", kDefaultIntensityCutoff);
    lighting.autoTiledThreshold = resolveSetting(given.autoTiledThreshold, quality, "autoTiledThreshold", kDefaultAutoTiledThreshold);
    lighting.shadows = resolveSetting(given.shadows, quality, "shadows", true);
    lighting.shadowMapSize = resolveSetting(given.shadowMapSize, quality, "shadowMapSize", kDefaultShadowMapSize);

    const uint32_t t = lighting.tileSize;
    if (t != 16 && t != 32 && t != 64 && t != 128 && t != 256)
        throw RendererError(fmt::format("tile size {} is not supported: use 16, 32, 64, 128 or 256 pixels", t));
    if (lighting.maxLightsPerTile < 1 || lighting.maxLightsPerTile > 1024)
        throw RendererError(fmt::format("maxLightsPerTile {} is out of range: it must be between 1 and 1024", lighting.maxLightsPerTile));
    if (!std::isfinite(lighting.intensityCutoff) || lighting.intensityCutoff < 0.0f)
        throw RendererError(fmt::format("intensity cut-off {} is not possible: it must be a finite number >= 0 (lux)",
                                        lighting.intensityCutoff));
    if (lighting.intensityCutoff == 0.0f && (lighting.culling == LightCulling::Tiles2D || lighting.culling == LightCulling::TilesDepth))
        throw RendererError(fmt::format("intensity cut-off 0 gives lights without a range an infinite range, which only naive "
                                        "culling can render; use LightCulling::Naive (\"naive\") or a cut-off above 0 with {}",
                                        toString(lighting.culling)));
}

void Renderer::Impl::chooseCulling() {
    cullingMode = lighting.culling;
    if (cullingMode == LightCulling::Auto) {
        // Infinite ranges (cut-off 0) can only be looped directly.
        const bool tiledPossible = lighting.intensityCutoff > 0.0f;
        cullingMode = tiledPossible && localLights.size() >= lighting.autoTiledThreshold ? LightCulling::TilesDepth : LightCulling::Naive;
    }
    // No local lights: nothing to cull, no prepass.
    if (localLights.empty()) cullingMode = LightCulling::Naive;
    if (tiled()) {
        tilesX = tileGrid.tilesX();
        tilesY = tileGrid.tilesY();
    }
    if (!localLights.empty()) {
        LightCullingReport report;
        report.mode = cullingMode;
        report.builder = tiled() ? (settings.path == FeaturePath::Compute ? "compute" : "cpu") : "";
        report.directionalLights = directionalCount;
        report.localLights = uint32_t(localLights.size());
        if (tiled()) {
            report.tileSize = lighting.tileSize;
            report.tilesX = tilesX;
            report.tilesY = tilesY;
            report.maxLightsPerTile = lighting.maxLightsPerTile;
        }
        cullingReport = report;
    }
}

}  // namespace janus::renderer
