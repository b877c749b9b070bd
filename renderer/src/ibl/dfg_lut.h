// The split-sum DFG table for image-based specular (internal to the renderer; docs/IBL.md,
// "Split-sum specular"). With the prefiltered environment L_pre(R, roughness), the specular
// image-based lighting of forward.frag's BRDF (GGX distribution, height-correlated Smith
// visibility, Schlick Fresnel) is approximated as
//     L_spec = L_pre(R, roughness) * (f0 * A + B)
// where, for view angle NoV and perceptual roughness r (alpha = r^2),
//     A = integral over the hemisphere of f_spec / F * (1 - Fc) * NoL,
//     B = integral of f_spec / F * Fc * NoL,   Fc = (1 - VoH)^5.
// The table is computed on the CPU in double precision (so every backend samples the same
// texels) by importance-sampling GGX: with H drawn from D(H) NoH, L = reflect(-V, H), the
// estimator of f_spec/F NoL / pdf(L) is 4 Vis(NoV, NoL) NoL VoH / NoH.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "janus/rhi/rhi.h"

namespace janus::renderer {

struct DfgTable {
    uint32_t size = 0;                // size x size texels
    // (A, B) at texel (x, y): NoV = (x + 0.5) / size, perceptual roughness = (y + 0.5) / size.
    std::vector<glm::vec2> values;
    glm::vec2 at(uint32_t x, uint32_t y) const { return values[size_t(y) * size + x]; }
};

inline constexpr uint32_t kDefaultDfgSize = 64;
inline constexpr uint32_t kDefaultDfgSamples = 1024;

// (A, B) for one view angle and perceptual roughness by GGX importance sampling (Hammersley
// points, `samples` of them), in double precision. NoV is clamped to [1e-4, 1]; roughness to
// [0, 1]; every division is guarded, so the result is finite for any input.
glm::dvec2 integrateDfg(double NoV, double perceptualRoughness, uint32_t samples);

// The whole table. Throws RendererError for size 0 or samples 0.
DfgTable computeDfgTable(uint32_t size = kDefaultDfgSize, uint32_t samples = kDefaultDfgSamples);

// The table as an RGBA16F texture (R = A, G = B, B = A = 0), sampled with linear filtering and
// clamp-to-edge at uv = (NoV, roughness).
rhi::TextureHandle uploadDfgTable(rhi::IDevice& device, const DfgTable& table);

}  // namespace janus::renderer
