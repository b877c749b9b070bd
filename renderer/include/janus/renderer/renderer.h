// janus::renderer: renders a Scene with a janus::rhi device.
//
// The frame is planned from the scene: a pass exists only if the scene needs it. Every feature
// has a compute path (needs Capability::Compute) and a fallback path (fragment shaders / CPU),
// and both run on every backend that can run them.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "janus/renderer/image.h"
#include "janus/renderer/scene.h"
#include "janus/rhi/rhi.h"

namespace janus::renderer {

enum class FeaturePath { Compute, Fallback };
const char* toString(FeaturePath path);          // "compute", "fallback"
std::optional<FeaturePath> parseFeaturePath(std::string_view name);

// How point and spot lights reach the pixels that they light (docs/LIGHTING.md).
enum class LightCulling {
    Auto,         // chosen per frame: Naive below LightingSettings::autoTiledThreshold local lights, else TilesDepth
    Naive,        // every pixel loops every local light (the reference)
    Tiles2D,      // screen tiles; a light is listed where its sphere meets the tile's frustum (near..far)
    TilesDepth,   // as Tiles2D, clipped to each tile's depth bounds from a depth prepass
};
const char* toString(LightCulling mode);          // "auto", "naive", "tiles-2d", "tiles-depth"
std::optional<LightCulling> parseLightCulling(std::string_view name);

enum class DebugView {
    None,
    Tiles,   // heat map of local lights per tile (blue = few, red = many) over the image; tiles at the cap are marked
};
const char* toString(DebugView view);             // "none", "tiles"
std::optional<DebugView> parseDebugView(std::string_view name);

// Lighting knobs. Unset fields take the scene file's "quality" value, then the default shown.
struct LightingSettings {
    std::optional<LightCulling> culling;          // default Auto
    std::optional<uint32_t> tileSize;             // pixels: 16, 32, 64, 128 or 256; default 16
    std::optional<uint32_t> maxLightsPerTile;     // 1..1024; default 256
    // Lights without a glTF range are culled where their illuminance falls below this (lux);
    // default 0.01. 0 = never cull them: infinite range, only Naive can render that (the
    // reference that measures the cut-off's error).
    std::optional<float> intensityCutoff;
    std::optional<uint32_t> autoTiledThreshold;   // Auto: fewer local lights than this loop naively; default 8 (bench)
    std::optional<bool> shadows;                  // shadow map for the main directional light; default true
    std::optional<uint32_t> shadowMapSize;        // default 1024
};

struct RenderSettings {
    uint32_t width = 256;
    uint32_t height = 256;
    FeaturePath path = FeaturePath::Compute;
    LightingSettings lighting;
    DebugView debugView = DebugView::None;
};

// One pass of one frame: what ran and what it cost.
struct PassReport {
    std::string name;
    std::optional<double> gpuMs;   // nullopt when the device has no timers
    double cpuMs = 0.0;            // recording time on the CPU
    uint32_t draws = 0;
    uint32_t dispatches = 0;
};

// What the light culling of one frame did. Present when the scene has point or spot lights.
struct LightCullingReport {
    LightCulling mode = LightCulling::Naive;   // resolved (never Auto)
    std::string builder;                       // "compute" or "cpu" for tiled modes, "" for Naive
    uint32_t directionalLights = 0;            // shaded (at most 4)
    uint32_t localLights = 0;                  // point + spot lights in the GPU light array
    uint32_t tileSize = 0, tilesX = 0, tilesY = 0, maxLightsPerTile = 0;
    uint64_t listedLights = 0;                 // sum over tiles of lights listed (after the cap)
    uint32_t overflowTiles = 0;                // tiles that had more lights than maxLightsPerTile
    uint64_t droppedLights = 0;                // light references lost to the cap (never silent: also warned on stderr)
};

struct FrameReport {
    std::string backend;           // "vulkan", "gl", "gles"
    std::string path;              // "compute", "fallback"
    uint32_t width = 0, height = 0;
    std::vector<PassReport> passes;
    std::optional<LightCullingReport> lightCulling;
    nlohmann::json toJson() const;
};

// The tile light lists of the last frame as the shaders read them (docs/LIGHTING.md, "Tile lists").
struct TileLists {
    uint32_t tileSize = 0, tilesX = 0, tilesY = 0, maxLightsPerTile = 0;
    std::vector<uint32_t> counts;    // tilesX * tilesY, row-major from the top-left tile, each <= maxLightsPerTile
    std::vector<uint32_t> indices;   // tilesX * tilesY * maxLightsPerTile; tile t's lights ascending at [t * maxLightsPerTile, + counts[t])
};

class RendererError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class Renderer {
public:
    // Uploads the scene. Throws RendererError for settings the device cannot honour (absurd
    // sizes; the compute path on a device without compute names the capability).
    Renderer(rhi::IDevice& device, const Scene& scene, const RenderSettings& settings);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    FrameReport renderFrame();
    ImageRGBA8 readDisplayImage();   // tonemapped, sRGB-encoded: what PNGs and parity use
    ImageRGBAF readHdrImage();       // linear scene radiance before tonemapping: EXR / PFM
    // For tests and analysis (they wait for the GPU). readTileLists throws RendererError when the
    // last frame built no tiles; readDepth returns the D32F depth of the last frame, row 0 on top.
    TileLists readTileLists();
    std::vector<float> readDepth();

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace janus::renderer
