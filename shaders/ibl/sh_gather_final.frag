#version 450
#extension GL_GOOGLE_include_directive : require
#include "janus/shaders/bindings.h"
// SH projection, fallback path, second level: a fullscreen triangle into the 9 x 1 RGBA32F
// coefficient texture. Pixel k sums column face * 9 + k of the row sums over the six faces and
// all rows, applies A_l / pi and stores (irradiance / pi SH, 0).
#include "ibl/sh_common.glsl"

layout(set = 0, binding = JANUS_BINDING_SH_PARTIALS) uniform sampler2D rowSums;

layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outCoefficient;

void main() {
    int size = int(shParams.x);
    int k = int(gl_FragCoord.x);
    vec3 sum = vec3(0.0);
    for (int face = 0; face < 6; ++face)
        for (int y = 0; y < size; ++y) sum += texelFetch(rowSums, ivec2(face * 9 + k, y), 0).rgb;
    outCoefficient = vec4(sum * shCosineOverPi(k), 0.0);
}
