// Shadows feature (internal to the renderer): the main directional light's shadow map
// (DirectionalShadowMap, docs/SHADOWS.md) for every view that wants shadows, or a 1x1 stand-in
// bound where there is none. The map does not depend on the camera, so one "shadow-map" pass per
// frame serves all views; when no view wants shadows, the pass is culled and the map never made.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "core/gpu_scene.h"
#include "core/pass_graph.h"
#include "core/render_feature.h"
#include "shadows/shadow_map.h"

namespace janus::renderer {

class MainLightShadows final : public RenderFeature {
public:
    // Finds the main light (mainDirectionalLight over the first `shadedDirectionalLights`), the
    // scene bounds and the casters; makes no GPU resource for the map yet.
    MainLightShadows(rhi::IDevice& device, const Scene& scene, const GpuScene& gpuScene, bool enabled, uint32_t mapSize,
                     uint32_t shadedDirectionalLights);

    // True when the scene has something to shadow: shadows on, a main light that gives light,
    // and meshes with geometry that cast shadows (alphaMode BLEND ones do not).
    bool active() const { return m_hasMainLight && hasCasters(); }

    // Renderer::setLights. checkLights throws RendererError when `lights` would need the
    // shadow-map pass this frame was planned without (a main light where there was none, with
    // shadows on and casters). setLights points the maps at the new main light and refits them;
    // without a main light in `lights` the pass stays (the plan is kept), shadowing nothing lit.
    void checkLights(std::span<const Light> lights) const;
    void setLights(std::span<const Light> lights);

    // Adds the "shadow-map" pass once per frame graph and map size (the map does not depend on
    // the view) and publishes it as frame_resources::kShadowMap: frame-wide for the renderer's
    // size, under the view's name for a view that asks for another (ViewPasses::shadowMapSize, a
    // reflection probe's setting). Views that want shadows read it, and when none does the graph
    // culls the pass. Its setup creates and fits that size's map (once, however many graphs add
    // the pass). Adds nothing when not active().
    void addPasses(PassGraph& graph, const SceneView& view) override;

    // The map of `size` (0 = the renderer's); valid once its pass setup ran (null before, and when
    // the pass was culled).
    const DirectionalShadowMap* map(uint32_t size = 0) const;
    uint32_t mapSize() const { return m_mapSize; }
    // The map (when made) or the stand-in, as the sampler2DShadow at `slot`.
    rhi::BindingItem binding(uint32_t slot) const;

private:
    // Alpha-masked casters cast only where their alpha test keeps them, as the forward pass draws
    // them: they are drawn through the scene's own draws (GpuScene::drawSelected) with the depth
    // prepass's shaders (forward.vert, depth_prepass.frag), their materials and the map's
    // polygon offset, into the map's pass after the other casters. Each map has its own view
    // uniforms (the light's view-projection as FrameUniforms::viewProjection).
    struct MaskedView {
        rhi::BufferHandle frameUniforms;
        rhi::BindingSetHandle bindings;
    };

    bool hasCasters() const { return !m_casters.empty() || !m_maskedDraws.empty(); }
    DirectionalShadowMap& createMap(uint32_t size);
    void recordMap(rhi::ICommandList& cmd, uint32_t size, PassReport& report);

    rhi::IDevice& m_device;
    const GpuScene& m_gpuScene;
    uint32_t m_mapSize = 0;
    uint32_t m_shadedDirectionalLights = 0;
    bool m_hasMainLight = false;
    glm::vec3 m_lightDirection{0.0f, -1.0f, 0.0f};
    WorldBounds m_bounds;
    std::vector<ShadowCaster> m_casters;    // opaque: the map's own position-only pipelines
    std::vector<uint32_t> m_maskedDraws;     // alpha-masked: indices into m_gpuScene.draws()
    GpuScene::MeshPipelines m_maskedPipelines;   // made with the first map
    std::map<uint32_t, std::unique_ptr<DirectionalShadowMap>> m_maps;   // by size
    std::map<uint32_t, MaskedView> m_maskedViews;                       // by size, where masked casters exist
    rhi::TextureHandle m_standInTexture;   // bound when nothing casts shadows
    rhi::SamplerHandle m_standInSampler;
};

}  // namespace janus::renderer
