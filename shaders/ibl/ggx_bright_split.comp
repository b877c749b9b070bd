#version 450
#extension GL_GOOGLE_include_directive : require
// GGX prefilter, bright-texel split, compute path: one dispatch writes mip 0 of the rest cube, all
// six faces (z = face) (renderer/src/ibl/ggx_prefilter.cpp).
#define JANUS_IBL_BRIGHT_SPLIT 1
#include "ibl/ggx_bright.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = JANUS_BINDING_BRIGHT_TARGET, rgba16f) uniform writeonly imageCube restTarget;

shared float groupMean;

void main() {
    // The cube's mean once per group, not per texel.
    if (gl_LocalInvocationIndex == 0u) groupMean = brightMean();
    barrier();
    ivec3 id = ivec3(gl_GlobalInvocationID);
    if (id.x >= brightParams.y || id.y >= brightParams.y || id.z >= 6) return;
    imageStore(restTarget, id, splitTexel(id.z, id.xy, groupMean));
}
