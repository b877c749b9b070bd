#version 450
#extension GL_GOOGLE_include_directive : require
// Compute path of the second relight pass (docs/GI.md): one workgroup per relit probe. Each
// invocation sums brick radiance x transfer over a strided share of the probe's transfers, then
// the nine coefficients are reduced in shared memory one after another (one vec3 per invocation
// of shared memory, not nine), and invocation 0 stores irradiance / pi into the volume.
#include "gi/gi_relight_common.glsl"
layout(local_size_x = 64) in;
layout(set = 0, binding = JANUS_BINDING_GI_TRANSFERS) uniform highp sampler2D giTransfers;
layout(set = 0, binding = JANUS_BINDING_GI_PROBES) uniform highp sampler2D giProbes;
layout(set = 0, binding = JANUS_BINDING_GI_BRICK_RADIANCE) uniform highp sampler2D giBrickRadiance;
layout(set = 0, binding = JANUS_BINDING_GI_TARGET, rgba16f) uniform writeonly highp image3D volumeImage;

shared vec3 partial[64];

void main() {
    int probeCount = relight.counts.y;
    int rank = (relight.schedule.x + int(gl_WorkGroupID.x)) % probeCount;
    int probe = int(giData(giProbes, probeCount + rank).x);
    vec4 range = giData(giProbes, probe);
    int first = int(range.x), count = int(range.y);
    uint lane = gl_LocalInvocationID.x;
    // Serial sum (schedule.w, for comparison): invocation 0 sums every transfer, the others idle.
    // The branch is uniform (a uniform block value), so the barriers below stay in uniform flow.
    bool serial = relight.schedule.w != 0;
    int stride = serial ? 1 : 64;
    vec3 c[9];
    for (int k = 0; k < 9; ++k) c[k] = vec3(0.0);
    ivec3 grid = ivec3(probe % relight.grid.x, (probe / relight.grid.x) % relight.grid.y,
                       probe / (relight.grid.x * relight.grid.y));
    if (serial && lane != 0u) return;
    for (int t = first + int(lane); t < first + count; t += stride) {
        vec4 a = giData(giTransfers, t * 3), b = giData(giTransfers, t * 3 + 1), d = giData(giTransfers, t * 3 + 2);
        int brick = int(a.x);
        vec3 radiance = giData(giBrickRadiance, brick).rgb;
        c[0] += radiance * a.y; c[1] += radiance * a.z; c[2] += radiance * a.w;
        c[3] += radiance * b.x; c[4] += radiance * b.y; c[5] += radiance * b.z; c[6] += radiance * b.w;
        c[7] += radiance * d.x; c[8] += radiance * d.y;
    }
    if (serial) {
        for (int k = 0; k < 9; ++k)
            imageStore(volumeImage, ivec3(grid.x, grid.z, grid.y * 9 + k), vec4(c[k] * giCosineLobe(k), k == 0 ? range.z : 0.0));
        return;
    }
    for (int k = 0; k < 9; ++k) {
        partial[lane] = c[k];
        barrier();
        for (uint stride = 32u; stride > 0u; stride >>= 1u) {
            if (lane < stride) partial[lane] += partial[lane + stride];
            barrier();
        }
        if (lane == 0u) {
            vec3 value = partial[0] * giCosineLobe(k);
            imageStore(volumeImage, ivec3(grid.x, grid.z, grid.y * 9 + k), vec4(value, k == 0 ? range.z : 0.0));
        }
        barrier();
    }
}
