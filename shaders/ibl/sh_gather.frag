#version 450
#extension GL_GOOGLE_include_directive : require
#include "janus/shaders/bindings.h"
// SH projection, fallback path, first level: a fullscreen triangle into an RGBA32F target of
// 54 x size. Pixel (face * 9 + k, y) sums coefficient k over row y of that face (size texels,
// so the loop is bounded by the face size).
#include "ibl/sh_common.glsl"

layout(set = 0, binding = JANUS_BINDING_SH_CUBE) uniform samplerCube cubeMap;
layout(set = 0, binding = JANUS_BINDING_SH_SOLID_ANGLES) uniform sampler2D solidAngles;

layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outSum;

void main() {
    int size = int(shParams.x);
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    int face = pixel.x / 9;
    int k = pixel.x - face * 9;
    int y = pixel.y;
    vec3 sum = vec3(0.0);
    for (int x = 0; x < size; ++x) {
        ivec2 texel = ivec2(x, y);
        vec3 dir = cubeTexelDirection(face, texel, size);
        vec3 weighted = textureLod(cubeMap, dir, 0.0).rgb * texelFetch(solidAngles, texel, 0).r;
        sum += weighted * shBasisAt(shEvalBasis(dir), k);
    }
    outSum = vec4(sum, 0.0);
}
