#version 450
// Writes texel (x, y, z) = 1 + x + 16 y + 256 z into every slice of a 3D image (one invocation
// per texel), which only works when the whole 3D level is bound (GL: layered binding).
layout(local_size_x = 1) in;
layout(r32ui, set = 0, binding = 0) uniform writeonly uimage3D volume;

void main() {
    uvec3 p = gl_GlobalInvocationID;
    imageStore(volume, ivec3(p), uvec4(1u + p.x + 16u * p.y + 256u * p.z));
}
