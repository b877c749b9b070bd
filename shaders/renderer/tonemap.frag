#version 450
#extension GL_GOOGLE_include_directive : require
// Tonemap, fallback path: a fullscreen triangle, one fragment per pixel -> RGBA8 attachment.
#include "renderer/tonemap_common.glsl"

layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

void main() {
    outColor = tonemapTexel(ivec2(gl_FragCoord.xy));
}
