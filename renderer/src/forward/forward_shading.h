// Forward shading feature (internal to the renderer; docs/LIGHTING.md): for each view, the
// depth prepass (tiled culling only), the tile-list builder (LocalLights) and the forward pass
// that shades every mesh with the directional lights, the local lights and the main light's
// shadow into the view's HDR target.
//
// Per view it owns the frame uniforms (set JANUS_SET_VIEW: camera, lights, shadow, tile grid)
// and the view's binding set; pipelines are shared between views with the same target formats
// and handedness.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "core/gpu_scene.h"
#include "core/pass_graph.h"
#include "core/render_feature.h"
#include "forward/frame_uniforms.h"
#include "forward/lighting_settings.h"
#include "forward/local_lights.h"
#include "gi/probe_gi.h"
#include "ibl/image_based_lighting.h"
#include "probes/reflection_probes.h"
#include "shadows/main_light_shadows.h"

namespace janus::renderer {



class ForwardShading final : public RenderFeature {
public:
    ForwardShading(rhi::IDevice& device, const Scene& scene, const GpuScene& gpuScene, LocalLights& localLights,
                   MainLightShadows& shadows, const ImageBasedLighting& imageBasedLighting,
                   const ReflectionProbes& reflectionProbes, const ProbeGi& probeGi, FeaturePath path);

    // Adds, for `view`: depth-prepass and the tile-list builder (when the view is tiled), then
    // forward, which writes the view's kHdr target (RGBA16F radiance, cleared to the ambient
    // colour) and kDepth. It reads kShadowMap only if the view wants shadows, and the sky
    // (ibl_resources::kSkyLight) when the frame has one. Publishes the
    // view's kTileLists when it is tiled (the tile heat map reads them).
    void addPasses(PassGraph& graph, const SceneView& view) override;

    // Renderer::setLights: the directional lights of every view's frame uniforms (and the shadow
    // matrices, so call it after MainLightShadows::setLights); the local lights are LocalLights'.
    void setLights(std::span<const Light> lights);

    // What the transparent pass (TransparentShading) shades a view with, the same as `forward`:
    // the resources forward reads besides the targets (tile lists, shadow map, sky, probes) once
    // addPasses ran for the view, and the view's set JANUS_SET_VIEW once forward's setup ran.
    // Throw RendererError for a view forward shading has not seen (or not set up).
    const std::vector<PassGraph::ResourceId>& lightingInputs(const std::string& viewName) const;
    const rhi::BindingSetHandle& viewBindings(const std::string& viewName) const;
    const rhi::ShaderHandle& vertexShader() const { return m_vertexShader; }
    const rhi::ShaderHandle& fragmentShader() const { return m_forwardShader; }

private:
    struct ViewState {
        SceneView view;
        bool tiled = false;
        bool shadowed = false;
        ViewTarget color, depth;
        std::vector<PassGraph::ResourceId> lightingInputs;
        rhi::BufferHandle frameUniforms;
        rhi::BindingSetHandle bindings;
        GpuScene::MeshPipelines forward, prepass;
    };
    // The mesh pipelines a view's passes draw with: the depth prepass's, the forward pass's, and
    // with alpha to coverage (SceneView::alphaToCoverage) the forward pass's for alpha-masked
    // draws, which cover samples by alpha and write depth (the prepass leaves them out: it has no
    // colour attachment, which alpha to coverage needs; rhi::GraphicsPipelineDesc::alphaToCoverage).
    enum class MeshPass { Prepass, Forward, ForwardMaskedCoverage };
    using PipelineKey = std::tuple<MeshPass, bool /*tiled*/, rhi::Format, rhi::Format, bool /*mirrored*/, uint32_t /*samples*/>;

    const ViewState& stateOf(const std::string& viewName) const;
    FrameUniforms viewFrameUniforms(const ViewState& state) const;
    void setupView(ViewState& state);
    const GpuScene::MeshPipelines& pipelines(MeshPass pass, const ViewState& state);
    // What alpha-masked draws take in `pass` (GpuScene::drawMeshes): nullptr = the pass's own
    // pipelines; with alpha to coverage, none in the prepass and their own in the forward pass.
    const GpuScene::MeshPipelines* maskedPipelines(MeshPass pass, const ViewState& state);
    void recordPrepass(const ViewState& state, rhi::ICommandList& cmd, PassReport& report);
    void recordForward(const ViewState& state, rhi::ICommandList& cmd, PassReport& report);

    rhi::IDevice& m_device;
    const GpuScene& m_gpuScene;
    LocalLights& m_localLights;
    MainLightShadows& m_shadows;
    const ImageBasedLighting& m_imageBasedLighting;
    const ReflectionProbes& m_reflectionProbes;
    const ProbeGi& m_probeGi;
    FeaturePath m_path;
    std::array<float, 4> m_background{};
    FrameUniforms m_sceneUniforms{};   // the view-independent part: ambient and directional lights
    std::vector<std::unique_ptr<ViewState>> m_views;
    std::map<PipelineKey, GpuScene::MeshPipelines> m_pipelines;
    rhi::ShaderHandle m_vertexShader, m_forwardShader, m_prepassShader;
};

}  // namespace janus::renderer
