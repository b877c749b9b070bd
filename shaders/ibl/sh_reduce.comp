#version 450
#extension GL_GOOGLE_include_directive : require
#include "janus/shaders/bindings.h"
// SH projection, compute path, second dispatch: 9 workgroups of 256, group k sums coefficient k
// over all partials (strided loop, then a shared-memory tree), applies A_l / pi and stores
// coefficients[k] = (irradiance / pi SH, 0). No atomics.
#include "ibl/sh_common.glsl"

layout(local_size_x = 256) in;
layout(set = 0, binding = JANUS_BINDING_SH_PARTIALS, std430) readonly buffer ShPartials {
    vec4 partials[];
};
layout(set = 0, binding = JANUS_BINDING_SH_COEFFICIENTS, std430) writeonly buffer ShCoefficients {
    vec4 coefficients[9];
};

shared vec4 sums[256];

void main() {
    uint k = gl_WorkGroupID.x;
    uint lid = gl_LocalInvocationIndex;
    uint groups = shParams.y;
    vec4 sum = vec4(0.0);
    for (uint g = lid; g < groups; g += 256u) sum += partials[g * 9u + k];
    sums[lid] = sum;
    memoryBarrierShared();
    barrier();
    for (uint stride = 128u; stride > 0u; stride >>= 1) {
        if (lid < stride) sums[lid] += sums[lid + stride];
        memoryBarrierShared();
        barrier();
    }
    if (lid == 0u) coefficients[k] = vec4(sums[0].rgb * shCosineOverPi(int(k)), 0.0);
}
