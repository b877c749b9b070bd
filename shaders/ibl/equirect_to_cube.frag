#version 450
#extension GL_GOOGLE_include_directive : require
// Equirect -> cube, fallback path: one fullscreen triangle per face into mip 0 of that face.
#include "ibl/equirect_common.glsl"

layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

void main() {
    outColor = equirectTexel(equirectParams.x, ivec2(gl_FragCoord.xy));
}
