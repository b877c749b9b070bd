// Debug view "tiles" (internal to the renderer): lights per tile as a heat colour (blue -> green
// -> red at maxLightsPerTile or 256, whichever is lower) alpha-blended over the display image,
// with a white hatch on tiles at a cap below the light count (shaders/renderer/tile_heatmap.frag).
#pragma once

#include "core/pass_graph.h"
#include "core/render_feature.h"
#include "forward/local_lights.h"

namespace janus::renderer {

class TileHeatmap final : public RenderFeature {
public:
    TileHeatmap(rhi::IDevice& device, const LocalLights& localLights, FeaturePath path);

    // The usage the display image needs on top of the tonemap's.
    static rhi::TextureUsage displayUsage() { return rhi::TextureUsage::RenderTarget; }

    // For a view with DebugView::Tiles and a kDisplay target, adds "tile-heatmap": reads the
    // view's kTileLists and kDisplay, writes kDisplay. Without tile lists (the view does not
    // tile) it adds nothing and warns why.
    void addPasses(PassGraph& graph, const SceneView& view) override;

private:
    void setup();
    void record(rhi::ICommandList& cmd, PassReport& report);

    rhi::IDevice& m_device;
    const LocalLights& m_localLights;
    FeaturePath m_path;
    ViewTarget m_display;
    rhi::BufferHandle m_uniforms;
    rhi::BindingSetHandle m_bindings;
    rhi::PipelineHandle m_pipeline;
};

}  // namespace janus::renderer
