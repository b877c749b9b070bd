// Debug view "tiles" (internal to the renderer): lights per tile as a heat colour (blue -> green
// -> red at maxLightsPerTile) alpha-blended over the display image, with a white hatch on tiles
// at the cap (shaders/renderer/tile_heatmap.frag).
#pragma once

#include "core/pass_graph.h"
#include "forward/local_lights.h"

namespace janus::renderer {

class TileHeatmap {
public:
    TileHeatmap(rhi::IDevice& device, const LocalLights& localLights, FeaturePath path);

    // The usage the display image needs on top of the tonemap's.
    static rhi::TextureUsage displayUsage() { return rhi::TextureUsage::RenderTarget; }

    // Adds "tile-heatmap": reads `tileLists` and `display`, writes `display`. Without tile lists
    // (the frame does not tile) it adds nothing and warns why.
    void addPass(PassGraph& graph, const std::string& view, std::optional<PassGraph::ResourceId> tileLists, const ViewTarget& display);

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
