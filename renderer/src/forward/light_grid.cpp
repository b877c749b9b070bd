// Light packing and the tile grid (docs/LIGHTING.md). The CPU tile builder and the analysis
// live in light_grid_build.cpp.
#include "janus/renderer/light_grid.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

namespace janus::renderer {

namespace {

float maxChannel(const glm::vec3& c) { return std::max(c.r, std::max(c.g, c.b)); }

}  // namespace

float cullingRadius(const Light& light, float intensityCutoff) {
    if (light.range) return *light.range;
    if (!(intensityCutoff > 0.0f)) return std::numeric_limits<float>::infinity();
    return std::sqrt(std::max(maxChannel(light.color), 0.0f) * std::max(light.intensity, 0.0f) / intensityCutoff);
}

PackedLights packLocalLights(const Scene& scene, float intensityCutoff) { return packLocalLights(scene.lights, intensityCutoff); }

PackedLights packLocalLights(std::span<const Light> lights, float intensityCutoff) {
    PackedLights packed;
    for (size_t i = 0; i < lights.size(); ++i) {
        const Light& light = lights[i];
        if (light.type == LightType::Directional) continue;
        if (darkLightReason(light)) {
            ++packed.skipped;
            continue;
        }
        PackedLight p;
        p.position = light.position;
        // A radius so small that its square underflows to zero would read as 0 = infinite range:
        // it becomes the smallest radius whose square is a normal float instead.
        const float radius = std::max(cullingRadius(light, intensityCutoff), kMinLightRadius);
        const float radiusSq = radius * radius;
        p.invRangeSq = std::isfinite(radiusSq) ? 1.0f / radiusSq : 0.0f;
        p.radiance = light.color * light.intensity;
        p.renderingLayers = light.renderingLayers;
        const float dirLength = glm::length(light.direction);
        p.direction = dirLength > 0.0f ? light.direction / dirLength : glm::vec3(0.0f, -1.0f, 0.0f);
        if (light.type == LightType::Spot) {
            p.type = kLocalLightTypeSpot;
            const float cosOuter = std::cos(light.outerConeAngle);
            const float cosInner = std::cos(std::min(light.innerConeAngle, light.outerConeAngle));
            // inner == outer would divide by zero: a 1e-4 cosine band makes a hard but finite edge.
            p.spotScale = 1.0f / std::max(cosInner - cosOuter, 1e-4f);
            p.spotOffset = -cosOuter * p.spotScale;
        } else {
            p.type = kLocalLightTypePoint;
            p.spotScale = 0.0f;
            p.spotOffset = 1.0f;
        }
        p.shadowIndex = -1;
        packed.lights.push_back(p);
        packed.sceneLightIndex.push_back(uint32_t(i));
    }
    if (packed.lights.size() > kMaxLocalLights)
        throw RendererError(fmt::format("the scene has {} point/spot lights; at most {} are supported",
                                        packed.lights.size(), kMaxLocalLights));
    return packed;
}

glm::mat4 makeView(const Camera& camera) { return glm::lookAt(camera.position, camera.target, camera.up); }

glm::mat4 makeProjection(const Camera& camera, uint32_t width, uint32_t height) {
    const float aspect = float(width) / float(height);
    glm::mat4 projection;
    if (camera.projection == CameraProjection::Orthographic) {
        const float halfHeight = camera.orthographicHalfHeight, halfWidth = halfHeight * aspect;
        projection = glm::orthoRH_ZO(-halfWidth, halfWidth, -halfHeight, halfHeight, camera.nearPlane, camera.farPlane);
    } else {
        projection = glm::perspectiveRH_ZO(camera.fovYRadians, aspect, camera.nearPlane, camera.farPlane);
    }
    projection[1][1] *= -1.0f;   // NDC y = -1 is row 0 on every backend (docs/ARCHITECTURE.md)
    return projection;
}

TileGrid makeTileGrid(const Camera& camera, uint32_t width, uint32_t height, uint32_t tileSize, uint32_t maxLightsPerTile) {
    if (width == 0 || height == 0) throw RendererError(fmt::format("tile grid: image size {}x{} is empty", width, height));
    if (tileSize == 0) throw RendererError("tile grid: tile size must be > 0");
    TileGrid grid;
    grid.width = width;
    grid.height = height;
    grid.tileSize = tileSize;
    grid.maxLightsPerTile = maxLightsPerTile;
    grid.view = makeView(camera);
    grid.projection = makeProjection(camera, width, height);
    grid.nearPlane = camera.nearPlane;
    grid.farPlane = camera.farPlane;
    return grid;
}

TileGrid makeTileGrid(const SceneView& view, uint32_t tileSize, uint32_t maxLightsPerTile) {
    if (view.width == 0 || view.height == 0)
        throw RendererError(fmt::format("tile grid: view '{}' size {}x{} is empty", view.name, view.width, view.height));
    if (tileSize == 0) throw RendererError("tile grid: tile size must be > 0");
    TileGrid grid;
    grid.width = view.width;
    grid.height = view.height;
    grid.tileSize = tileSize;
    grid.maxLightsPerTile = maxLightsPerTile;
    grid.view = view.view;
    grid.projection = view.projection;
    grid.nearPlane = view.nearPlane;
    grid.farPlane = view.farPlane;
    return grid;
}

CullUniforms makeCullUniforms(const TileGrid& grid, uint32_t lightCount, LightCulling mode) {
    CullUniforms u;
    u.view = grid.view;
    u.projection = grid.projection;
    u.inverseProjection = glm::inverse(grid.projection);
    u.grid = glm::uvec4(grid.width, grid.height, grid.tileSize, grid.maxLightsPerTile);
    u.counts = glm::uvec4(grid.tilesX(), grid.tilesY(), lightCount,
                          mode == LightCulling::TilesDepth ? kCullModeTilesDepth : kCullModeTiles2D);
    u.planes = glm::vec4(grid.nearPlane, grid.farPlane, grid.rangeFromNearPlane ? 1.0f : 0.0f, 0.0f);
    return u;
}

std::vector<uint32_t> flattenTileData(const TileLists& lists) {
    const size_t tileCount = size_t(lists.tilesX) * lists.tilesY;
    std::vector<uint32_t> data(tileCount * (1 + size_t(lists.maxLightsPerTile)), 0u);
    std::copy(lists.counts.begin(), lists.counts.end(), data.begin());
    std::copy(lists.indices.begin(), lists.indices.end(), data.begin() + tileCount);
    return data;
}

TileLists unflattenTileData(std::span<const uint32_t> tileData, uint32_t tileSize, uint32_t tilesX, uint32_t tilesY,
                            uint32_t maxLightsPerTile) {
    const size_t tileCount = size_t(tilesX) * tilesY;
    const size_t expected = tileCount * (1 + size_t(maxLightsPerTile));
    if (tileData.size() < expected)
        throw RendererError(fmt::format("tile data has {} words; {}x{} tiles with {} lights each need {}", tileData.size(),
                                        tilesX, tilesY, maxLightsPerTile, expected));
    TileLists lists;
    lists.tileSize = tileSize;
    lists.tilesX = tilesX;
    lists.tilesY = tilesY;
    lists.maxLightsPerTile = maxLightsPerTile;
    lists.counts.assign(tileData.begin(), tileData.begin() + tileCount);
    lists.indices.assign(tileData.begin() + tileCount, tileData.begin() + expected);
    return lists;
}

}  // namespace janus::renderer
