#version 450
// Texel (x, y) of layer L at mip M = (10 + 20x, 10 + 20y, 5 + 10L, 255 - 40M) / 255: exact in
// RGBA8 and different in every texel, layer and mip the tests use. One invocation per texel
// and layer (z = layer). ARRAY: image2DArray, CUBE: imageCube (z = face), CUBE_ARRAY:
// imageCubeArray (z = layer-face), LAYER: one layer bound as image2D (z = 0, L = params.y).
layout(local_size_x = 1) in;
layout(set = 0, binding = 0) uniform Params { uvec4 p; } params;   // x: mip M, y: first layer
#if defined(ARRAY)
layout(rgba8, set = 0, binding = 1) uniform writeonly image2DArray image;
#elif defined(CUBE)
layout(rgba8, set = 0, binding = 1) uniform writeonly imageCube image;
#elif defined(CUBE_ARRAY)
layout(rgba8, set = 0, binding = 1) uniform writeonly imageCubeArray image;
#else
layout(rgba8, set = 0, binding = 1) uniform writeonly image2D image;
#endif

void main() {
    uvec3 g = gl_GlobalInvocationID;
    uint layer = g.z + params.p.y;
    vec4 v = vec4(float(10u + 20u * g.x), float(10u + 20u * g.y), float(5u + 10u * layer), float(255u - 40u * params.p.x));
#if defined(LAYER)
    imageStore(image, ivec2(g.xy), v / 255.0);
#else
    imageStore(image, ivec3(g), v / 255.0);
#endif
}
