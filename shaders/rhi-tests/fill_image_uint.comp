#version 450
// Texel (x, y) = (7x + 1, 5y + 2, 1000 + x, 0xFFFFFFF0 + y): exact in 32-bit unsigned integers,
// distinct per texel. IMAGE_FORMAT is the image's format qualifier (r32ui, rgba32ui).
layout(local_size_x = 1) in;
layout(IMAGE_FORMAT, set = 0, binding = 0) uniform writeonly uimage2D image;

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    imageStore(image, ivec2(p), uvec4(7u * p.x + 1u, 5u * p.y + 2u, 1000u + p.x, 0xFFFFFFF0u + p.y));
}
