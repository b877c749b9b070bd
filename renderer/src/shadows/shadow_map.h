// Shadow map for the main directional light (internal to the renderer; see docs/SHADOWS.md).
//
// Usage, once per scene:   DirectionalShadowMap shadows(device, 1024);
//                          shadows.fit(light.direction, sceneMin, sceneMax);
//                          shadows.setCasters(casters);            // caster slots and their binding set made here
// once per frame:          shadows.record(cmd, casters, draws);    // one depth-only render pass
// in the forward pass:     shadows.binding(JANUS_BINDING_SHADOW_MAP) in set 0 (sampler2DShadow), worldToShadow() and
//                          texelSize() / normalOffset() in the frame uniforms, and
//                          shaders/renderer/shadow_sampling.glsl in the shader.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "janus/rhi/rhi.h"

namespace janus::renderer {

struct Scene;
struct Light;

// World-space axis-aligned bounds of every instance's vertices. Empty (min > max) for a scene
// without vertices.
struct WorldBounds {
    glm::vec3 min{INFINITY};
    glm::vec3 max{-INFINITY};
    bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
};
WorldBounds sceneWorldBounds(const Scene& scene);

// mainDirectionalLight(scene) is public (janus/renderer/renderer.h); the same over a light list
// (Renderer::setLights), an index into `lights`.
std::optional<size_t> mainDirectionalLight(std::span<const Light> lights, uint32_t shadedDirectionalLights = 4);

// One mesh drawn into the shadow map. The vertex buffer holds renderer Vertex structs (position
// at offset 0); the index buffer holds uint32 indices.
struct ShadowCaster {
    rhi::BufferHandle vertices;
    rhi::BufferHandle indices;
    uint32_t indexCount = 0;
    glm::mat4 world{1.0f};
    bool doubleSided = false;   // drawn without face culling, like the forward pass draws it
    // A negative determinant of `world` (a mirrored node) flips the winding; record() picks the
    // pipeline that culls the right faces from the matrix it draws with.
};

class DirectionalShadowMap {
public:
    static constexpr rhi::Format kDepthFormat = rhi::Format::D32_FLOAT;
    static constexpr uint32_t kMinSize = 16;   // fit() keeps a border of a few texels
    // Polygon offset of the shadow pass. Slope-scaled bias removes acne on surfaces at grazing
    // angles to the light; the constant part (in units of the D32F value's ulp) covers the flat
    // case. The normal offset in shadow_sampling.glsl does the rest, so both stay small enough
    // not to detach shadows from their casters (peter-panning).
    static constexpr float kDepthBiasConstant = 2.0f;
    static constexpr float kDepthBiasSlope = 2.0f;

    // Creates the depth texture (size x size D32F), the compare sampler and the depth-only
    // pipelines. Throws RendererError when `size` is below kMinSize or above the device's
    // maximum 2D texture size.
    DirectionalShadowMap(rhi::IDevice& device, uint32_t size);

    // Fits an orthographic light view-projection around the axis-aligned box [sceneMin, sceneMax]
    // seen along `lightDirection` (the way the light travels; need not be unit length). The map
    // is square in world units, keeps two texels of border for the PCF kernel and is snapped to
    // whole texels, so equal inputs always give bit-equal matrices. An empty or inverted box is
    // treated as a point at its centre. Throws RendererError for a zero or non-finite direction
    // or non-finite bounds.
    void fit(const glm::vec3& lightDirection, const glm::vec3& sceneMin, const glm::vec3& sceneMax);

    // World -> clip space of the shadow pass (Vulkan conventions: depth [0, 1], NDC y = -1 is row 0).
    const glm::mat4& lightViewProjection() const { return m_lightViewProjection; }
    // World -> (u, v, depth): u, v in [0, 1] with v = 0 at row 0, depth in [0, 1] as stored in the
    // map; exactly the coordinates texture(sampler2DShadow, vec3) expects (w stays 1).
    glm::mat4 worldToShadow() const;
    // 1 / size: one texel in u, v (the PCF kernel's step).
    float texelSize() const { return 1.0f / float(m_size); }
    // World-space width of one texel (square texels).
    float texelWorldSize() const { return m_texelWorldSize; }
    // Suggested normal offset for shadowCoordFor() in world units (1.5 texels, see docs/SHADOWS.md).
    float normalOffset() const { return 1.5f * m_texelWorldSize; }
    uint32_t size() const { return m_size; }
    const glm::vec3& lightDirection() const { return m_lightDirection; }

    // Prepares one uniform slot per caster and the set that shows one slot at a time (a dynamic
    // uniform buffer: each draw binds it at its caster's slot). Call when the set of casters
    // changes; record() calls it itself when given more casters than were prepared.
    void setCasters(std::span<const ShadowCaster> casters);

    // Records the depth-only render pass: clears the map to 1 and draws every caster with an
    // index count, then calls `drawInPass` (when given) inside the same pass: casters its owner
    // draws itself (alpha-masked ones, whose alpha test needs their materials). Changed world
    // matrices or a changed fit are uploaded by a copy recorded before the pass. Adds the number
    // of caster draws to `drawCount`.
    void record(rhi::ICommandList& cmd, std::span<const ShadowCaster> casters, uint32_t& drawCount,
                const std::function<void(rhi::ICommandList&)>& drawInPass = {});
    // The polygon offset of the map's own pipelines, for pipelines that draw into its pass.
    static rhi::RasterState depthBias();

    // Whether the map holds what record() would draw now: it was recorded since it was made, since
    // setCasters and since a fit that changed the light's view-projection (a fit to the same light
    // and bounds changes nothing). Casters that moved since are for its owner to know. Its owner
    // records it again only when not (a static scene's map is drawn once).
    bool upToDate() const { return m_upToDate; }

    // The map as a sampler2DShadow at `slot` (compare LessOrEqual: 1 = lit, linear filtering
    // gives hardware 2x2 PCF per tap).
    rhi::BindingItem binding(uint32_t slot) const;
    const rhi::TextureHandle& texture() const { return m_depth; }
    const rhi::SamplerHandle& compareSampler() const { return m_compareSampler; }

private:
    void uploadPassUniforms(rhi::ICommandList& cmd);

    rhi::IDevice& m_device;
    uint32_t m_size = 0;
    rhi::TextureHandle m_depth;
    rhi::SamplerHandle m_compareSampler;
    // Culled casters with the light's winding, and with the opposite one for mirrored casters
    // (a world matrix with a negative determinant turns their front faces clockwise).
    rhi::PipelineHandle m_culledPipeline, m_doubleSidedPipeline, m_culledMirroredPipeline;
    rhi::BufferHandle m_passUniforms;     // set 0, binding 0: light view-projection
    rhi::BindingSetHandle m_passBindings;
    rhi::BufferHandle m_casterUniforms;   // set 1, binding 1: one world matrix slot per caster
    // Set 1: one window onto m_casterUniforms, moved to each caster's slot by its bind's dynamic
    // offset (no set per caster).
    rhi::BindingSetHandle m_casterBindings;
    size_t m_casterSlots = 0;
    std::vector<glm::mat4> m_casterWorlds;   // what the slots on the GPU hold
    uint64_t m_casterStride = 0;
    bool m_passUniformsDirty = true;
    bool m_fitted = false;
    bool m_upToDate = false;
    glm::vec3 m_lightDirection{0.0f, -1.0f, 0.0f};
    glm::mat4 m_lightViewProjection{1.0f};
    float m_texelWorldSize = 0.0f;
};

}  // namespace janus::renderer
