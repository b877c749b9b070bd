// Mesh deformation on the GPU (internal to the renderer): skins and morph targets.
//
// Recipe. Every instance whose mesh has morph targets, or joints and a skin, gets its own posed
// vertex buffer in the renderer's Vertex layout; GpuScene draws that instance from it, so every
// pass that draws meshes (shadow map, prepass, forward, transparent, cube captures, the GI bake)
// sees the posed geometry without knowing about skins. A vertex is morphed first (the targets'
// displacements times the instance's morph weights), then skinned (the weighted sum of its four
// joint matrices), in deform_common.glsl, the math both paths share:
//   - compute path: deform.comp, one invocation per vertex, reads the mesh's vertices, joints and
//     weights, displacements and joint matrices from storage buffers and writes the posed buffer;
//   - fallback path (no compute, no SSBOs: GLES 3.0): deform_points.vert does the same in a vertex
//     shader with the joint matrices and displacements in RGBA32F textures, and draws five
//     one-pixel points per vertex into an RGBA32F target, one 16-byte texel of the 80-byte Vertex
//     each; the target is then copied into the posed buffer. So both paths hand the frame the
//     same buffer, and the rest of the renderer has one way of drawing deformed meshes.
// The scene's pose is fixed for the renderer's life (poseScene before making the renderer): the
// deformation runs once, when the renderer is made, and is reported with the first frame.
#pragma once

#include <cstdint>
#include <vector>

#include "core/gpu_scene.h"
#include "core/render_feature.h"
#include "janus/renderer/scene.h"
#include "janus/renderer/settings.h"
#include "janus/rhi/rhi.h"

namespace janus::renderer {

class MeshDeformer : public RenderFeature {
public:
    // Whether `instance` of `scene` is deformed: its mesh has morph targets, or joints and the
    // instance a skin.
    static bool deforms(const Scene& scene, const Instance& instance);
    static bool needed(const Scene& scene);

    // Deforms every deformed instance of `scene` now and points `gpuScene`'s draws of them at the
    // posed buffers. `scene` must have passed validateScene.
    MeshDeformer(rhi::IDevice& device, const Scene& scene, GpuScene& gpuScene, FeaturePath path);

    void addPasses(PassGraph&, const SceneView&) override {}
    std::vector<PassReport> takeStartupReports() override { return std::move(m_startupReports); }

    // Instance `instance`'s posed vertices (Vertex layout; the fallback path's buffer may be
    // longer than the vertices), or null when it is not deformed.
    rhi::BufferHandle posedVertices(uint32_t instance) const;

private:
    struct MeshData {
        rhi::BufferHandle base;        // the mesh's vertices: storage (compute) | vertex buffer (fallback)
        rhi::BufferHandle skin;        // per vertex (joints as floats, weights): storage | vertex buffer
        rhi::BufferHandle morphBuffer;     // compute: displacements
        rhi::TextureHandle morphTexture;   // fallback: displacements
        uint32_t vertexCount = 0;
    };
    struct InstanceData {
        uint32_t instance = 0;
        uint32_t mesh = 0;
        rhi::BufferHandle uniforms;
        rhi::BufferHandle jointBuffer;      // compute
        rhi::TextureHandle jointTexture;    // fallback
        rhi::TextureHandle target;          // fallback: the posed vertices as texels
        rhi::BufferHandle posed;
        rhi::BindingSetHandle bindings;
    };
    const MeshData& meshData(const Scene& scene, uint32_t mesh);
    void record(rhi::ICommandList& cmd, PassReport& report) const;

    rhi::IDevice& m_device;
    FeaturePath m_path;
    std::vector<MeshData> m_meshes;   // by mesh index; vertexCount 0 = not made (yet)
    std::vector<InstanceData> m_instances;
    rhi::PipelineHandle m_pipeline;
    rhi::SamplerHandle m_pointSampler;
    std::vector<PassReport> m_startupReports;
};

}  // namespace janus::renderer
