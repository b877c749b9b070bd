#version 450
#extension GL_GOOGLE_include_directive : require
// Equirect -> cube, compute path: one dispatch, z = face, writes mip 0 of all six faces.
#include "ibl/equirect_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = JANUS_BINDING_EQUIRECT_CUBE, rgba16f) uniform writeonly imageCube cubeTarget;

void main() {
    ivec3 id = ivec3(gl_GlobalInvocationID);
    if (id.x >= equirectParams.y || id.y >= equirectParams.y || id.z >= 6) return;
    imageStore(cubeTarget, id, equirectTexel(id.z, id.xy));
}
