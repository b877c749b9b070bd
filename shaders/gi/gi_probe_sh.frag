#version 450
#extension GL_GOOGLE_include_directive : require
// Fallback path of the second relight pass (docs/GI.md): one draw per layer y of probes and
// group g of three coefficients, into three slices of the volume at once (y * 9 + 3g + j, one
// render target each: three render passes per layer instead of nine, and each transfer read once
// for three coefficients); each fragment (x, z) gathers coefficients 3g .. 3g + 2 of probe
// (x, y, z) over its transfers, in transfer order. Probes not relit this frame are discarded, so
// they keep what they hold.
#include "gi/gi_relight_common.glsl"
layout(set = 0, binding = JANUS_BINDING_GI_TRANSFERS) uniform highp sampler2D giTransfers;
layout(set = 0, binding = JANUS_BINDING_GI_PROBES) uniform highp sampler2D giProbes;
layout(set = 0, binding = JANUS_BINDING_GI_BRICK_RADIANCE) uniform highp sampler2D giBrickRadiance;
layout(location = 0) out vec4 outCoefficient0;
layout(location = 1) out vec4 outCoefficient1;
layout(location = 2) out vec4 outCoefficient2;

void main() {
    ivec2 texel = ivec2(gl_FragCoord.xy);
    int y = relight.schedule.z / 3, group = relight.schedule.z % 3;
    int probe = texel.x + relight.grid.x * (y + relight.grid.y * texel.y);
    vec4 range = giData(giProbes, probe);
    int probeCount = relight.counts.y;
    int rank = int(range.w);
    if ((rank - relight.schedule.x + probeCount) % probeCount >= relight.schedule.y) discard;
    int first = int(range.x), count = int(range.y);
    vec3 sum0 = vec3(0.0), sum1 = vec3(0.0), sum2 = vec3(0.0);
    for (int t = first; t < first + count; ++t) {
        // A transfer's three texels: (brick, T0, T1, T2), (T3 .. T6), (T7, T8, 0, 0).
        vec4 word0 = giData(giTransfers, t * 3);
        vec3 radiance = giData(giBrickRadiance, int(word0.x)).rgb;
        vec3 factors;
        if (group == 0) {
            factors = word0.yzw;
        } else {
            vec4 word1 = giData(giTransfers, t * 3 + 1);
            if (group == 1) {
                factors = word1.xyz;
            } else {
                vec4 word2 = giData(giTransfers, t * 3 + 2);
                factors = vec3(word1.w, word2.xy);
            }
        }
        sum0 += radiance * factors.x;
        sum1 += radiance * factors.y;
        sum2 += radiance * factors.z;
    }
    int k = group * 3;
    outCoefficient0 = vec4(sum0 * giCosineLobe(k), k == 0 ? range.z : 0.0);
    outCoefficient1 = vec4(sum1 * giCosineLobe(k + 1), 0.0);
    outCoefficient2 = vec4(sum2 * giCosineLobe(k + 2), 0.0);
}
