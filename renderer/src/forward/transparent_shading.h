// Transparent shading feature (internal to the renderer; docs/LIGHTING.md, "Transparent
// surfaces"): the glTF alphaMode BLEND instances, which the depth prepass, the forward pass and
// the shadow map leave out. After the sky (so they composite over it), the "transparent" pass
// draws them back to front per instance (GpuScene::sortBlendedBackToFront) into the view's HDR
// target, depth tested against the opaque depth (LessOrEqual) without writing it, with the
// forward shader and the forward pass's view bindings: the same directional lights and shadow,
// local lights (the same tile lists), sky and reflection probes. forward.frag writes
// premultiplied radiance and coverage alpha for them; the pipelines blend One, OneMinusSrcAlpha.
//
// Only views that see a blended instance (their rendering layers) get the pass, so a scene
// without BLEND materials has none.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "core/gpu_scene.h"
#include "core/pass_graph.h"
#include "core/render_feature.h"
#include "forward/forward_shading.h"

namespace janus::renderer {

class TransparentShading final : public RenderFeature {
public:
    // Throws RendererError when the scene has blended instances and the device cannot blend into
    // the HDR format (FormatCapability::Blendable of RGBA16F; e.g. ES 3.0 without
    // EXT_color_buffer_half_float), naming a blended material.
    TransparentShading(rhi::IDevice& device, const Scene& scene, const GpuScene& gpuScene, const ForwardShading& forward);

    // The blending of the transparent pass: premultiplied alpha "over" (One, OneMinusSrcAlpha for
    // colour and alpha, so the HDR target's alpha stays 1).
    static rhi::BlendAttachment blendState();

    // Adds "transparent" for a view that sees a blended instance: reads the view's kHdr and
    // kDepth and what its forward pass reads, writes kHdr. Throws RendererError when the view's
    // colour format cannot be blended on this device.
    void addPasses(PassGraph& graph, const SceneView& view) override;

private:
    struct ViewState {
        SceneView view;
        ViewTarget color, depth;
        std::vector<uint32_t> order;   // back to front, indices into GpuScene::blendedDraws()
        rhi::BindingSetHandle bindings;
    };
    using PipelineKey = std::tuple<rhi::Format, rhi::Format, bool /*mirrored*/, uint32_t /*samples*/>;

    void requireBlendable(rhi::Format format, const std::string& target) const;
    void setup(ViewState& state);
    const GpuScene::BlendedPipelines& pipelines(const SceneView& view);
    void record(const ViewState& state, rhi::ICommandList& cmd, PassReport& report);

    rhi::IDevice& m_device;
    const GpuScene& m_gpuScene;
    const ForwardShading& m_forward;
    std::string m_blendedMaterial;   // one of the scene's blended materials, for messages
    std::vector<std::unique_ptr<ViewState>> m_views;   // by view name, reused when a view renders again
    std::map<PipelineKey, GpuScene::BlendedPipelines> m_pipelines;
};

}  // namespace janus::renderer
