#version 450
#extension GL_GOOGLE_include_directive : require
// GGX prefilter, fallback path: one fullscreen triangle per face and target mip, into that
// face/mip as the attachment (renderer/src/ibl/ggx_prefilter.cpp).
#define JANUS_IBL_PREFILTER 1
#include "ibl/ggx_common.glsl"

layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

void main() {
    outColor = prefilterTexel(prefilterParams.x, ivec2(gl_FragCoord.xy));
}
