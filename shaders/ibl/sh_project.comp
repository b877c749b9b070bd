#version 450
#extension GL_GOOGLE_include_directive : require
#include "janus/shaders/bindings.h"
// SH projection, compute path, first dispatch: one 16x16 workgroup per tile of a face
// (groups = tiles x tiles x 6). Each invocation weights its texel's radiance by its solid angle
// and the nine basis values; a shared-memory tree reduction sums the group, one coefficient after
// another (256 vec4 of shared memory), into partials[group * 9 + k].
#include "ibl/sh_common.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(set = 0, binding = JANUS_BINDING_SH_CUBE) uniform samplerCube cubeMap;
layout(set = 0, binding = JANUS_BINDING_SH_SOLID_ANGLES) uniform sampler2D solidAngles;
layout(set = 0, binding = JANUS_BINDING_SH_PARTIALS, std430) writeonly buffer ShPartials {
    vec4 partials[];
};

shared vec4 sums[256];

void main() {
    int size = int(shParams.x);
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    int face = int(gl_WorkGroupID.z);
    vec3 weighted = vec3(0.0);
    ShBasis basis = ShBasis(vec4(0.0), vec4(0.0), 0.0);
    if (all(lessThan(texel, ivec2(size)))) {
        vec3 dir = cubeTexelDirection(face, texel, size);
        weighted = textureLod(cubeMap, dir, 0.0).rgb * texelFetch(solidAngles, texel, 0).r;
        basis = shEvalBasis(dir);
    }
    uint group = (gl_WorkGroupID.z * gl_NumWorkGroups.y + gl_WorkGroupID.y) * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint lid = gl_LocalInvocationIndex;
    for (int k = 0; k < 9; ++k) {
        sums[lid] = vec4(weighted * shBasisAt(basis, k), 0.0);
        memoryBarrierShared();
        barrier();
        for (uint stride = 128u; stride > 0u; stride >>= 1) {
            if (lid < stride) sums[lid] += sums[lid + stride];
            memoryBarrierShared();
            barrier();
        }
        if (lid == 0u) partials[group * 9u + uint(k)] = sums[0];
        barrier();
    }
}
