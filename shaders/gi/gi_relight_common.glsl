// The GI relight's data (docs/GI.md, "Relight"): the bake in RGBA32F data textures 1024 texels
// wide (element e at (e % 1024, e / 1024)), read with texelFetch on both paths (ES 3.0 has no
// storage buffers). Counts and indices are stored as floats (exact below 2^24).
//   surfels:   4 texels each: (position, face normal's octahedral x), (normal, its octahedral y),
//              (diffuse albedo, rendering layers' low 16 bits), (emission, their high 16 bits); grouped by brick
//   bricks:    2 texels each: (first surfel, surfel count, 1 = a sky sample, 0), (sky direction, 0);
//              placed by surfel count (gi_bake.h giBrickSlot), some empty (count 0, not sky)
//   transfers: 3 texels each, grouped by probe: (brick, T0, T1, T2), (T3..T6), (T7, T8, 0, 0): the SH
//              projection of the brick's surfels this probe sees, sum of Y_k(direction) * 4 pi / N
//   probes:    texel p (grid order p = x + X (y + Y z)): (first transfer, count, validity, relight rank);
//              texel P + r: (probe of rank r, 0, 0, 0): probes in relight order (nearest the camera first)
#ifndef JANUS_GI_RELIGHT_COMMON_GLSL
#define JANUS_GI_RELIGHT_COMMON_GLSL
#include "janus/shaders/bindings.h"
#include "gi/gi_octahedral.glsl"

const int kGiDataWidth = 1024;

layout(set = 0, binding = JANUS_BINDING_GI_RELIGHT_PARAMS, std140) uniform GiRelightParams {
    ivec4 counts;     // x bricks, y probes, z 1 = add the last relight's irradiance (a further bounce), w SH coefficients kept (4 | 9)
    ivec4 schedule;   // x first rank relit, y probes relit (ranks first .. first + y - 1, mod probes), z layer and coefficient group (fallback SH pass: y * 3 + g, coefficients 3g .. 3g + 2), w 1 = serial sum (compute SH pass: one invocation per probe, no reduction; for comparison)
    ivec4 grid;       // xyz probes per axis
} relight;

vec4 giData(highp sampler2D data, int e) { return texelFetch(data, ivec2(e % kGiDataWidth, e / kGiDataWidth), 0); }

// The clamped-cosine convolution divided by pi for coefficient k (A_l / pi: 1, 2/3, 1/4), or 0
// for L2 terms of an L1 volume: what turns radiance SH into the irradiance / pi shading reads.
float giCosineLobe(int k) {
    if (k == 0) return 1.0;
    if (k < 4) return 2.0 / 3.0;
    return relight.counts.w > 4 ? 0.25 : 0.0;
}
#endif
