// L2 spherical-harmonic irradiance on the GPU (internal to the renderer; docs/IBL.md,
// "Spherical harmonics (L2)"): nine RGB coefficients of irradiance / pi from one mip of a cube
// map, the same numbers spherical_harmonics.h computes on the CPU in double.
//
// Compute path: sh_project.comp (16x16 groups, one per tile of a face, shared-memory tree
// reduction of one coefficient after another into per-group partials), then sh_reduce.comp (9
// groups sum the partials, apply A_l / pi) into a storage buffer of 9 vec4 (std430).
// Fallback path (no compute): sh_gather.frag sums each face row per coefficient into a 54 x size
// RGBA32F target, then sh_gather_final.frag sums those into a 9 x 1 RGBA32F texture.
// Both sum in float; the texel solid angles are computed in double on the CPU and uploaded.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include <glm/glm.hpp>

#include "core/pass_graph.h"
#include "janus/renderer/settings.h"

namespace janus::renderer {

class ShIrradiance {
public:
    ShIrradiance(rhi::IDevice& device, FeaturePath path);

    static const char* passName(FeaturePath path);   // "sh-irradiance-compute" | "sh-irradiance-fallback"

    // Adds the pass: reads `cubeResource` (whose texture is `cube`; mip `mip` is projected),
    // writes `shResource` (the coefficients: coefficientBuffer() or coefficientTexture()).
    void addPass(PassGraph& graph, PassGraph::ResourceId cubeResource, rhi::TextureHandle cube, uint32_t mip,
                 PassGraph::ResourceId shResource, const std::string& view = "");

    // Direct use (tests, tools): prepare() once for a cube and mip (pipelines, targets, binding
    // sets; throws RendererError for a cube that is not a sampled RGBA16F/RGBA32F TextureCube,
    // or a device without what the path needs), then record() into any command list.
    void prepare(const rhi::TextureHandle& cube, uint32_t mip = 0);
    void record(rhi::ICommandList& cmd, PassReport& report);
    // prepare + record + execute on a command list of its own.
    void run(const rhi::TextureHandle& cube, uint32_t mip = 0);

    // Reads the nine (r, g, b) irradiance / pi coefficients back (waits for the GPU).
    std::array<glm::vec3, 9> readCoefficients();

    FeaturePath path() const { return m_path; }
    // Where the result lives, for shading: a 144-byte buffer of 9 vec4 (compute path, Storage
    // and Uniform usage) or a 9 x 1 RGBA32F texture (fallback path). Null before prepare().
    const rhi::BufferHandle& coefficientBuffer() const { return m_coefficients; }
    const rhi::TextureHandle& coefficientTexture() const { return m_coefficientTexture; }

private:
    rhi::IDevice& m_device;
    FeaturePath m_path;
    rhi::TextureHandle m_cube;
    uint32_t m_mip = 0;
    uint32_t m_size = 0;
    uint32_t m_tiles = 0;   // compute: tiles per face side
    rhi::SamplerHandle m_nearest;
    rhi::BufferHandle m_uniforms;
    rhi::TextureHandle m_solidAngles;
    // Compute path.
    rhi::BufferHandle m_partials, m_coefficients;
    rhi::PipelineHandle m_projectPipeline, m_reducePipeline;
    rhi::BindingSetHandle m_projectBindings, m_reduceBindings;
    // Fallback path.
    rhi::TextureHandle m_rowSums, m_coefficientTexture;
    rhi::PipelineHandle m_gatherPipeline, m_finalPipeline;
    rhi::BindingSetHandle m_gatherBindings, m_finalBindings;
};

}  // namespace janus::renderer
