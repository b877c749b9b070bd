// The scene on the GPU, uploaded once (internal to the renderer): meshes, material textures and
// samplers, and one draw per instance. A draw's uniforms are its slot of one buffer, which one
// binding set shows as a dynamic window (set JANUS_SET_DRAW, the slot's offset given at each
// bind); a material's five textures are a set per material (JANUS_SET_MATERIAL), bound when the
// material changes (draws are sorted by material within each pipeline). Every feature that
// draws meshes for a view uses drawMeshes() (opaque and alpha-masked instances) or drawBlended()
// (alphaMode BLEND, back to front), so views and features share one way of drawing the scene.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "janus/renderer/frame_report.h"
#include "janus/renderer/scene.h"
#include "janus/renderer/scene_view.h"
#include "janus/rhi/rhi.h"

namespace janus::renderer {

class GpuScene {
public:
    struct Mesh {
        rhi::BufferHandle vertices;   // renderer Vertex (80 bytes)
        rhi::BufferHandle indices;    // uint32
        uint32_t indexCount = 0;
    };
    struct Draw {
        uint32_t mesh = 0;
        uint32_t instance = 0;
        bool doubleSided = false;
        // The world matrix flips handedness (negative determinant, e.g. a mirrored node): its
        // counter-clockwise front faces appear clockwise, so it draws with the opposite winding.
        bool mirrored = false;
        // alphaMode BLEND: not in draws() (so not in the prepass, the forward pass or the shadow
        // map) but in blendedDraws(), drawn by the transparent pass.
        bool blended = false;
        bool masked = false;   // alphaMode MASK: drawMeshes can give these pipelines of their own
        MeshTopology topology = MeshTopology::Triangles;   // points and lines draw without culling
        uint32_t renderingLayers = 1u;
        rhi::BufferHandle vertices;       // the mesh's, or the instance's posed vertices (MeshDeformer)
        glm::mat4 world{1.0f};
        glm::vec3 boundsCenter{0.0f};     // world-space centre of the mesh's bounding box (sorting)
        uint32_t uniformsOffset = 0;      // its DrawUniforms slot: the dynamic offset of set JANUS_SET_DRAW
        uint32_t material = 0;            // its material's set (JANUS_SET_MATERIAL): index into m_materialBindings
    };
    // The pipelines of one kind of mesh pass: back-face culled, and without culling for
    // double-sided materials, each with the view's winding and with the opposite one for
    // mirrored instances; line and point lists (null where the scene has no such draw).
    struct MeshPipelines {
        rhi::PipelineHandle culled;
        rhi::PipelineHandle doubleSided;
        rhi::PipelineHandle culledMirrored;
        rhi::PipelineHandle doubleSidedMirrored;
        rhi::PipelineHandle lines;
        rhi::PipelineHandle points;
        const rhi::PipelineHandle& forDraw(const Draw& draw) const {
            if (draw.topology == MeshTopology::Lines) return lines;
            if (draw.topology == MeshTopology::Points) return points;
            return draw.doubleSided ? (draw.mirrored ? doubleSidedMirrored : doubleSided) : (draw.mirrored ? culledMirrored : culled);
        }
    };

    // The pipelines of the transparent pass (alpha blending, no depth writes). A double-sided
    // blended instance draws twice: its back faces (frontCulled) first, then its front faces
    // (backCulled), so a closed convex mesh composites its far side under its near side.
    struct BlendedPipelines {
        rhi::PipelineHandle backCulled;
        rhi::PipelineHandle frontCulled;           // double-sided draws' back faces
        rhi::PipelineHandle backCulledMirrored;
        rhi::PipelineHandle frontCulledMirrored;
        rhi::PipelineHandle lines;                 // blended line and point lists: one draw each
        rhi::PipelineHandle points;
    };

    GpuScene(rhi::IDevice& device, const Scene& scene);

    // The renderer Vertex as vertex buffer `binding`: locations 0-5 (position, normal, uv,
    // tangent, uv1, colour), as forward.vert and deform_points.vert read them.
    static rhi::GraphicsPipelineDesc& addVertexLayout(rhi::GraphicsPipelineDesc& desc, uint32_t binding = 0);

    const std::vector<Mesh>& meshes() const { return m_meshes; }
    // Draws instance `instance` from `vertices` (Vertex layout, at least the mesh's vertex count)
    // instead of its mesh's buffer: the mesh deformer's posed vertices.
    void useInstanceVertices(uint32_t instance, rhi::BufferHandle vertices);
    // The vertex buffer instance `instance` is drawn from (shadow casters use it too).
    const rhi::BufferHandle& instanceVertices(uint32_t instance) const;
    // Opaque and alpha-masked instances with geometry, single-sided first, unmirrored first
    // (fewer pipeline switches).
    const std::vector<Draw>& draws() const { return m_draws; }
    // alphaMode BLEND instances with geometry, in scene (instance) order.
    const std::vector<Draw>& blendedDraws() const { return m_blendedDraws; }
    // Whether `view` (its rendering layers) sees any blended instance.
    bool viewSeesBlended(const SceneView& view) const;
    // Whether draws() holds alpha-masked instances (their own pipelines with alpha to coverage).
    bool hasMaskedDraws() const { return m_hasMasked; }
    // Nearest, clamp: for targets and data textures read with texelFetch (filtering never applies).
    const rhi::SamplerHandle& pointSampler() const { return m_pointSampler; }

    // Pipelines that draw the scene's Vertex layout with `vertexShader`/`fragmentShader` into a
    // target of the given formats (colorFormat Unknown: depth only). A mirrored view's
    // front faces are clockwise, and a mirrored instance flips that again.
    // `depthBias`: its polygon offset (the shadow map's alpha-masked casters); its culling and
    // winding are the pipelines' own. `alphaToCoverage`: rhi::GraphicsPipelineDesc's (sampleCount > 1).
    MeshPipelines createMeshPipelines(const rhi::ShaderHandle& vertexShader, const rhi::ShaderHandle& fragmentShader,
                                      rhi::DepthState depth, rhi::Format colorFormat, rhi::Format depthFormat, bool mirrored,
                                      const std::string& name, const rhi::RasterState& depthBias = {}, uint32_t sampleCount = 1,
                                      bool alphaToCoverage = false) const;

    // Pipelines without face culling (every field set; gl_FrontFacing tells the sides apart) into
    // the given colour targets: the GI bake's G-buffer. Triangles only: drawMeshes with these
    // skips points and lines.
    MeshPipelines createUnculledPipelines(const rhi::ShaderHandle& vertexShader, const rhi::ShaderHandle& fragmentShader,
                                          rhi::DepthState depth, const std::vector<rhi::Format>& colorFormats, rhi::Format depthFormat,
                                          bool mirrored, const std::string& name) const;

    // The same for the transparent pass: `blend` on the one colour attachment, and the culling
    // of BlendedPipelines (null where the scene has no such blended draw).
    BlendedPipelines createBlendedPipelines(const rhi::ShaderHandle& vertexShader, const rhi::ShaderHandle& fragmentShader,
                                            rhi::DepthState depth, rhi::BlendAttachment blend, rhi::Format colorFormat,
                                            rhi::Format depthFormat, bool mirrored, const std::string& name,
                                            uint32_t sampleCount = 1) const;

    // Draws every opaque or alpha-masked instance the view sees (its rendering layers) inside the
    // current render pass: set JANUS_SET_VIEW = viewBindings, set JANUS_SET_DRAW at each draw's
    // uniforms, set JANUS_SET_MATERIAL = its material's textures. Alpha-masked draws take
    // `maskedPipelines` when given (an empty MeshPipelines leaves them out).
    void drawMeshes(rhi::ICommandList& cmd, const SceneView& view, const MeshPipelines& pipelines,
                    const rhi::BindingSetHandle& viewBindings, PassReport& report,
                    const MeshPipelines* maskedPipelines = nullptr) const;
    // The same for draws()[i] for each i of `drawIndices`, whatever their layers (the shadow map's
    // alpha-masked casters: the renderer chose them).
    void drawSelected(rhi::ICommandList& cmd, std::span<const uint32_t> drawIndices, const MeshPipelines& pipelines,
                      const rhi::BindingSetHandle& viewBindings, PassReport& report) const;

    // The blended instances `view` sees, back to front: by the view-space depth of their bounds
    // centre, farthest first; ties keep scene order. Indices into blendedDraws().
    std::vector<uint32_t> sortBlendedBackToFront(const SceneView& view) const;
    // Draws blendedDraws()[i] for each i of `order`, in that order (a double-sided one as two
    // draws: back faces, then front faces), inside the current render pass.
    void drawBlended(rhi::ICommandList& cmd, const std::vector<uint32_t>& order, const BlendedPipelines& pipelines,
                     const rhi::BindingSetHandle& viewBindings, PassReport& report) const;

private:
    // What the draws of one pass bound so far: each is bound again only when it changes. The
    // backends also skip a buffer bound again, but the call still passes the front's checks:
    // leaving it out here kept a Vulkan forward draw about 30 ns cheaper when measured (session
    // 27; the other passes and backends within noise).
    struct BoundForDraws {
        const rhi::IPipeline* pipeline = nullptr;
        uint32_t material = UINT32_MAX;
        const rhi::IBuffer* vertices = nullptr;
        const rhi::IBuffer* indices = nullptr;
    };
    void recordDraw(rhi::ICommandList& cmd, const rhi::PipelineHandle& pipeline, const Draw& draw,
                    const rhi::BindingSetHandle& viewBindings, BoundForDraws& bound, PassReport& report) const;
    rhi::PipelineHandle createMeshPipeline(const rhi::ShaderHandle& vertexShader, const rhi::ShaderHandle& fragmentShader,
                                           rhi::CullMode cull, bool clockwise, rhi::DepthState depth, rhi::BlendAttachment blend,
                                           const std::vector<rhi::Format>& colorFormats, rhi::Format depthFormat,
                                           const std::string& name,
                                           rhi::PrimitiveTopology topology = rhi::PrimitiveTopology::TriangleList,
                                           const rhi::RasterState& depthBias = {}, uint32_t sampleCount = 1,
                                           bool alphaToCoverage = false) const;
    // The line and point pipelines of `pipelines` (where the scene has such draws).
    void addLineAndPointPipelines(rhi::PipelineHandle& lines, rhi::PipelineHandle& points, const rhi::ShaderHandle& vertexShader,
                                  const rhi::ShaderHandle& fragmentShader, rhi::DepthState depth, rhi::BlendAttachment blend,
                                  const std::vector<rhi::Format>& colorFormats, rhi::Format depthFormat, const std::string& name,
                                  bool blended, uint32_t sampleCount, bool alphaToCoverage = false) const;
    // Level 0 from `rgba`, then the levels below it (mipChainBelow).
    rhi::TextureHandle createTexture(const std::string& name, uint32_t width, uint32_t height, std::span<const uint8_t> rgba, bool srgb,
                                     const std::vector<std::vector<uint8_t>>& mipsBelow);
    rhi::SamplerHandle createSampler(const TextureSampling& sampling);
    void uploadTextures(const Scene& scene);
    void uploadMeshes(const Scene& scene);
    void createDraws(const Scene& scene);

    rhi::IDevice& m_device;
    std::vector<Mesh> m_meshes;
    std::vector<rhi::BufferHandle> m_instanceVertices;   // per scene instance
    std::vector<Draw> m_draws, m_blendedDraws;
    bool m_hasKind[2][2] = {};          // [doubleSided][mirrored]: which pipelines draws() needs
    bool m_hasBlendedKind[2][2] = {};   // the same for blendedDraws()
    bool m_hasMasked = false;           // draws() holds an alphaMode MASK instance
    bool m_hasTopology[2][3] = {};      // [blended][MeshTopology]: which topologies draws() / blendedDraws() hold
    std::vector<rhi::TextureHandle> m_textures;
    std::vector<rhi::SamplerHandle> m_textureSamplers;   // per scene texture, shared between equal samplings
    rhi::TextureHandle m_whiteTexture, m_flatNormalTexture;
    rhi::SamplerHandle m_materialSampler, m_pointSampler;
    rhi::BufferHandle m_drawUniforms;
    rhi::BindingSetHandle m_drawBindings;                 // set JANUS_SET_DRAW: one window into m_drawUniforms
    std::vector<rhi::BindingSetHandle> m_materialBindings;   // set JANUS_SET_MATERIAL: one per material drawn
};

}  // namespace janus::renderer
