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
    // Bright-texel variant only: x GGX alpha^2 of D (alpha = roughness^2), y the lobe's normalisation
    // Z = integral of D(n.h) max(n.l, 0) over l, z source face size, w 1 = this mip takes the bright
    // texels out (0: roughness 0, the mirror reads the source).
    vec4 prefilterLobe;
};

// 1024 vec4 = 16 KiB: the minimum GL_MAX_UNIFORM_BLOCK_SIZE (GLES 3.0, GL) and maxUniformBufferRange.
#define JANUS_GGX_MAX_SAMPLES 1024
layout(std140, set = 0, binding = JANUS_BINDING_PREFILTER_SAMPLES) uniform PrefilterSamples {
    // xyz: the sample direction L in the frame where N = V = +Z (z = NdotL > 0 for used samples,
    // 0 for padding); w: the source mip to read it from.
    vec4 ggxSamples[JANUS_GGX_MAX_SAMPLES];
};

layout(set = 0, binding = JANUS_BINDING_PREFILTER_SOURCE) uniform samplerCube prefilterSource;

#ifdef JANUS_IBL_PREFILTER_BRIGHT
// The bright-texel split (renderer/src/ibl/ggx_prefilter.cpp, docs/IBL.md "Bright texels"): the
// source without its bright texels (same size, its own box-filtered chain) and the list of those
// texels, copied from the list texture (one row of RGBA16F texels, 2 per entry) into a uniform
// block: element i holds texels 2i and 2i + 1 as packed halves. Element 0 = the header (x entries,
// y 1 = more bright texels than entries: the split is off, read the source, add nothing); element
// k + 1 = entry k: (radiance rgb, 1 = valid), (face, x, y, 1).
layout(set = 0, binding = JANUS_BINDING_PREFILTER_REST) uniform samplerCube prefilterRest;
// 1024 uvec4 = 16 KiB, the minimum uniform block size: up to 1023 entries.
layout(std140, set = 0, binding = JANUS_BINDING_PREFILTER_BRIGHT_LIST) uniform PrefilterBrightList {
    uvec4 prefilterBrightData[1024];
};
vec4 brightListFirst(int element) {
    uvec4 p = prefilterBrightData[element];
    return vec4(unpackHalf2x16(p.x), unpackHalf2x16(p.y));
}
vec4 brightListSecond(int element) {
    uvec4 p = prefilterBrightData[element];
    return vec4(unpackHalf2x16(p.z), unpackHalf2x16(p.w));
}

// sum_k L_k D(n.h_k) max(n.l_k, 0) Omega_k / Z over the listed texels: exactly the terms the CPU
// reference (GgxReference) has for them. Each texel's weight is at most 1 (a texel cannot hold more
// than the whole lobe; only lobes far narrower than a texel get there).
vec3 brightTexelSum(vec3 n, int count) {
    float a2 = prefilterLobe.x;
    float z = prefilterLobe.y;
    float size = prefilterLobe.z;
    vec3 sum = vec3(0.0);
    for (int k = 0; k < count; ++k) {
        vec4 radiance = brightListFirst(k + 1);
        vec4 where = brightListSecond(k + 1);
        if (radiance.w < 0.5) continue;
        vec3 c = cubeDirection(int(where.x + 0.5), (where.yz + 0.5) / size);   // major axis 1
        float invLength = inversesqrt(dot(c, c));
        vec3 l = c * invLength;
        float nDotL = dot(n, l);
        if (nDotL <= 0.0) continue;
        float solidAngle = 4.0 / (size * size) * invLength * invLength * invLength;   // texel area / r^3 at its centre
        // With h = normalize(n + l): |n x h|^2 = (1 - n.l) / 2, (n.h)^2 = (1 + n.l) / 2; 1 - n.l as
        // |n x l|^2 / (1 + n.l), without fp32 cancellation for near-mirror lobes.
        vec3 nxl = cross(n, l);
        float d = 0.5 * (dot(nxl, nxl) / (1.0 + nDotL) + a2 * (1.0 + nDotL));
        float ggx = a2 / (kPi * d * d);
        sum += radiance.rgb * min(ggx * nDotL * solidAngle / z, 1.0);
    }
    return sum;
}
#endif

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
#ifdef JANUS_IBL_PREFILTER_BRIGHT
    // The same for every invocation: the list's header and this mip's flag.
    vec4 header = brightListFirst(0);
    bool split = prefilterLobe.w > 0.5 && header.y < 0.5;
    if (split) {
        for (int i = 0; i < count; ++i) {
            vec4 s = ggxSamples[i];
            if (s.z <= 0.0) continue;
            vec3 l = tangentX * s.x + tangentY * s.y + n * s.z;
            sum += textureLod(prefilterRest, l, s.w).rgb * s.z;
            weight += s.z;
        }
    } else
#endif
    for (int i = 0; i < count; ++i) {
        vec4 s = ggxSamples[i];
        if (s.z <= 0.0) continue;
        vec3 l = tangentX * s.x + tangentY * s.y + n * s.z;
        sum += textureLod(prefilterSource, l, s.w).rgb * s.z;
        weight += s.z;
    }
    vec3 result = weight > 0.0 ? sum / weight : vec3(0.0);
#ifdef JANUS_IBL_PREFILTER_BRIGHT
    if (split) result += brightTexelSum(n, int(header.x + 0.5));
#endif
    // fp16 storage: keep radiance finite (65504 is the largest half).
    return vec4(min(result, vec3(65504.0)), 1.0);
}
#endif  // JANUS_IBL_PREFILTER

#endif
