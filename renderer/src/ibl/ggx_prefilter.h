// GGX prefiltering of a cube map for image-based lighting (internal to the renderer; docs/IBL.md,
// "GGX prefiltering"), and its CPU reference.
//
// GgxPrefilter reads a source cube (mip 0 filled; e.g. EnvironmentMap::cube() or a reflection
// probe capture) and writes a separate destination cube of the same face size:
//   1. generateMips(source) rebuilds the source's box-filtered chain from its mip 0;
//   2. destination mip 0 = copy of source mip 0 (six copyTexture: the mirror, roughness 0);
//   3. (with settings.brightTexels > 0) the bright-texel split: a "rest" cube = the source without
//      its few brightest texels (a sun), with its own box-filtered chain, and a list of those texels
//      (one dispatch | one draw per face, generateMips, one dispatch | one draw);
//   4. destination mips 1..N-1: the split-sum prefilter (N = V = R) with roughness r(m) from the
//      precomputed sample sets (ggx_samples.h), reading the source's whole chain (the rest's with
//      the split, plus the exact sum over the listed texels). Compute path: one dispatch per mip
//      writing all six faces (storage imageCube of that mip); fallback: one fullscreen draw per
//      face per mip into that face/mip as the attachment.
// A separate destination keeps every read and write apart on every backend (GLES emulates views
// with base/max level, one range per texture per draw), so no view of the written texture exists.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/pass_graph.h"
#include "ibl/ggx_samples.h"
#include "janus/renderer/settings.h"

namespace janus::renderer {

struct GgxPrefilterSettings {
    // Levels of the destination (mip 0 = source); 0 = the full chain of the source's face size.
    uint32_t mipCount = 0;
    // Samples of mip 1, 2, ... (the last entry repeats), each 1..kMaxGgxSamples.
    std::vector<uint32_t> samplesPerMip = defaultGgxSamplesPerMip();
    // Optional perceptual roughness per destination mip (index = mip; mip 0 is ignored); empty =
    // ggxRoughnessForMip(m, mipCount). For tests and special probes.
    std::vector<float> roughness;
    // Added to every sample's source lod, 0.5 log2(Omega_s / Omega_p) (docs/IBL.md); finite.
    float lodBias = kDefaultGgxLodBias;
    // Bright texels (docs/IBL.md, "Bright texels"): at most this many source texels whose r + g + b is
    // at least `brightThreshold` times the cube's mean are taken out of what the samples read and
    // added exactly (their reference terms). 0 = off (plain filtered importance sampling, no extra
    // passes); at most kMaxGgxBrightTexels. More bright texels than this in a source: that update
    // runs without the split. Only for power-of-two faces (others: off).
    uint32_t brightTexels = 0;
    float brightThreshold = kDefaultGgxBrightThreshold;   // finite, >= 1
    std::string debugName = "environment ggx";   // of the destination cube
};

// What the bright-texel list of the last update holds (GgxPrefilter::readBrightTexels()).
struct GgxBrightTexels {
    struct Texel {
        uint32_t face = 0, x = 0, y = 0;   // source mip 0
        glm::vec3 radiance{0.0f};
    };
    uint32_t found = 0;          // bright texels in the source (saturates at 65504)
    bool overflow = false;       // found > capacity: the update ran without the split
    std::vector<Texel> texels;   // those listed (none on overflow)
};

class GgxPrefilter {
public:
    // Throws RendererError for a missing capability of the path or bad settings.
    GgxPrefilter(rhi::IDevice& device, FeaturePath path, GgxPrefilterSettings settings = {});

    // Adds "ggx-prefilter-compute" | "ggx-prefilter-fallback": reads `source` (an RGBA16F cube with
    // a full chain and mip 0 filled; its mips 1.. are regenerated), writes the prefiltered cube,
    // published frame-wide as ibl_resources::kPrefilteredEnvironment and returned. The destination
    // is made at compile() (and kept while the source's face size stays the same).
    ViewTarget addPasses(PassGraph& graph, const ViewTarget& source);

    // Without a graph (reflection probes spread one prefilter over frames): prepare() makes the
    // destination and the pipeline for `source`; recordMips() records destination mips
    // [firstMip, endMip). firstMip 0 also regenerates the source's chain and copies mip 0, so a
    // split run starts with 0 and continues where the last part ended.
    void prepare(const rhi::TextureHandle& source);
    void recordMips(rhi::ICommandList& cmd, PassReport& report, uint32_t firstMip, uint32_t endMip);
    // Relative GPU work of destination mip `mip` (texels x samples; 0 for mip 0), valid after
    // prepare(): what time slicing balances.
    double mipCost(uint32_t mip) const;

    // Prefilters `source` now (its own graph and command list); returns the pass's report.
    PassReport run(const rhi::TextureHandle& source);

    const rhi::TextureHandle& prefiltered() const { return m_target; }
    // Whether the bright-texel split runs for the last source (settings.brightTexels > 0 and a
    // power-of-two face), and the list of the last update (reads it back: waits for the GPU; empty
    // without the split).
    bool brightSplit() const { return m_brightSplit; }
    GgxBrightTexels readBrightTexels() const;
    // Resolved for the last source: destination levels, roughness and sample set of each mip.
    uint32_t mipCount() const { return m_mipCount; }
    float roughnessForMip(uint32_t mip) const;
    const std::vector<GgxSampleSet>& sampleSets() const { return m_sets; }   // index = mip (0: empty)

private:
    void bindSource(const rhi::TextureHandle& source);
    void setup();
    void record(rhi::ICommandList& cmd, PassReport& report);
    void recordBrightSplit(rhi::ICommandList& cmd, PassReport& report);

    rhi::IDevice& m_device;
    FeaturePath m_path;
    GgxPrefilterSettings m_settings;
    rhi::TextureHandle m_source, m_target;
    uint32_t m_mipCount = 0;
    std::vector<GgxSampleSet> m_sets;
    rhi::SamplerHandle m_sampler, m_nearest;
    rhi::PipelineHandle m_pipeline;
    std::vector<rhi::BufferHandle> m_buffers;
    // Compute: one set per mip (index mip - 1); fallback: one per mip and face ((mip - 1) * 6 + face).
    std::vector<rhi::BindingSetHandle> m_bindings;
    // The bright-texel split: the rest cube (full chain), the 2(K + 1) x 1 list and its copy as a
    // uniform buffer, their passes' pipelines and sets (split: 1 | one per face; list: 1).
    bool m_brightSplit = false;
    rhi::TextureHandle m_rest, m_brightList;
    rhi::BufferHandle m_brightListBuffer;
    rhi::PipelineHandle m_splitPipeline, m_listPipeline;
    std::vector<rhi::BindingSetHandle> m_splitBindings;
    rhi::BindingSetHandle m_listBindings;
};

// A cube map read back from the GPU: six faces of size^2 RGBA floats (row 0 first), faces +X .. -Z.
// (Not spherical_harmonics.h's CubeImage: that one holds vec4 texels for the SH projection.)
struct FloatCube {
    uint32_t size = 0;
    std::array<std::vector<float>, 6> faces;
    glm::dvec3 texel(uint32_t face, uint32_t x, uint32_t y) const {
        const float* p = faces[face].data() + (size_t(y) * size + x) * 4;
        return {p[0], p[1], p[2]};
    }
};

// Reads back one mip of an RGBA16F / RGBA32F cube (waits for the GPU).
FloatCube readCube(rhi::IDevice& device, const rhi::TextureHandle& cube, uint32_t mip);

// The CPU reference, in double precision: the split-sum prefiltered radiance along `n` for
// perceptual `roughness`, brute force over every texel of `cube` with its exact solid angle:
//   sum_t L(t) D(n.h) max(n.l, 0) Omega_t / sum_t D(n.h) max(n.l, 0) Omega_t,  h = normalize(n + l)
// (the expectation of the GPU's NdotL-weighted GGX importance sampling). Roughness 0 (alpha below
// 1e-6): the texel whose centre is nearest to n. A zero weight sum gives 0, never 0/0.
// Normalization::Exact divides by the lobe's exact integral Z = ggxLobeNormalization(alpha) instead
// of its texel-centre sum: a diagnostic only (docs/IBL.md, "Bright texels": for lobes a few texels
// wide the two differ by ~0.3 %, which is all of the error left near a sun).
class GgxReference {
public:
    enum class Normalization { TexelSum, Exact };
    explicit GgxReference(const FloatCube& cube);
    glm::dvec3 radiance(const glm::dvec3& n, double roughness, Normalization normalization = Normalization::TexelSum) const;

private:
    struct Texel {
        glm::dvec3 direction;
        double solidAngle;
        glm::dvec3 radiance;
    };
    std::vector<Texel> m_texels;
};

}  // namespace janus::renderer
