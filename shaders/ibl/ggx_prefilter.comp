#version 450
#extension GL_GOOGLE_include_directive : require
// GGX prefilter, compute path: one dispatch per target mip, z = face; writes that mip of all six
// faces (renderer/src/ibl/ggx_prefilter.cpp).
#define JANUS_IBL_PREFILTER 1
#include "ibl/ggx_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = JANUS_BINDING_PREFILTER_TARGET, rgba16f) uniform writeonly imageCube prefilterTarget;

void main() {
    ivec3 id = ivec3(gl_GlobalInvocationID);
    if (id.x >= prefilterParams.z || id.y >= prefilterParams.z || id.z >= 6) return;
    imageStore(prefilterTarget, id, prefilterTexel(id.z, id.xy));
}
