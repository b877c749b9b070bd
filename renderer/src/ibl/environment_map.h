// The environment cube map (internal to the renderer; docs/IBL.md, "Environment map"): an
// equirectangular float image (readRadianceHDR / readEXR) becomes an RGBA16F cube map with a full
// mip chain, converted on the GPU. Compute path: one dispatch writes mip 0 of all six faces
// (equirect_to_cube.comp, storage imageCube); fallback: six fullscreen draws, one per face as an
// attachment (equirect_to_cube.frag). Both sample the equirect bilinearly, wrapping in u.
// Only mip 0 is written; GgxPrefilter builds the rest of the chain from it. The same equirect can
// also be converted into a second cube, the sky's background (addBackgroundPasses), with its own
// face size and a box-filtered mip chain.
#pragma once

#include <cstdint>
#include <string>

#include <glm/glm.hpp>

#include "core/pass_graph.h"
#include "ibl/cube_geometry.h"
#include "janus/renderer/image.h"
#include "janus/renderer/settings.h"

namespace janus::renderer {

// Blackboard names (frame-wide) of the IBL cubes.
namespace ibl_resources {
inline constexpr const char* kEnvironment = "environment";                     // RGBA16F cube, mip 0 from the sky
inline constexpr const char* kPrefilteredEnvironment = "environment-ggx";      // GGX-prefiltered mips
}  // namespace ibl_resources

// Equirectangular mapping (docs/IBL.md): u = 0.5 + atan2(x, -z) / 2pi, v = acos(y) / pi. u = 0.5
// looks along -Z, u = 0.75 along +X, u = 0.25 along -X, u = 0 and 1 along +Z; v = 0 (row 0) is +Y.
glm::dvec2 equirectUv(const glm::dvec3& direction);
glm::dvec3 equirectDirection(const glm::dvec2& uv);

class EnvironmentMap {
public:
    // Uploads `equirect` (RGBA32F when the device filters it, RGBA16F otherwise, values clamped to
    // 65504 then) and makes the cube: RGBA16F, faceSize^2, full mip chain, usage Sampled plus
    // Storage (compute) or RenderTarget (fallback). Throws RendererError for an empty image, a
    // face size of 0 or above the device's cube limit, or a missing capability of the path.
    EnvironmentMap(rhi::IDevice& device, const ImageRGBAF& equirect, uint32_t faceSize, FeaturePath path);

    // Adds "equirect-to-cube-compute" | "equirect-to-cube-fallback", which writes mip 0 of the
    // cube; publishes it frame-wide as ibl_resources::kEnvironment and returns it.
    ViewTarget addPasses(PassGraph& graph);

    // Runs the conversion now (its own graph and command list) and returns the pass's report.
    PassReport convert();

    // Adds "background-cube-compute" | "background-cube-fallback": the same conversion into a
    // second RGBA16F cube of `faceSize`, then its box-filtered mip chain (generateMips), for the
    // sky's background (docs/IBL.md, "The background"); returns it. Throws RendererError for a
    // face size of 0 or above the device's cube limit, or a second call.
    ViewTarget addBackgroundPasses(PassGraph& graph, uint32_t faceSize);

    const rhi::TextureHandle& cube() const { return m_lighting.cube; }
    // The background cube; null before addBackgroundPasses.
    const rhi::TextureHandle& background() const { return m_background.cube; }
    FeaturePath path() const { return m_path; }

private:
    // A cube the equirect is converted into, and the binding sets that write its mip 0.
    struct Conversion {
        uint32_t faceSize = 0;
        rhi::TextureHandle cube;
        std::vector<rhi::BindingSetHandle> bindings;   // compute: 1; fallback: one per face
    };
    void requireFaceSize(uint32_t faceSize, const char* what) const;   // RendererError unless 1..the device's cube limit
    rhi::TextureHandle createCube(uint32_t faceSize, const char* debugName) const;
    void setup(Conversion& conversion);
    void record(const Conversion& conversion, rhi::ICommandList& cmd, PassReport& report);

    rhi::IDevice& m_device;
    FeaturePath m_path;
    rhi::TextureHandle m_equirect;
    rhi::SamplerHandle m_sampler;
    rhi::PipelineHandle m_pipeline;   // one for both conversions: the face size is a uniform
    Conversion m_lighting, m_background;
};

}  // namespace janus::renderer
