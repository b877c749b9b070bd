// Point and spot lights for forward shading (internal to the renderer; docs/LIGHTING.md): the
// GPU light array and, when the culling mode tiles, the tile light lists of one view with the
// pass that builds them each frame (light_cull.comp on the compute path, the CPU builder of
// light_grid.h between submissions on the fallback path).
//
// The light array is the same for every view. Tile lists exist for the view the lights were
// set up with (the main camera); other views loop every local light (lightCounts.z = 0), which
// gives the same image.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/pass_graph.h"
#include "forward/lighting_settings.h"
#include "janus/renderer/light_grid.h"
#include "janus/renderer/scene_view.h"
#include "janus/rhi/rhi.h"

namespace janus::renderer {

class LocalLights {
public:
    // Packs the lights (warns about and skips those that light nothing; throws RendererError past
    // kMaxLocalLights), resolves the culling mode (never Auto) and creates the light array and
    // tile storage in the form `path` reads them.
    LocalLights(rhi::IDevice& device, const Scene& scene, const ResolvedLighting& lighting, FeaturePath path,
                const SceneView& tiledView, rhi::SamplerHandle pointSampler);

    // Renderer::setLights. The light array keeps the size it was made with (the culling mode,
    // the tile storage and the frame's passes are planned for it): checkLights throws
    // RendererError when more point/spot lights light something than it holds; setLights packs
    // them and fills the rest with dark placeholders (no radiance, no rendering layer: they add
    // exactly 0), then uploads the array.
    void checkLights(std::span<const Light> lights) const;
    void setLights(std::span<const Light> lights);

    LightCulling mode() const { return m_mode; }
    bool tiled() const { return m_mode == LightCulling::Tiles2D || m_mode == LightCulling::TilesDepth; }
    // Whether `view` reads tile lists (the tiled view, when it wants culling) or loops every light.
    bool tiledFor(const SceneView& view) const { return tiled() && view.passes.lightCulling && view.name == m_tiledViewName; }
    // The settings as this renderer uses them: an automatic maxLightsPerTile is the cap it chose
    // (kAutoMaxLightsPerTile only without tiles).
    const ResolvedLighting& lighting() const { return m_lighting; }
    uint32_t count() const { return uint32_t(m_lights.size()); }
    uint32_t directionalCount() const { return m_directionalCount; }
    const TileGrid& tileGrid() const { return m_grid; }
    uint32_t tilesX() const { return m_tilesX; }
    uint32_t tileCount() const { return m_tilesX * m_tilesY; }

    // Adds the tile-list builder for the tiled view (the graph creates the tile lists' storage
    // only if the pass is kept): light-cull-compute | light-cull-cpu, which
    // reads `depth` (the prepass) and writes the returned "tile-lists" resource. `depthTexture` is
    // what the builder samples or reads back.
    PassGraph::ResourceId addCullingPass(PassGraph& graph, PassGraph::ResourceId depth, rhi::TextureHandle depthTexture);

    // Bindings JANUS_BINDING_LOCAL_LIGHTS and JANUS_BINDING_TILE_LISTS of the view set.
    void addViewBindings(rhi::BindingSetDesc& set) const;
    // JANUS_BINDING_TILE_LISTS alone (the tile heat map).
    rhi::BindingItem tileListBinding() const;

    // After a frame: the culling counts of that frame (nullopt without point/spot lights); warns
    // once per renderer about overflowing tiles.
    std::optional<LightCullingReport> finishFrame();
    // The last frame's tile lists as the shaders read them. Throws RendererError without tiles.
    TileLists readTileLists();

private:
    void uploadLights();
    rhi::TextureHandle createDataTexture(rhi::Format format, size_t elements, const char* name);
    void writeDataTexture(const rhi::TextureHandle& texture, const void* data, size_t elements, size_t texelBytes);
    // The tile lists' storage buffer | R32UI texture of `words` uints (once).
    void createTileStorage(size_t words);
    // The largest maxLightsPerTile whose lists this device can hold for this grid and path (0: none):
    // one storage buffer binding (compute) or one data texture (fallback).
    uint32_t largestCapThatFits() const;
    // RendererError (before any resource is made) when maxLightsPerTile is above that, with the
    // sizes that do not fit.
    void checkTileStorageFits() const;
    void createCullCompute();
    void recordCullCompute(rhi::ICommandList& cmd, PassReport& report);
    void buildTilesOnCpu(PassReport& report);

    rhi::IDevice& m_device;
    ResolvedLighting m_lighting;
    FeaturePath m_path;
    std::string m_tiledViewName;
    rhi::SamplerHandle m_pointSampler;
    LightCulling m_mode = LightCulling::Naive;
    std::vector<PackedLight> m_lights;
    uint32_t m_directionalCount = 0;
    TileGrid m_grid;
    uint32_t m_tilesX = 0, m_tilesY = 0;
    bool m_autoMaxLightsPerTile = false;   // m_lighting.maxLightsPerTile was sized here (autoMaxLightsPerTile)

    rhi::BufferHandle m_lightBuffer, m_tileBuffer;     // compute path (storage buffers)
    rhi::TextureHandle m_lightTexture, m_tileTexture;  // fallback path (RGBA32UI / R32UI)
    std::vector<uint32_t> m_cpuTileData;               // fallback path: what the CPU builder produced

    rhi::TextureHandle m_depthTexture;                 // the prepass depth the builder reads
    rhi::PipelineHandle m_cullPipeline;                // compute path (light_cull.comp)
    rhi::BufferHandle m_cullUniforms, m_cullStats;
    rhi::BindingSetHandle m_cullBindings;

    std::optional<LightCullingReport> m_report;
    bool m_culledThisFrame = false;
    bool m_overflowWarned = false;
};

}  // namespace janus::renderer
