// Precomputed GGX sample sets for prefiltering (internal to the renderer; docs/IBL.md, "GGX
// prefiltering"). Made once on the CPU and uploaded as uniform buffers.
//
// Roughness of mip m of an N-mip prefiltered cube: r(m) = m / (N - 1) (perceptual roughness;
// GGX alpha = r^2), so mip 0 is the mirror (the source itself) and the last mip is r = 1.
// Each set holds `count` Hammersley points mapped to half vectors H with the GGX D(H) NdotH pdf,
// reflected about N = V into L. Samples below the horizon (NdotL <= 0) are dropped (their weight
// is 0). Each keeps its weight NdotL and the source mip it reads: with the sample's solid angle
// Omega_s = 1 / (count * pdf(L)), pdf(L) = D / 4 (N = V = H-reflected), and a source texel's
// Omega_p = 4 pi / (6 w^2) at mip 0, lod = 0.5 log2(Omega_s / Omega_p) + lodBias (GPU Gems 3,
// ch. 20, "filtered importance sampling"; bias 0 by default, Karis' +1 over-blurs: docs/IBL.md),
// clamped to [0, sourceMips - 1]. pdf = 0
// (or not finite) gives the coarsest mip; roughness 0 gives one sample at N from mip 0.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace janus::renderer {

struct GgxSample {
    glm::vec3 direction{0, 0, 1};   // L in the frame N = V = +Z; direction.z = NdotL = the weight
    float lod = 0.0f;               // source mip to read it from
};

struct GgxSampleSet {
    float roughness = 0.0f;          // perceptual
    uint32_t requested = 0;          // Hammersley points generated
    std::vector<GgxSample> samples;  // those above the horizon (at most `requested`)
    // ggxLobeNormalization(roughness^2): what the bright-texel sum divides by (0 for the mirror).
    double normalization = 0.0;
};

// Default samples per prefiltered mip (mips 1, 2, ...; the last entry repeats): few where the
// lobe is narrow and the source mip does most of the filtering, more where it is wide.
inline const std::vector<uint32_t>& defaultGgxSamplesPerMip() {
    static const std::vector<uint32_t> kDefault = {21, 34, 55, 89, 89, 89};
    return kDefault;
}
// JANUS_GGX_MAX_SAMPLES in ggx_common.glsl. 1024 vec4 = 16384 bytes, the whole PrefilterSamples
// block: exactly the minimum uniform block size of GLES 3.0 / GL 4.x (GL_MAX_UNIFORM_BLOCK_SIZE) and
// Vulkan (maxUniformBufferRange), so every conforming device takes it.
inline constexpr uint32_t kMaxGgxSamples = 1024;
// Added to each sample's source lod (GgxPrefilterSettings::lodBias). 0: the bilinear taps of the
// box-filtered mips already blur enough; Karis' +1 gives 3-4x the error against GgxReference
// (docs/IBL.md, "GGX prefiltering").
inline constexpr float kDefaultGgxLodBias = 0.0f;
// The bright-texel split (GgxPrefilterSettings::brightTexels, docs/IBL.md "Bright texels"): list
// capacity the environment uses, the most a prefilter takes, and the default threshold (a texel is
// bright when its r + g + b is at least this many times the cube's mean).
inline constexpr uint32_t kDefaultGgxBrightTexels = 64;
inline constexpr uint32_t kMaxGgxBrightTexels = 1023;   // + the header: 1024 uvec4, a 16 KiB uniform block
inline constexpr float kDefaultGgxBrightThreshold = 64.0f;

// r(m) = m / (mipCount - 1); 0 for a single mip.
float ggxRoughnessForMip(uint32_t mip, uint32_t mipCount);
// samplesPerMip[mip - 1], the last entry for mips beyond it (mip >= 1); throws for an empty list.
uint32_t ggxSamplesForMip(const std::vector<uint32_t>& samplesPerMip, uint32_t mip);
// GGX normal distribution D(NdotH) for alpha = roughness^2 (alpha > 0).
double ggxDistribution(double nDotH, double alpha);
// Z(alpha) = integral over the sphere of D(n.h) max(n.l, 0) dl with N = V (h = normalize(n + l)): the
// weight sum of the split-sum prefilter, so that sum_t L_t D max(n.l, 0) Omega_t / Z is the share
// texels t take of the prefiltered value. 4 E[max(0, 2 cos^2 theta_h - 1)] over H ~ D NdotH (closed form
// in the Hammersley coordinate u, Simpson for alpha^2 >= 0.5); 1 at alpha = 1, -> 4 as alpha -> 0; 0 below 1e-6.
double ggxLobeNormalization(double alpha);
// Van der Corput radical inverse in base 2 (the second Hammersley coordinate).
double radicalInverse(uint32_t bits);

// One set: `count` (1..kMaxGgxSamples) samples for `roughness` in [0, 1], reading a source cube of
// `sourceFaceSize` texels at mip 0 with `sourceMipCount` levels. Throws std::invalid_argument
// outside those ranges. Every value is finite.
// `lodBias` is added to every sample's lod (before the clamp); finite.
GgxSampleSet makeGgxSampleSet(float roughness, uint32_t count, uint32_t sourceFaceSize, uint32_t sourceMipCount,
                              float lodBias = kDefaultGgxLodBias);

}  // namespace janus::renderer
