// janus::renderer: Forward+ light grid. Packs point/spot lights into the GPU layout, builds
// per-tile light lists on the CPU (the fallback path; the compute path runs light_cull.comp,
// which makes the same decisions), and measures how good and how safe the culling is.
// Layout, formulas and the culling algorithm: docs/LIGHTING.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "janus/renderer/frame_report.h"
#include "janus/renderer/settings.h"
#include "janus/renderer/scene.h"
#include "janus/renderer/scene_view.h"

namespace janus::renderer {

inline constexpr uint32_t kDataTextureWidth = 1024;       // fallback path: element e at texel (e % 1024, e / 1024)
// Smaller culling radii are raised to this: its square (1e-36) is still a normal float, so
// 1 / radius^2 stays finite and never underflows to 0, which the layout reserves for "infinite".
inline constexpr float kMinLightRadius = 1e-18f;
inline constexpr uint32_t kLocalLightTypePoint = 1;
inline constexpr uint32_t kLocalLightTypeSpot = 2;

// One local light, 64 bytes = 4 x uvec4; identical in the storage buffer and the RGBA32UI texture.
struct PackedLight {
    glm::vec3 position{0.0f};
    float invRangeSq = 0.0f;          // 1 / cullingRadius^2; 0 = infinite range (Naive only)
    glm::vec3 radiance{0.0f};         // colour * intensity
    uint32_t type = kLocalLightTypePoint;
    glm::vec3 direction{0.0f, -1.0f, 0.0f};   // unit, the way the light travels
    uint32_t renderingLayers = 1u;
    float spotScale = 0.0f;           // cone = clamp(dot(direction, -toLight) * spotScale + spotOffset, 0, 1)
    float spotOffset = 1.0f;
    int32_t shadowIndex = -1;
    uint32_t reserved = 0;
};
static_assert(sizeof(PackedLight) == 64, "PackedLight must match 4 x uvec4 in the shaders");
static_assert(alignof(PackedLight) == 4);

struct PackedLights {
    std::vector<PackedLight> lights;
    std::vector<uint32_t> sceneLightIndex;   // lights[i] comes from scene.lights[sceneLightIndex[i]]
    uint32_t skipped = 0;                    // point/spot lights that light nothing (not packed)
};

// Radius beyond which a light is treated as dark: the glTF range if given, otherwise
// sqrt(maxChannel(colour) * intensity / intensityCutoff), i.e. where the unwindowed inverse-square
// irradiance falls to the cut-off. Cut-off <= 0 without a range: +infinity.
float cullingRadius(const Light& light, float intensityCutoff);

// Point and spot lights of the scene in scene order, minus those that light nothing
// (darkLightReason: range <= 0, zero intensity or colour), which `skipped` counts; loadScene has
// named them in Scene::warnings. Throws RendererError past kMaxLocalLights.
PackedLights packLocalLights(const Scene& scene, float intensityCutoff);
// The same for a light list (sceneLightIndex indexes it).
PackedLights packLocalLights(std::span<const Light> lights, float intensityCutoff);

// std140 mirror of light_cull.comp's CullUniforms block (set 0, binding 0).
struct CullUniforms {
    glm::mat4 view{1.0f};
    glm::mat4 projection{1.0f};
    glm::mat4 inverseProjection{1.0f};
    glm::uvec4 grid{0u};     // x width, y height, z tileSize, w maxLightsPerTile
    glm::uvec4 counts{0u};   // x tilesX, y tilesY, z lightCount, w mode (1 Tiles2D, 2 TilesDepth)
    glm::vec4 planes{0.0f};  // x near, y far, z 1 = TileGrid::rangeFromNearPlane
};
static_assert(sizeof(CullUniforms) == 240);
inline constexpr uint32_t kCullModeTiles2D = 1;
inline constexpr uint32_t kCullModeTilesDepth = 2;

// Screen tiling plus the camera matrices culling and shading both use.
struct TileGrid {
    uint32_t width = 0, height = 0, tileSize = 16, maxLightsPerTile = 0;
    glm::mat4 view{1.0f};
    // perspectiveRH_ZO or orthoRH_ZO (symmetric) with [1][1] negated: NDC y = -1 is row 0. Culling
    // reads which from the matrix: w = P23 * z + P33 is -z for perspective, 1 for orthographic.
    glm::mat4 projection{1.0f};
    float nearPlane = 0.05f, farPlane = 100.0f;
    // TilesDepth only: each tile's depth range starts at the near plane (not at its nearest
    // depth) and tiles without depth cover near to far, so the lists also hold every light that
    // reaches a surface in front of the depth buffer's: the transparent (alphaMode BLEND)
    // surfaces, which the depth prepass leaves out. The renderer sets it when the scene has them.
    bool rangeFromNearPlane = false;

    uint32_t tilesX() const { return (width + tileSize - 1) / tileSize; }
    uint32_t tilesY() const { return (height + tileSize - 1) / tileSize; }
    uint32_t tileCount() const { return tilesX() * tilesY(); }
    glm::mat4 viewProjection() const { return projection * view; }
};

// The renderer uses this for its viewProjection too, so culling and shading agree exactly.
// Throws RendererError for zero sizes or a tile size of 0.
TileGrid makeTileGrid(const Camera& camera, uint32_t width, uint32_t height, uint32_t tileSize,
                      uint32_t maxLightsPerTile);
// The same for any scene view (its matrices, size and near/far planes).
TileGrid makeTileGrid(const SceneView& view, uint32_t tileSize, uint32_t maxLightsPerTile);
// The camera's projection for a width x height image (Vulkan clip conventions, y flipped so
// NDC y = -1 is row 0): perspective from fovYRadians, orthographic from orthographicHalfHeight;
// both take their horizontal extent from the image's aspect ratio.
glm::mat4 makeProjection(const Camera& camera, uint32_t width, uint32_t height);
glm::mat4 makeView(const Camera& camera);

CullUniforms makeCullUniforms(const TileGrid& grid, uint32_t lightCount, LightCulling mode);

struct TileBuildStats {
    uint64_t listedLights = 0;    // sum of the (capped) counts
    uint32_t overflowTiles = 0;   // tiles that met more lights than maxLightsPerTile
    uint64_t droppedLights = 0;   // lights those tiles could not list (the highest indices)
    uint32_t densestTileLights = 0;   // the most lights one tile met, listed or not
};

// CPU builder (fallback path). depth: D32F values, width*height, row 0 on top; empty = Tiles2D
// (tile frustum from near to far), otherwise TilesDepth (see TileGrid::rangeFromNearPlane). threads 0 = hardware concurrency.
// The output does not depend on the thread count.
TileLists buildTileListsCpu(const TileGrid& grid, std::span<const PackedLight> lights,
                            std::span<const float> depth, TileBuildStats* stats = nullptr,
                            unsigned threads = 0);

// The contract's tileData array: tileCount counts, then tileCount * maxLightsPerTile indices.
std::vector<uint32_t> flattenTileData(const TileLists& lists);
TileLists unflattenTileData(std::span<const uint32_t> tileData, uint32_t tileSize, uint32_t tilesX,
                            uint32_t tilesY, uint32_t maxLightsPerTile);

// --- Analysis (double precision; tests and the benchmark) ---

// A light evaluation "contributes" when the pixel's world position (reconstructed from its depth
// at the pixel centre) is strictly inside the light's range and, for spots, its outer cone.
// Only pixels with geometry (depth < 1) count.
struct CullingEfficiency {
    uint64_t performed = 0;      // light evaluations the shader runs (tile counts, or all lights for naive)
    uint64_t contributing = 0;   // of those, the ones that contribute
    double ratio() const { return performed == 0 ? 1.0 : double(contributing) / double(performed); }
};
CullingEfficiency measureCullingEfficiency(const TileGrid& grid, std::span<const PackedLight> lights,
                                           const TileLists* lists /* null = naive */,
                                           std::span<const float> depth);

struct MissingLight {
    uint32_t x = 0, y = 0, light = 0;   // pixel and packed light index
};
// Per-pixel brute force: contributing lights absent from the pixel's tile list.
std::vector<MissingLight> findMissingLights(const TileGrid& grid, std::span<const PackedLight> lights,
                                            const TileLists& lists, std::span<const float> depth,
                                            size_t maxReported = 16);

}  // namespace janus::renderer
