#version 450
// Mip N from mip N - 1 of the same texture: texel (x, y) of every layer = parent texel
// (2x, 2y) of that layer plus 1/255 in red, so each level proves it read the level written
// before it. `src` is a view of mip N - 1 only, as a 2D array (texelFetch has no cube form);
// `dst` is mip N as a storage image: image2DArray, CUBE imageCube, CUBE_ARRAY imageCubeArray.
layout(local_size_x = 1) in;
layout(set = 0, binding = 0) uniform sampler2DArray src;
#if defined(CUBE)
layout(rgba8, set = 0, binding = 1) uniform writeonly imageCube dst;
#elif defined(CUBE_ARRAY)
layout(rgba8, set = 0, binding = 1) uniform writeonly imageCubeArray dst;
#else
layout(rgba8, set = 0, binding = 1) uniform writeonly image2DArray dst;
#endif

void main() {
    ivec3 p = ivec3(gl_GlobalInvocationID);
    vec4 parent = texelFetch(src, ivec3(2 * p.xy, p.z), 0);
    imageStore(dst, p, parent + vec4(1.0 / 255.0, 0.0, 0.0, 0.0));
}
