#version 450
#extension GL_GOOGLE_include_directive : require
// GGX prefilter, bright-texel split, fallback path: one fullscreen triangle per face into mip 0 of
// the rest cube (renderer/src/ibl/ggx_prefilter.cpp); the cube's mean comes from the vertex shader.
#define JANUS_IBL_BRIGHT_SPLIT 1
#include "ibl/ggx_bright.glsl"

layout(location = 0) flat in float vMean;
layout(location = 0) out vec4 outColor;

void main() {
    outColor = splitTexel(brightParams.x, ivec2(gl_FragCoord.xy), vMean);
}
