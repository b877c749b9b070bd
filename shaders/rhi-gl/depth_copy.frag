#version 450
// Copies a 2D depth image texel for texel into an r32f target, because OpenGL ES 3.0 cannot read
// depth with glReadPixels (without NV_read_depth). Binding 30 keeps clear of user bindings (< 16).
layout(set = 0, binding = 30) uniform sampler2D depthImage;
layout(location = 0) out float depth;

void main() {
    depth = texelFetch(depthImage, ivec2(gl_FragCoord.xy), 0).r;
}
