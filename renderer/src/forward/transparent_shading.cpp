// Transparent shading: the "transparent" pass (alphaMode BLEND), back to front per instance.
#include "forward/transparent_shading.h"

#include <algorithm>

#include <fmt/format.h>

#include "janus/shaders/bindings.h"

namespace janus::renderer {

TransparentShading::TransparentShading(rhi::IDevice& device, const Scene& scene, const GpuScene& gpuScene,
                                       const ForwardShading& forward)
    : m_device(device), m_gpuScene(gpuScene), m_forward(forward) {
    if (gpuScene.blendedDraws().empty()) return;
    const Instance& instance = scene.instances.at(gpuScene.blendedDraws().front().instance);
    const int32_t material = scene.meshes.at(instance.mesh).material;
    m_blendedMaterial = material >= 0 && !scene.materials[size_t(material)].name.empty()
                            ? fmt::format("'{}'", scene.materials[size_t(material)].name)
                            : fmt::format("#{}", material);
    // The main view's HDR target; cube captures check their own format when they add the pass.
    requireBlendable(rhi::Format::RGBA16_FLOAT, "the HDR target");
}

rhi::BlendAttachment TransparentShading::blendState() {
    return rhi::BlendAttachment{true,
                                rhi::BlendFactor::One,
                                rhi::BlendFactor::OneMinusSrcAlpha,
                                rhi::BlendOp::Add,
                                rhi::BlendFactor::One,
                                rhi::BlendFactor::OneMinusSrcAlpha,
                                rhi::BlendOp::Add,
                                0xF};
}

void TransparentShading::requireBlendable(rhi::Format format, const std::string& target) const {
    if (m_device.formatCapabilities(format).has(rhi::FormatCapability::Blendable)) return;
    throw RendererError(fmt::format(
        "the scene has materials with alphaMode BLEND (material {} and maybe others), whose transparent pass blends into {} ({}); "
        "this {} device cannot blend into {} (format capability '{}'{}). Render the scene on a device that can, or make those "
        "materials OPAQUE or MASK",
        m_blendedMaterial, target, rhi::toString(format), rhi::toString(m_device.info().backend), rhi::toString(format),
        rhi::toString(rhi::FormatCapability::Blendable),
        m_device.info().backend == rhi::Backend::GLES ? "; OpenGL ES 3.0 needs EXT_color_buffer_half_float for rgba16f" : ""));
}

void TransparentShading::addPasses(PassGraph& graph, const SceneView& view) {
    if (!m_gpuScene.viewSeesBlended(view)) return;
    const ViewTarget* color = graph.find(view.name, frame_resources::kHdr);
    const ViewTarget* depth = graph.find(view.name, frame_resources::kDepth);
    if (!color || !depth)
        throw RendererError(fmt::format("transparent shading: view '{}' has no '{}' and '{}' targets", view.name,
                                        frame_resources::kHdr, frame_resources::kDepth));
    requireBlendable(view.colorFormat, fmt::format("view '{}'", view.name));
    auto it = std::find_if(m_views.begin(), m_views.end(), [&](const auto& s) { return s->view.name == view.name; });
    if (it == m_views.end()) it = m_views.insert(m_views.end(), std::make_unique<ViewState>());
    ViewState& state = **it;
    state = ViewState{};
    state.view = view;
    state.color = *color;
    state.depth = *depth;

    PassGraph::PassDesc pass;
    pass.name = "transparent";
    pass.view = view.name;
    pass.reads = {color->resource, depth->resource};
    const std::vector<PassGraph::ResourceId>& lighting = m_forward.lightingInputs(view.name);
    pass.reads.insert(pass.reads.end(), lighting.begin(), lighting.end());
    pass.writes = {color->resource};
    pass.setup = [this, &state] { setup(state); };
    pass.record = [this, &state](rhi::ICommandList& cmd, PassReport& report) { record(state, cmd, report); };
    graph.addPass(std::move(pass));
}

void TransparentShading::setup(ViewState& state) {
    // A view's camera is fixed once its graph is built, so the order is too.
    state.order = m_gpuScene.sortBlendedBackToFront(state.view);
    state.bindings = m_forward.viewBindings(state.view.name);
    pipelines(state.view);
}

const GpuScene::BlendedPipelines& TransparentShading::pipelines(const SceneView& view) {
    const PipelineKey key{view.colorFormat, view.depthFormat, view.mirrored, view.sampleCount};
    auto it = m_pipelines.find(key);
    if (it != m_pipelines.end()) return it->second;
    // Tested against the opaque surfaces' depth (LessOrEqual, as forward after the prepass), not
    // written: blended surfaces never hide each other, the order composites them.
    GpuScene::BlendedPipelines made = m_gpuScene.createBlendedPipelines(
        m_forward.vertexShader(), m_forward.fragmentShader(), rhi::DepthState{true, false, rhi::CompareOp::LessOrEqual},
        blendState(), view.colorFormat, view.depthFormat, view.mirrored, "transparent", view.sampleCount);
    return m_pipelines.emplace(key, std::move(made)).first->second;
}

void TransparentShading::record(const ViewState& state, rhi::ICommandList& cmd, PassReport& report) {
    cmd.beginRenderPass(rhi::RenderPassDesc{}
                            .addColor(rhi::Attachment::load(state.color.texture, state.color.subresource))
                            .setDepth(rhi::Attachment::load(state.depth.texture, state.depth.subresource)));
    m_gpuScene.drawBlended(cmd, state.order, pipelines(state.view), state.bindings, report);
    cmd.endRenderPass();
}

}  // namespace janus::renderer
