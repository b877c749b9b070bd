#version 450
#extension GL_GOOGLE_include_directive : require
// GGX prefilter, bright-texel list, fallback path: one fullscreen triangle into the 2(K + 1) x 1 list
// (renderer/src/ibl/ggx_prefilter.cpp).
#define JANUS_IBL_BRIGHT_LIST 1
#include "ibl/ggx_bright.glsl"

layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

void main() {
    outColor = listTexel(int(gl_FragCoord.x));
}
