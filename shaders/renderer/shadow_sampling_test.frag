#version 450
#extension GL_GOOGLE_include_directive : require
// Test shader for shadow_sampling.glsl (tests/renderer/shadow_map_test.cpp): pixel x of an N x 1
// target writes the lit fraction of world point points[x].xyz with an upward normal.
#include "renderer/shadow_sampling.glsl"

layout(set = 0, binding = 0) uniform ShadowLookups {
    mat4 worldToShadow;
    vec4 params;        // x texel size, y normal offset (world units)
    vec4 points[16];
} lookups;
layout(set = 0, binding = 1) uniform sampler2DShadow shadowMap;

layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

void main() {
    vec3 point = lookups.points[int(gl_FragCoord.x)].xyz;
    vec3 coord = shadowCoordFor(lookups.worldToShadow, point, vec3(0.0, 1.0, 0.0), lookups.params.y);
    outColor = vec4(sampleShadowPCF(shadowMap, coord, lookups.params.x));
}
