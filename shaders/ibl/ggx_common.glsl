// Shared by the IBL shaders (equirect_to_cube.*, ggx_prefilter.*): the
// equirectangular mapping and the GGX prefilter loop. The mappings are documented in
// docs/IBL.md and mirrored on the CPU by renderer/src/ibl/environment_map.cpp.
#ifndef JANUS_IBL_GGX_COMMON_GLSL
#define JANUS_IBL_GGX_COMMON_GLSL

#include "janus/shaders/bindings.h"
#include "ibl/cube_geometry.glsl"

const float kPi = 3.14159265358979;

// Equirectangular (u, v) of a unit direction: u = 0.5 + atan(x, -z) / 2pi (u = 0.5 looks along
// -Z, u = 0.75 along +X, u = 0 / 1 along +Z), v = acos(y) / pi (v = 0 is +Y, row 0 on top).
vec2 equirectUv(vec3 d) {
    float u = 0.5 + atan(d.x, -d.z) / (2.0 * kPi);
    float v = acos(clamp(d.y, -1.0, 1.0)) / kPi;
    return vec2(u, v);
}

#ifdef JANUS_IBL_PREFILTER
// std140 mirrors: renderer/src/ibl/ggx_prefilter.cpp.
layout(std140, set = 0, binding = JANUS_BINDING_PREFILTER_PARAMS) uniform PrefilterParams {
    ivec4 prefilterParams;   // x face (fallback path), y target mip, z target size (texels), w sample count
};

// 1024 vec4 = 16 KiB: the minimum GL_MAX_UNIFORM_BLOCK_SIZE (GLES 3.0, GL) and maxUniformBufferRange.
#define JANUS_GGX_MAX_SAMPLES 1024
layout(std140, set = 0, binding = JANUS_BINDING_PREFILTER_SAMPLES) uniform PrefilterSamples {
    // xyz: the sample direction L in the frame where N = V = +Z (z = NdotL > 0 for used samples,
    // 0 for padding); w: the source mip to read it from.
    vec4 ggxSamples[JANUS_GGX_MAX_SAMPLES];
};

layout(set = 0, binding = JANUS_BINDING_PREFILTER_SOURCE) uniform samplerCube prefilterSource;

// The split-sum prefilter at the centre of texel `texel` of face `face`: the NdotL-weighted mean
// of the importance-sampled GGX directions around N = V = R. Weight sum 0 -> black, never 0/0.
vec4 prefilterTexel(int face, ivec2 texel) {
    vec3 n = cubeTexelDirection(face, texel, prefilterParams.z);
    vec3 up = abs(n.z) < 0.999 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
    vec3 tangentX = normalize(cross(up, n));
    vec3 tangentY = cross(n, tangentX);
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    int count = min(prefilterParams.w, JANUS_GGX_MAX_SAMPLES);
    for (int i = 0; i < count; ++i) {
        vec4 s = ggxSamples[i];
        if (s.z <= 0.0) continue;
        vec3 l = tangentX * s.x + tangentY * s.y + n * s.z;
        sum += textureLod(prefilterSource, l, s.w).rgb * s.z;
        weight += s.z;
    }
    vec3 result = weight > 0.0 ? sum / weight : vec3(0.0);
    // fp16 storage: keep radiance finite (65504 is the largest half).
    return vec4(min(result, vec3(65504.0)), 1.0);
}
#endif  // JANUS_IBL_PREFILTER

#endif
