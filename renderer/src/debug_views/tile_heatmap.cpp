#include "debug_views/tile_heatmap.h"

#include <algorithm>
#include <cstdint>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "core/gpu_util.h"
#include "janus/shaders/bindings.h"

namespace janus::renderer {
namespace {

constexpr uint32_t kHeatmapScaleTop = 256;

// std140 mirror of tile_heatmap.frag's HeatmapUniforms.
struct HeatmapUniforms {
    glm::ivec4 grid;    // x tileSize, y tilesX, z the count shown red, w tileCount
    glm::ivec4 marks;   // x the count from which a tile is hatched
};

}  // namespace

TileHeatmap::TileHeatmap(rhi::IDevice& device, const LocalLights& localLights, FeaturePath path)
    : m_device(device), m_localLights(localLights), m_path(path) {}

void TileHeatmap::addPasses(PassGraph& graph, const SceneView& sceneView) {
    const ViewTarget* display = graph.find(sceneView.name, frame_resources::kDisplay);
    if (sceneView.debugView != DebugView::Tiles || !display) return;
    const ViewTarget* tileLists = graph.find(sceneView.name, frame_resources::kTileLists);
    if (!tileLists) {
        fmt::print(stderr, "janus renderer: warning: no tiles to show: the frame uses {} light culling ({}); the tile debug view "
                           "needs tiles-2d or tiles-depth and point/spot lights\n",
                   toString(m_localLights.mode()), m_localLights.count() == 0 ? "the scene has no point or spot lights" : "no tile lists");
        return;
    }
    m_display = *display;
    PassGraph::PassDesc pass;
    pass.name = "tile-heatmap";
    pass.view = sceneView.name;
    pass.reads = {tileLists->resource, display->resource};
    pass.writes = {display->resource};
    pass.setup = [this] { setup(); };
    pass.record = [this](rhi::ICommandList& cmd, PassReport& report) { record(cmd, report); };
    graph.addPass(std::move(pass));
}

void TileHeatmap::setup() {
    const ResolvedLighting& lighting = m_localLights.lighting();
    // A cap of at least every light cannot drop one: no tile is hatched then.
    const uint32_t cap = lighting.maxLightsPerTile;
    const int hatchFrom = cap < m_localLights.count() ? int(cap) : int(cap) + 1;
    // Red at the cap, or at kHeatmapScaleTop lights when the cap is higher: one colour is one
    // density whatever an automatic cap chose.
    const int red = int(std::min(cap, kHeatmapScaleTop));
    const HeatmapUniforms uniforms{glm::ivec4(int(lighting.tileSize), int(m_localLights.tilesX()), red, int(m_localLights.tileCount())),
                                   glm::ivec4(hatchFrom, 0, 0, 0)};
    m_uniforms = makeUniformBuffer(m_device, uniforms, "heat map uniforms");
    m_bindings = m_device.createBindingSet(rhi::BindingSetDesc{}
                                               .add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_HEATMAP_UNIFORMS, m_uniforms))
                                               .add(m_localLights.tileListBinding()));
    m_pipeline = m_device.createGraphicsPipeline(
        rhi::GraphicsPipelineDesc{}
            .setShaders(makeShader(m_device, rhi::ShaderStage::Vertex, "fullscreen_vert"),
                        makeShader(m_device, rhi::ShaderStage::Fragment,
                                   m_path == FeaturePath::Compute ? "tile_heatmap_frag" : "tile_heatmap_textures_frag"))
            .addColorFormat(m_display.texture->desc().format, rhi::BlendAttachment::alpha())
            .setDebugName("tile heat map"));
}

void TileHeatmap::record(rhi::ICommandList& cmd, PassReport& report) {
    drawFullscreenTriangle(cmd, rhi::Attachment::load(m_display.texture, m_display.subresource), m_pipeline, m_bindings, report);
}

}  // namespace janus::renderer
