#include "debug_views/gi_probe_view.h"

#include <algorithm>

#include <fmt/format.h>

#include "core/gpu_util.h"
#include "gi/gi_bake.h"
#include "janus/shaders/bindings.h"

namespace janus::renderer {
namespace {

// std140 mirror of gi_probe_view_common.glsl's GiProbeViewUniforms.
struct GiProbeViewUniforms {
    glm::mat4 viewProjection;
    glm::vec4 camera;    // homogeneous, as FrameUniforms::cameraPosition
    glm::vec4 spheres;   // x radius
};

}  // namespace

GiProbeView::GiProbeView(rhi::IDevice& device, const IrradianceVolume& volume, const ProbeGi& probeGi)
    : m_device(device), m_probeGi(probeGi) {
    const glm::vec3 spacing = giProbeSpacing(volume);
    // Small enough that neighbours never touch (they are one spacing apart), large enough to see.
    m_radius = kRadiusOfSpacing * std::min({spacing.x, spacing.y, spacing.z});
    m_probeCount = uint32_t(probeGi.bake().probePositions.size());
}

void GiProbeView::addPasses(PassGraph& graph, const SceneView& view) {
    if (view.debugView != DebugView::Gi || !m_probeGi.active() || m_probeCount == 0) return;
    const ViewTarget* color = graph.find(view.name, frame_resources::kHdr);
    const ViewTarget* depth = graph.find(view.name, frame_resources::kDepth);
    const ViewTarget* volume = graph.find("", gi_resources::kIrradianceVolume);
    if (!color || !depth || !volume)
        throw RendererError(fmt::format("gi probe view: view '{}' has no '{}' and '{}' targets or no irradiance volume", view.name,
                                        frame_resources::kHdr, frame_resources::kDepth));
    m_view = view;
    m_color = *color;
    m_depth = *depth;
    PassGraph::PassDesc pass;
    pass.name = "gi-probes";
    pass.view = view.name;
    pass.reads = {color->resource, depth->resource, volume->resource};
    // Depth too: the spheres hide each other by depth.
    pass.writes = {color->resource, depth->resource};
    pass.setup = [this] { setup(); };
    pass.record = [this](rhi::ICommandList& cmd, PassReport& report) { record(cmd, report); };
    graph.addPass(std::move(pass));
}

void GiProbeView::setup() {
    const GiProbeViewUniforms uniforms{m_view.viewProjection(), m_view.homogeneousCamera(), glm::vec4(m_radius, 0.0f, 0.0f, 0.0f)};
    m_uniforms = makeUniformBuffer(m_device, uniforms, "gi probe view");
    rhi::BindingSetDesc set;
    set.add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_GI_PROBE_VIEW, m_uniforms));
    m_probeGi.addViewBindings(set);
    m_bindings = m_device.createBindingSet(set);
    // No culling: the quads face the camera whichever way the view's projection turns them.
    m_pipeline = m_device.createGraphicsPipeline(rhi::GraphicsPipelineDesc{}
                                                     .setShaders(makeShader(m_device, rhi::ShaderStage::Vertex, "gi_probe_view_vert"),
                                                                 makeShader(m_device, rhi::ShaderStage::Fragment, "gi_probe_view_frag"))
                                                     .addColorFormat(m_view.colorFormat)
                                                     .setDepth(rhi::DepthState{true, true, rhi::CompareOp::LessOrEqual})
                                                     .setDepthFormat(m_view.depthFormat)
                                                     .setSampleCount(m_view.sampleCount)
                                                     .setDebugName("gi probe view"));
}

void GiProbeView::record(rhi::ICommandList& cmd, PassReport& report) {
    cmd.beginRenderPass(rhi::RenderPassDesc{}
                            .addColor(rhi::Attachment::load(m_color.texture, m_color.subresource))
                            .setDepth(rhi::Attachment::load(m_depth.texture, m_depth.subresource)));
    cmd.setPipeline(m_pipeline);
    cmd.setBindingSet(0, m_bindings);
    cmd.draw(m_probeCount * 6);
    ++report.draws;
    cmd.endRenderPass();
}

}  // namespace janus::renderer
