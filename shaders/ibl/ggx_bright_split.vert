#version 450
#extension GL_GOOGLE_include_directive : require
// GGX prefilter, bright-texel split, fallback path: the fullscreen triangle (as fullscreen.vert),
// and the cube's mean r + g + b once per vertex instead of once per fragment (the same for all).
#define JANUS_IBL_BRIGHT_SPLIT 1
#include "ibl/ggx_bright.glsl"

layout(location = 0) flat out float vMean;

void main() {
    vec2 uv = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
    vMean = brightMean();
    gl_Position = vec4(uv * 2.0 - 1.0, 0.0, 1.0);
}
