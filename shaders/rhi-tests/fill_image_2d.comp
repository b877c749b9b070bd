#version 450
// Texel (x, y) = (17x, 17y, 255 - 17x, 255) / 255: exact in RGBA8, different in every texel
// of a 16x16 image and asymmetric in x and y.
layout(local_size_x = 1) in;
layout(rgba8, set = 0, binding = 0) uniform writeonly image2D image;

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    imageStore(image, ivec2(p), vec4(17.0 * float(p.x), 17.0 * float(p.y), 255.0 - 17.0 * float(p.x), 255.0) / 255.0);
}
