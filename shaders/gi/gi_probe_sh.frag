#version 450
#extension GL_GOOGLE_include_directive : require
// Fallback path of the second relight pass (docs/GI.md): one draw per slice y * 9 + k of the
// volume; each fragment (x, z) gathers coefficient k of probe (x, y, z) over its transfers.
// Probes not relit this frame are discarded, so they keep what they hold.
#include "gi/gi_relight_common.glsl"
layout(set = 0, binding = JANUS_BINDING_GI_TRANSFERS) uniform highp sampler2D giTransfers;
layout(set = 0, binding = JANUS_BINDING_GI_PROBES) uniform highp sampler2D giProbes;
layout(set = 0, binding = JANUS_BINDING_GI_BRICK_RADIANCE) uniform highp sampler2D giBrickRadiance;
layout(location = 0) out vec4 outCoefficient;

void main() {
    ivec2 texel = ivec2(gl_FragCoord.xy);
    int y = relight.schedule.z / 9, k = relight.schedule.z % 9;
    int probe = texel.x + relight.grid.x * (y + relight.grid.y * texel.y);
    vec4 range = giData(giProbes, probe);
    int probeCount = relight.counts.y;
    int rank = int(range.w);
    if ((rank - relight.schedule.x + probeCount) % probeCount >= relight.schedule.y) discard;
    int first = int(range.x), count = int(range.y);
    vec3 sum = vec3(0.0);
    for (int t = first; t < first + count; ++t) {
        int word = k < 3 ? 0 : k < 7 ? 1 : 2;
        vec4 factors = giData(giTransfers, t * 3 + word);
        int brick = int(giData(giTransfers, t * 3).x);
        float factor = k < 3 ? factors[k + 1] : k < 7 ? factors[k - 3] : factors[k - 7];
        sum += giData(giBrickRadiance, brick).rgb * factor;
    }
    outCoefficient = vec4(sum * giCosineLobe(k), k == 0 ? range.z : 0.0);
}
