// janus::renderer frame report: what each frame ran (per view and pass) and what it cost, and the
// tile light lists a frame built (for tests and analysis).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "janus/renderer/settings.h"

namespace janus::renderer {

// One pass of one frame: what ran, for which view, and what it cost.
struct PassReport {
    std::string name;
    std::optional<double> gpuMs;   // nullopt when the device has no timers
    double cpuMs = 0.0;            // recording time on the CPU (CPU steps: their work)
    uint32_t draws = 0;
    uint32_t dispatches = 0;
    std::string view;              // the SceneView the pass rendered for ("main", "cube +X", ...); "" = not view-specific
};

// One camera the frame rendered from: the main camera, or e.g. one face of a cube capture.
struct ViewReport {
    std::string name;
    uint32_t width = 0, height = 0;
    uint32_t sampleCount = 1;   // samples per pixel it was shaded with
};

// What the light culling of one frame did. Present when the scene has point or spot lights.
struct LightCullingReport {
    LightCulling mode = LightCulling::Naive;   // resolved (never Auto)
    std::string builder;                       // "compute" or "cpu" for tiled modes, "" for Naive
    uint32_t directionalLights = 0;            // shaded (at most 4)
    uint32_t localLights = 0;                  // point + spot lights in the GPU light array
    uint32_t tileSize = 0, tilesX = 0, tilesY = 0, maxLightsPerTile = 0;
    bool maxLightsPerTileAuto = false;         // the cap was sized from the lights (LightingSettings::maxLightsPerTile unset)
    uint64_t listedLights = 0;                 // sum over tiles of lights listed (after the cap)
    uint32_t overflowTiles = 0;                // tiles that had more lights than maxLightsPerTile
    uint64_t droppedLights = 0;                // light references lost to the cap (never silent: also warned on stderr)
    uint32_t densestTileLights = 0;            // the most lights one tile met, listed or not: the cap that would drop none
};

// One frame's share of a reflection probe's update (docs/PROBES.md, "Cost of an update"): an
// update is spread over `steps` frames by the probe's time slicing.
struct ProbeUpdateReport {
    std::string probe;
    uint32_t update = 0;                  // 1 for the probe's first update
    uint32_t step = 0, steps = 0;         // this frame ran step `step` (1-based) of `steps`
    bool shown = false;                   // the update finished this frame: shading reads it from now on
    uint32_t draws = 0, dispatches = 0;   // this frame's share (capture, prefilter)
    std::optional<double> gpuMs;          // this frame's share; nullopt without timers
    // The update so far (all of it once shown), and of that the GGX prefilter alone.
    uint32_t updateDraws = 0, updateDispatches = 0;
    uint32_t prefilterDraws = 0, prefilterDispatches = 0;
    uint32_t copies = 0;                  // texture copies that showed it (faces x mips)
    uint32_t msaaSamples = 1;             // samples per pixel of its capture
};

struct FrameReport {
    std::string backend;           // "vulkan", "gl", "gles"
    std::string path;              // "compute", "fallback"
    uint32_t width = 0, height = 0;
    // Samples per pixel of the main view (RenderSettings::msaaSamples), and whether its
    // alpha-masked materials used alpha to coverage (msaaSamples > 1). In renderCubeCapture's
    // report: the capture's.
    uint32_t msaaSamples = 1;
    bool alphaToCoverage = false;
    std::vector<ViewReport> views;     // in the order they were rendered; views[0] is "main" for renderFrame()
    std::vector<PassReport> passes;    // in execution order; PassReport::view names the view
    std::optional<LightCullingReport> lightCulling;
    std::vector<ProbeUpdateReport> probeUpdates;   // probes whose update ran a step this frame
    // The driver's performance messages during the frame (rhi::IDevice::takePerformanceMessages;
    // with validation on): counted and shown, not failures.
    std::vector<std::string> performanceMessages;
    nlohmann::json toJson() const;
};

// The tile light lists of the last frame as the shaders read them (docs/LIGHTING.md, "Tile lists").
struct TileLists {
    uint32_t tileSize = 0, tilesX = 0, tilesY = 0, maxLightsPerTile = 0;
    bool maxLightsPerTileAuto = false;         // the cap was sized from the lights (LightingSettings::maxLightsPerTile unset)
    std::vector<uint32_t> counts;    // tilesX * tilesY, row-major from the top-left tile, each <= maxLightsPerTile
    std::vector<uint32_t> indices;   // tilesX * tilesY * maxLightsPerTile; tile t's lights ascending at [t * maxLightsPerTile, + counts[t])
};

}  // namespace janus::renderer
