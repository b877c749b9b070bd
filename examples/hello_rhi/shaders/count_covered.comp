#version 450
// The compute path: one invocation per pixel, counting those the triangle covered (alpha 1; the
// clear left alpha 0).
layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D image;
layout(set = 0, binding = 1, std430) buffer Count {
    uint covered;
};

void main() {
    const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, textureSize(image, 0)))) return;
    if (texelFetch(image, pixel, 0).a > 0.5) atomicAdd(covered, 1u);
}
