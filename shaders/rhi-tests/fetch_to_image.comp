#version 450
// Copies a sampled texture into a storage image texel by texel (texelFetch: no filtering).
layout(local_size_x = 1) in;
layout(set = 0, binding = 0) uniform sampler2D source;
layout(rgba8, set = 0, binding = 1) uniform writeonly image2D destination;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    imageStore(destination, p, texelFetch(source, p, 0));
}
