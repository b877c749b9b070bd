// CPU tile builder and culling analysis (docs/LIGHTING.md, "Culling").
//
// The sphere-vs-tile test here and cullLightAgainstTile() in shaders/renderer/
// light_culling_common.glsl are the same algorithm with the same margins, in float, so both
// builders list the same lights (the GPU may list a few more through rounding, never fewer, as
// the margins are far larger than the rounding).
#include "janus/renderer/light_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/parallel.h"

namespace janus::renderer {

namespace {

// Keep in sync with light_culling_common.glsl.
constexpr float kRadiusRelativeMargin = 1e-3f;   // float error of the view transform and planes, relative to the radius
constexpr float kRadiusAbsoluteMargin = 1e-4f;   // ...and absolute, for tiny lights (world units)
constexpr float kDepthRelativeMargin = 1e-5f;    // float error of depth linearisation (a few ulps)
constexpr float kDepthUlps = 2.0f * 0x1p-24f;     // a stored depth's error: its rounding plus P22's, in units of max(z, |P22|)

struct CullLight {
    glm::vec3 center;   // view space
    float radius;       // with margins; +inf for an infinite range
};

// Bounding sphere of what the light can reach: its range sphere, or for a spot whose outer cone
// is narrower than 90 degrees the smaller sphere around the spherical sector (range sphere
// clipped to the cone). Narrow cones (<= 45 deg): centre on the axis at R = range / (2 cos),
// through the apex and the rim; wider ones: centre at range * cos on the axis, R = range * sin.
// Either contains the whole sector (docs/LIGHTING.md, "Culling").
CullLight toCullLight(const TileGrid& grid, const PackedLight& light) {
    CullLight cull;
    if (!(light.invRangeSq > 0.0f)) {
        cull.center = glm::vec3(grid.view * glm::vec4(light.position, 1.0f));
        cull.radius = std::numeric_limits<float>::infinity();
        return cull;
    }
    const float range = 1.0f / std::sqrt(light.invRangeSq);
    glm::vec3 center = light.position;
    float radius = range;
    if (light.type == kLocalLightTypeSpot && light.spotScale > 0.0f) {
        const float cosOuter = -light.spotOffset / light.spotScale;
        if (cosOuter >= 0.70710678f) {
            radius = range / (2.0f * cosOuter);
            center = light.position + light.direction * radius;
        } else if (cosOuter > 0.0f) {
            radius = range * std::sqrt(1.0f - cosOuter * cosOuter);
            center = light.position + light.direction * (range * cosOuter);
        }
    }
    cull.center = glm::vec3(grid.view * glm::vec4(center, 1.0f));
    cull.radius = radius * (1.0f + kRadiusRelativeMargin) + kRadiusAbsoluteMargin;
    return cull;
}

// The tile in view space (d = -z = distance along the view axis): its side planes x = ox + x * d
// and y = oy + y * d, and a depth range. A perspective tile's planes pass through the eye (slopes
// x/d, offsets 0); an orthographic tile is a box (offsets, slopes 0).
struct TileRegion {
    float x0, x1, y0, y1;        // slopes
    float ox0, ox1, oy0, oy1;    // offsets
    float invNormX0, invNormX1, invNormY0, invNormY1;   // 1 / |plane normal|, per tile rather than per light
    float dMin, dMax;
    bool hasGeometry;
};

// Stored depth -> distance along the view axis, for either projection: depth = (P22 z + P32) / w
// with w = P23 z + P33 and z = -d. Perspective (P23 = -1, P33 = 0): d = P32 / (depth + P22);
// orthographic (P23 = 0, P33 = 1): d = (P32 - depth) / P22. The same operations as the
// perspective-only formula when P33 = 0 and P23 = -1, so perspective results keep their bits.
float linearDepth(const glm::mat4& projection, float depth) {
    return (projection[3][2] - depth * projection[3][3]) / (projection[2][2] - depth * projection[2][3]);
}

// How far a tile's depth bound may be from its surfaces, at view distance d of stored depth z. The
// D32F depth is the surface's rounded to float, and P22 is rounded too; d = P32 / (z + P22) turns
// an error dz into dz * d^2 / |P32|, which grows with (d / near)^2: at far / near = 1e5 a surface
// 600 m away has depth steps of 2 m, far beyond a relative margin. Plus the relative term for the
// division's own rounding. light_culling_common.glsl's depthMargin is the same formula.
// Orthographic depth is linear: d = (P32 - z) / P22 turns dz into dz / |P22|, the same everywhere,
// with the stored depth's error relative to max(z, |P32|).
float depthMargin(const glm::mat4& projection, float z, float d) {
    if (isOrthographicProjection(projection)) {
        const float zError = kDepthUlps * (std::abs(z) + std::abs(projection[3][2]));
        return d * kDepthRelativeMargin + zError / std::abs(projection[2][2]);
    }
    const float zError = kDepthUlps * (std::abs(z) + std::abs(projection[2][2]));
    return d * kDepthRelativeMargin + zError * d * d / std::abs(projection[3][2]);
}

TileRegion tileSlopes(const TileGrid& grid, uint32_t tx, uint32_t ty) {
    const uint32_t px0 = tx * grid.tileSize, px1 = std::min(px0 + grid.tileSize, grid.width);
    const uint32_t py0 = ty * grid.tileSize, py1 = std::min(py0 + grid.tileSize, grid.height);
    const float ndcX0 = 2.0f * float(px0) / float(grid.width) - 1.0f;
    const float ndcX1 = 2.0f * float(px1) / float(grid.width) - 1.0f;
    const float ndcY0 = 2.0f * float(py0) / float(grid.height) - 1.0f;
    const float ndcY1 = 2.0f * float(py1) / float(grid.height) - 1.0f;
    const float ax = ndcX0 / grid.projection[0][0], bx = ndcX1 / grid.projection[0][0];
    const float ay = ndcY0 / grid.projection[1][1], by = ndcY1 / grid.projection[1][1];
    // View x = ndcX / P00 * w and w = P33 - P23 * d: the slope is -P23 of that, the offset P33.
    const float slope = -grid.projection[2][3], offset = grid.projection[3][3];
    TileRegion region{};
    region.x0 = std::min(ax, bx) * slope;
    region.x1 = std::max(ax, bx) * slope;
    region.y0 = std::min(ay, by) * slope;
    region.y1 = std::max(ay, by) * slope;
    region.ox0 = std::min(ax, bx) * offset;
    region.ox1 = std::max(ax, bx) * offset;
    region.oy0 = std::min(ay, by) * offset;
    region.oy1 = std::max(ay, by) * offset;
    region.invNormX0 = 1.0f / std::sqrt(1.0f + region.x0 * region.x0);
    region.invNormX1 = 1.0f / std::sqrt(1.0f + region.x1 * region.x1);
    region.invNormY0 = 1.0f / std::sqrt(1.0f + region.y0 * region.y0);
    region.invNormY1 = 1.0f / std::sqrt(1.0f + region.y1 * region.y1);
    region.dMin = grid.nearPlane;
    region.dMax = grid.farPlane;
    region.hasGeometry = true;
    return region;
}

// Conservative: false only when the (margined) sphere is entirely outside the tile's region.
bool sphereMeetsTile(const CullLight& light, const TileRegion& tile, bool useDepthBox) {
    if (!tile.hasGeometry) return false;
    const float r = light.radius;
    if (std::isinf(r)) return true;
    const glm::vec3 c = light.center;
    const float d = -c.z;
    if (d + r < tile.dMin || d - r > tile.dMax) return false;
    // Side planes; inside means x <= ox1 + x1 * d etc. Signed distance = n . c - offset, |n| = 1.
    if ((c.x + tile.x1 * c.z - tile.ox1) * tile.invNormX1 > r) return false;
    if ((-c.x - tile.x0 * c.z + tile.ox0) * tile.invNormX0 > r) return false;
    if ((c.y + tile.y1 * c.z - tile.oy1) * tile.invNormY1 > r) return false;
    if ((-c.y - tile.y0 * c.z + tile.oy0) * tile.invNormY0 > r) return false;
    if (useDepthBox) {
        // The side planes alone let a sphere beside a thin depth slab through; its bounding box does not.
        const float boxMinX = std::min(tile.ox0 + tile.x0 * tile.dMin, tile.ox0 + tile.x0 * tile.dMax);
        const float boxMaxX = std::max(tile.ox1 + tile.x1 * tile.dMin, tile.ox1 + tile.x1 * tile.dMax);
        const float boxMinY = std::min(tile.oy0 + tile.y0 * tile.dMin, tile.oy0 + tile.y0 * tile.dMax);
        const float boxMaxY = std::max(tile.oy1 + tile.y1 * tile.dMin, tile.oy1 + tile.y1 * tile.dMax);
        const float ex = std::max(std::max(boxMinX - c.x, c.x - boxMaxX), 0.0f);
        const float ey = std::max(std::max(boxMinY - c.y, c.y - boxMaxY), 0.0f);
        const float ez = std::max(std::max(tile.dMin - d, d - tile.dMax), 0.0f);
        if (ex * ex + ey * ey + ez * ez > r * r) return false;
    }
    return true;
}

void checkDepth(const TileGrid& grid, std::span<const float> depth, const char* who) {
    if (depth.size() != size_t(grid.width) * grid.height)
        throw RendererError(fmt::format("{}: depth has {} values, the {}x{} grid needs {}", who, depth.size(), grid.width,
                                        grid.height, size_t(grid.width) * grid.height));
}

void checkLists(const TileGrid& grid, const TileLists& lists, const char* who) {
    if (lists.tilesX != grid.tilesX() || lists.tilesY != grid.tilesY() || lists.tileSize != grid.tileSize ||
        lists.counts.size() != size_t(grid.tileCount()) ||
        lists.indices.size() != size_t(grid.tileCount()) * lists.maxLightsPerTile)
        throw RendererError(fmt::format("{}: tile lists ({}x{} tiles of {} px) do not match the grid ({}x{} tiles of {} px)",
                                        who, lists.tilesX, lists.tilesY, lists.tileSize, grid.tilesX(), grid.tilesY(),
                                        grid.tileSize));
}

// --- Analysis in double ---

struct AnalysisLight {
    glm::dvec3 center;      // view space
    glm::dvec3 direction;   // view space, unit
    double invRangeSq, spotScale, spotOffset;
};

std::vector<AnalysisLight> toAnalysisLights(const TileGrid& grid, std::span<const PackedLight> lights) {
    const glm::dmat4 view(grid.view);
    std::vector<AnalysisLight> out;
    out.reserve(lights.size());
    for (const PackedLight& light : lights) {
        AnalysisLight a;
        a.center = glm::dvec3(view * glm::dvec4(glm::dvec3(light.position), 1.0));
        a.direction = glm::dmat3(view) * glm::dvec3(light.direction);
        const double len = glm::length(a.direction);
        if (len > 0.0) a.direction /= len;
        a.invRangeSq = light.invRangeSq;
        a.spotScale = light.spotScale;
        a.spotOffset = light.spotOffset;
        out.push_back(a);
    }
    return out;
}

// View-space position of pixel (x, y)'s centre from its depth.
glm::dvec3 pixelViewPosition(const TileGrid& grid, uint32_t x, uint32_t y, float depth) {
    const glm::dmat4 p(grid.projection);
    const double z = depth;
    const double d = (p[3][2] - z * p[3][3]) / (p[2][2] - z * p[2][3]);   // as linearDepth, in double
    const double w = p[3][3] - p[2][3] * d;                                // d for perspective, 1 for orthographic
    const double ndcX = 2.0 * (double(x) + 0.5) / double(grid.width) - 1.0;
    const double ndcY = 2.0 * (double(y) + 0.5) / double(grid.height) - 1.0;
    return {ndcX / p[0][0] * w, ndcY / p[1][1] * w, -d};
}

bool contributes(const AnalysisLight& light, const glm::dvec3& p) {
    const glm::dvec3 toPixel = p - light.center;
    const double distSq = glm::dot(toPixel, toPixel);
    if (light.invRangeSq > 0.0 && !(distSq * light.invRangeSq < 1.0)) return false;
    if (distSq == 0.0) return true;   // a light exactly at the point: no direction to test the cone with
    const double cone = glm::dot(light.direction, toPixel) / std::sqrt(distSq) * light.spotScale + light.spotOffset;
    return cone > 0.0;
}

}  // namespace

TileLists buildTileListsCpu(const TileGrid& grid, std::span<const PackedLight> lights, std::span<const float> depth,
                            TileBuildStats* stats, unsigned threads) {
    const bool useDepth = !depth.empty();
    if (useDepth) checkDepth(grid, depth, "buildTileListsCpu");
    if (grid.tileSize == 0 || grid.width == 0 || grid.height == 0) throw RendererError("buildTileListsCpu: empty tile grid");
    if (lights.size() > kMaxLocalLights)
        throw RendererError(fmt::format("buildTileListsCpu: {} lights, at most {} are supported", lights.size(), kMaxLocalLights));

    const uint32_t tilesX = grid.tilesX(), tilesY = grid.tilesY(), cap = grid.maxLightsPerTile;
    TileLists lists;
    lists.tileSize = grid.tileSize;
    lists.tilesX = tilesX;
    lists.tilesY = tilesY;
    lists.maxLightsPerTile = cap;
    lists.counts.assign(size_t(tilesX) * tilesY, 0u);
    lists.indices.assign(size_t(tilesX) * tilesY * cap, 0u);

    std::vector<CullLight> cullLights;
    cullLights.reserve(lights.size());
    for (const PackedLight& light : lights) cullLights.push_back(toCullLight(grid, light));

    std::vector<TileBuildStats> rowStats(tilesY);
    parallelFor(tilesY, parallelThreads(threads, tilesY), [&](uint32_t ty) {
        TileBuildStats& rs = rowStats[ty];
        std::vector<TileRegion> regions(tilesX);
        for (uint32_t tx = 0; tx < tilesX; ++tx) {
            TileRegion& region = regions[tx];
            region = tileSlopes(grid, tx, ty);
            if (useDepth) {
                float minDepth = 1.0f, maxDepth = 0.0f;
                const uint32_t px0 = tx * grid.tileSize, px1 = std::min(px0 + grid.tileSize, grid.width);
                const uint32_t py0 = ty * grid.tileSize, py1 = std::min(py0 + grid.tileSize, grid.height);
                for (uint32_t y = py0; y < py1; ++y)
                    for (uint32_t x = px0; x < px1; ++x) {
                        const float z = depth[size_t(y) * grid.width + x];
                        if (z < 1.0f) {   // 1 = cleared: no geometry, nothing to light
                            minDepth = std::min(minDepth, z);
                            maxDepth = std::max(maxDepth, z);
                        }
                    }
                region.hasGeometry = minDepth <= maxDepth;
                const float dMin = linearDepth(grid.projection, minDepth), dMax = linearDepth(grid.projection, maxDepth);
                region.dMin = dMin - depthMargin(grid.projection, minDepth, dMin);
                region.dMax = dMax + depthMargin(grid.projection, maxDepth, dMax);
                if (grid.rangeFromNearPlane) {
                    // Transparent surfaces lie in front of the depth: from the near plane on, and
                    // anywhere where no depth was written.
                    region.dMin = grid.nearPlane;
                    if (!region.hasGeometry) {
                        region.hasGeometry = true;
                        region.dMax = grid.farPlane;
                    }
                }
            }
        }
        // Speed only: the row's region contains each of its tiles' regions, so lights that miss
        // the row miss every tile of it; each tile then tests the row's candidates, in order.
        TileRegion row = regions.front();
        row.x1 = regions.back().x1;
        row.ox1 = regions.back().ox1;
        row.invNormX1 = regions.back().invNormX1;
        row.hasGeometry = false;
        row.dMin = std::numeric_limits<float>::max();
        row.dMax = 0.0f;
        for (const TileRegion& region : regions)
            if (region.hasGeometry) {
                row.hasGeometry = true;
                row.dMin = std::min(row.dMin, region.dMin);
                row.dMax = std::max(row.dMax, region.dMax);
            }
        std::vector<uint32_t> candidates;
        for (uint32_t i = 0; i < cullLights.size(); ++i)
            if (sphereMeetsTile(cullLights[i], row, useDepth)) candidates.push_back(i);

        for (uint32_t tx = 0; tx < tilesX; ++tx) {
            const size_t tile = size_t(ty) * tilesX + tx;
            uint32_t* out = lists.indices.data() + tile * cap;
            uint32_t met = 0;
            for (uint32_t i : candidates) {
                if (!sphereMeetsTile(cullLights[i], regions[tx], useDepth)) continue;
                if (met < cap) out[met] = i;   // ascending by construction; past the cap the highest indices drop
                ++met;
            }
            const uint32_t listed = std::min(met, cap);
            lists.counts[tile] = listed;
            rs.listedLights += listed;
            rs.densestTileLights = std::max(rs.densestTileLights, met);
            if (met > cap) {
                ++rs.overflowTiles;
                rs.droppedLights += met - cap;
            }
        }
    });
    if (stats) {
        *stats = {};
        for (const TileBuildStats& rs : rowStats) {
            stats->listedLights += rs.listedLights;
            stats->overflowTiles += rs.overflowTiles;
            stats->droppedLights += rs.droppedLights;
            stats->densestTileLights = std::max(stats->densestTileLights, rs.densestTileLights);
        }
    }
    return lists;
}

CullingEfficiency measureCullingEfficiency(const TileGrid& grid, std::span<const PackedLight> lights, const TileLists* lists,
                                           std::span<const float> depth) {
    checkDepth(grid, depth, "measureCullingEfficiency");
    if (lists) checkLists(grid, *lists, "measureCullingEfficiency");
    const std::vector<AnalysisLight> analysis = toAnalysisLights(grid, lights);
    // Naive evaluates every light; its contributing lights are found through an uncapped
    // Tiles2D list (conservative, which findMissingLights checks in the tests) to stay fast.
    TileLists candidates;
    if (!lists) {
        TileGrid uncapped = grid;
        uncapped.maxLightsPerTile = uint32_t(lights.size());
        candidates = buildTileListsCpu(uncapped, lights, {});
    }
    const TileLists& evaluated = lists ? *lists : candidates;
    std::vector<CullingEfficiency> rows(grid.height);
    parallelFor(grid.height, parallelThreads(0, grid.height), [&](uint32_t y) {
        CullingEfficiency& e = rows[y];
        for (uint32_t x = 0; x < grid.width; ++x) {
            const float z = depth[size_t(y) * grid.width + x];
            if (!(z < 1.0f)) continue;
            const size_t tile = size_t(y / grid.tileSize) * grid.tilesX() + x / grid.tileSize;
            const uint32_t count = evaluated.counts[tile];
            e.performed += lists ? count : lights.size();
            const glm::dvec3 p = pixelViewPosition(grid, x, y, z);
            const uint32_t* list = evaluated.indices.data() + tile * evaluated.maxLightsPerTile;
            for (uint32_t k = 0; k < count; ++k)
                if (contributes(analysis[list[k]], p)) ++e.contributing;
        }
    });
    CullingEfficiency total;
    for (const CullingEfficiency& e : rows) {
        total.performed += e.performed;
        total.contributing += e.contributing;
    }
    return total;
}

std::vector<MissingLight> findMissingLights(const TileGrid& grid, std::span<const PackedLight> lights, const TileLists& lists,
                                            std::span<const float> depth, size_t maxReported) {
    checkDepth(grid, depth, "findMissingLights");
    checkLists(grid, lists, "findMissingLights");
    const std::vector<AnalysisLight> analysis = toAnalysisLights(grid, lights);
    std::vector<std::vector<MissingLight>> rows(grid.height);
    parallelFor(grid.height, parallelThreads(0, grid.height), [&](uint32_t y) {
        std::vector<MissingLight>& missing = rows[y];
        std::vector<bool> listed(lights.size());
        uint32_t listedTile = UINT32_MAX;
        for (uint32_t x = 0; x < grid.width; ++x) {
            const float z = depth[size_t(y) * grid.width + x];
            if (!(z < 1.0f)) continue;
            const uint32_t tile = (y / grid.tileSize) * grid.tilesX() + x / grid.tileSize;
            if (tile != listedTile) {
                std::fill(listed.begin(), listed.end(), false);
                const uint32_t* list = lists.indices.data() + size_t(tile) * lists.maxLightsPerTile;
                for (uint32_t k = 0; k < lists.counts[tile] && k < lists.maxLightsPerTile; ++k)
                    if (list[k] < lights.size()) listed[list[k]] = true;
                listedTile = tile;
            }
            const glm::dvec3 p = pixelViewPosition(grid, x, y, z);
            for (uint32_t i = 0; i < analysis.size() && missing.size() < maxReported; ++i)
                if (!listed[i] && contributes(analysis[i], p)) missing.push_back({x, y, i});
        }
    });
    std::vector<MissingLight> all;
    for (const auto& row : rows)
        for (const MissingLight& m : row) {
            if (all.size() >= maxReported) return all;
            all.push_back(m);
        }
    return all;
}

}  // namespace janus::renderer
