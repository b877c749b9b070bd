#version 450
// Texel (x, y) = (x / 16, y / 16, 4 - x / 4, 1 + y): exact in half and single floats, distinct
// per texel, outside [0, 1] in places. IMAGE_FORMAT is the image's format qualifier.
layout(local_size_x = 1) in;
layout(IMAGE_FORMAT, set = 0, binding = 0) uniform writeonly image2D image;

void main() {
    vec2 p = vec2(gl_GlobalInvocationID.xy);
    imageStore(image, ivec2(p), vec4(p.x / 16.0, p.y / 16.0, 4.0 - p.x / 4.0, 1.0 + p.y));
}
