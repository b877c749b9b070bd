#include "ibl/sky_background.h"

#include <algorithm>

#include <fmt/format.h>

#include "core/gpu_util.h"
#include "janus/shaders/bindings.h"

namespace janus::renderer {
namespace {

// std140 mirror of sky.frag's SkyUniforms.
struct SkyUniforms {
    glm::mat4 inverseViewProjection;
    glm::vec4 params;   // x intensity
};

}  // namespace

SkyBackground::SkyBackground(rhi::IDevice& device, const ImageBasedLighting& lighting) : m_device(device), m_lighting(lighting) {
    m_sampler = device.createSampler(rhi::SamplerDesc{}.setFilter(rhi::Filter::Linear).setAddress(rhi::AddressMode::ClampToEdge));
}

void SkyBackground::addPasses(PassGraph& graph, const SceneView& view) {
    const ViewTarget* sky = graph.find(view.name, ibl_resources::kSkyLight);
    const ViewTarget* hdr = graph.find(view.name, frame_resources::kHdr);
    const ViewTarget* depth = graph.find(view.name, frame_resources::kDepth);
    if (!sky || !hdr || !depth) return;
    auto it = std::find_if(m_views.begin(), m_views.end(), [&](const auto& s) { return s->view.name == view.name; });
    if (it == m_views.end()) it = m_views.insert(m_views.end(), std::make_unique<ViewState>());
    ViewState& state = **it;
    state = ViewState{view, *hdr, *depth};
    PassGraph::PassDesc pass;
    pass.name = "sky";
    pass.view = view.name;
    pass.reads = {hdr->resource, depth->resource, sky->resource};
    pass.writes = {hdr->resource};
    pass.setup = [this, &state] { setup(state); };
    pass.record = [this, &state](rhi::ICommandList& cmd, PassReport& report) { record(state, cmd, report); };
    graph.addPass(std::move(pass));
}

void SkyBackground::setup(ViewState& state) {
    // Directions only: the view without its translation, so the sky is infinitely far.
    const glm::mat4 rotation = glm::mat4(glm::mat3(state.view.view));
    const SkyUniforms uniforms{glm::inverse(state.view.projection * rotation), glm::vec4(m_lighting.intensity(), 0.0f, 0.0f, 0.0f)};
    state.uniforms = makeUniformBuffer(m_device, uniforms, fmt::format("sky uniforms ({})", state.view.name).c_str());
    state.bindings = m_device.createBindingSet(rhi::BindingSetDesc{}
                                                   .add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_SKY_UNIFORMS, state.uniforms))
                                                   .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_SKY_RADIANCE, m_lighting.backgroundCube(),
                                                                                         m_sampler)));
    state.pipeline = m_device.createGraphicsPipeline(rhi::GraphicsPipelineDesc{}
                                                         .setShaders(makeShader(m_device, rhi::ShaderStage::Vertex, "sky_vert"),
                                                                     makeShader(m_device, rhi::ShaderStage::Fragment, "sky_frag"))
                                                         .setDepth(rhi::DepthState{true, false, rhi::CompareOp::LessOrEqual})
                                                         .addColorFormat(state.view.colorFormat)
                                                         .setDepthFormat(state.view.depthFormat)
                                                         .setSampleCount(state.view.sampleCount)
                                                         .setDebugName("sky"));
}

void SkyBackground::record(const ViewState& state, rhi::ICommandList& cmd, PassReport& report) {
    cmd.beginRenderPass(rhi::RenderPassDesc{}
                            .addColor(rhi::Attachment::load(state.hdr.texture, state.hdr.subresource))
                            .setDepth(rhi::Attachment::load(state.depth.texture, state.depth.subresource)));
    cmd.setPipeline(state.pipeline);
    cmd.setBindingSet(0, state.bindings);
    cmd.draw(3);
    ++report.draws;
    cmd.endRenderPass();
}

}  // namespace janus::renderer
