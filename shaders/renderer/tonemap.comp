#version 450
#extension GL_GOOGLE_include_directive : require
#include "janus/shaders/bindings.h"
// Tonemap, compute path: one invocation per pixel, HDR texel -> RGBA8 storage image.
#include "renderer/tonemap_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = JANUS_BINDING_TONEMAP_DISPLAY, rgba8) uniform writeonly image2D displayImage;

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(texel, imageSize(displayImage)))) return;
    imageStore(displayImage, texel, tonemapTexel(texel));
}
