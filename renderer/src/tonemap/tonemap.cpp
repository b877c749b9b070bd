#include "tonemap/tonemap.h"

#include <glm/glm.hpp>

#include "core/gpu_util.h"
#include "janus/shaders/bindings.h"

namespace janus::renderer {
namespace {

constexpr uint32_t kTonemapGroupSize = 8;   // tonemap.comp local_size

// std140 mirror of tonemap_common.glsl's TonemapUniforms.
struct TonemapUniforms {
    glm::vec4 params;   // x exposure
};

}  // namespace

Tonemap::Tonemap(rhi::IDevice& device, float exposure, FeaturePath path, rhi::SamplerHandle pointSampler)
    : m_device(device), m_exposure(exposure), m_path(path), m_pointSampler(std::move(pointSampler)) {}

rhi::TextureUsage Tonemap::displayUsage(FeaturePath path) {
    return path == FeaturePath::Compute ? rhi::TextureUsage::Storage : rhi::TextureUsage::RenderTarget;
}

void Tonemap::addPass(PassGraph& graph, const std::string& view, const ViewTarget& hdr, const ViewTarget& display) {
    m_hdr = hdr;
    m_display = display;
    PassGraph::PassDesc pass;
    pass.name = m_path == FeaturePath::Compute ? "tonemap-compute" : "tonemap-fallback";
    pass.view = view;
    pass.reads = {hdr.resource};
    pass.writes = {display.resource};
    pass.setup = [this] { setup(); };
    pass.record = [this](rhi::ICommandList& cmd, PassReport& report) { record(cmd, report); };
    graph.addPass(std::move(pass));
}

void Tonemap::setup() {
    m_uniforms = makeUniformBuffer(m_device, TonemapUniforms{glm::vec4(m_exposure, 0.0f, 0.0f, 0.0f)}, "tonemap uniforms");
    rhi::BindingSetDesc bindings;
    bindings.add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_TONEMAP_UNIFORMS, m_uniforms))
        .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_TONEMAP_HDR, m_hdr.texture, m_pointSampler));
    if (m_path == FeaturePath::Compute) {
        bindings.add(rhi::BindingItem::storageImage(JANUS_BINDING_TONEMAP_DISPLAY, m_display.texture, m_display.subresource.mipLevel));
        m_pipeline = m_device.createComputePipeline(
            rhi::ComputePipelineDesc{}.setShader(makeShader(m_device, rhi::ShaderStage::Compute, "tonemap_comp")).setDebugName("tonemap"));
    } else {
        m_pipeline = m_device.createGraphicsPipeline(rhi::GraphicsPipelineDesc{}
                                                         .setShaders(makeShader(m_device, rhi::ShaderStage::Vertex, "fullscreen_vert"),
                                                                     makeShader(m_device, rhi::ShaderStage::Fragment, "tonemap_frag"))
                                                         .addColorFormat(m_display.texture->desc().format)
                                                         .setDebugName("tonemap"));
    }
    m_bindings = m_device.createBindingSet(bindings);
}

void Tonemap::record(rhi::ICommandList& cmd, PassReport& report) {
    const rhi::TextureDesc& desc = m_display.texture->desc();
    if (m_path == FeaturePath::Compute) {
        cmd.setPipeline(m_pipeline);
        cmd.setBindingSet(0, m_bindings);
        cmd.dispatch((desc.width + kTonemapGroupSize - 1) / kTonemapGroupSize, (desc.height + kTonemapGroupSize - 1) / kTonemapGroupSize);
        ++report.dispatches;
        return;
    }
    // Every pixel is written, so the previous contents do not matter.
    rhi::Attachment target = rhi::Attachment::clear(m_display.texture, {0, 0, 0, 0}, m_display.subresource);
    target.loadOp = rhi::LoadOp::DontCare;
    drawFullscreenTriangle(cmd, target, m_pipeline, m_bindings, report);
}

}  // namespace janus::renderer
