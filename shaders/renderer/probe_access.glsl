// Reflection probes for forward shading (docs/PROBES.md): each shown probe's GGX-prefiltered
// capture, blended over the sky. Probes come in blend order (smallest influence first); each
// contributes weight w of what is left, so the remainder (returned) is what the sky fills.
// The captures are one cube array (cube = slot), or, on devices without cube arrays
// (PROBES_AS_CUBES: GLES 3.0), one samplerCube per slot and at most two slots.
#ifndef JANUS_PROBE_ACCESS_GLSL
#define JANUS_PROBE_ACCESS_GLSL

#ifdef PROBES_AS_CUBES
const int kMaxShownProbes = 2;
layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_PROBE_CUBES) uniform samplerCube probeCube0;
layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_PROBE_CUBE_1) uniform samplerCube probeCube1;
vec3 probeRadianceLod(int slot, vec3 direction, float lod) {
    if (slot == 0) return textureLod(probeCube0, direction, lod).rgb;
    return textureLod(probeCube1, direction, lod).rgb;
}
#else
const int kMaxShownProbes = 16;
layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_PROBE_CUBES) uniform samplerCubeArray probeCubes;
vec3 probeRadianceLod(int slot, vec3 direction, float lod) { return textureLod(probeCubes, vec4(direction, float(slot)), lod).rgb; }
#endif

struct ReflectionProbe {
    vec4 influenceMin;   // xyz world box, w blend distance
    vec4 influenceMax;   // xyz, w 1 = box projection onto the parallax box
    vec4 parallaxMin;    // xyz, w the probe's mip 0 in the cube (array) = roughness 0
    vec4 parallaxMax;    // xyz, w its last mip = roughness 1
    vec4 position;       // xyz capture position, w slot (array cube / binding)
};

layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_REFLECTION_PROBES, std140) uniform ReflectionProbeUniforms {
    ivec4 probeCount;    // x probes listed (each shown: all its faces and mips from one update)
    ReflectionProbe probes[kMaxShownProbes];
} reflectionProbes;

// 1 deep inside the box, falling linearly to 0 over `blend` inside each face; 0 outside.
float probeInfluence(vec3 p, vec3 boxMin, vec3 boxMax, float blend) {
    vec3 inside = min(p - boxMin, boxMax - p);
    float depth = min(min(inside.x, inside.y), inside.z);
    if (depth < 0.0) return 0.0;
    return blend > 0.0 ? clamp(depth / blend, 0.0, 1.0) : 1.0;
}

// Box projection: the direction from the capture point to where the ray p + t r leaves the
// box. p is first clamped into the box, so surfaces lying on a face of the box (walls the box was
// fitted to) project the same whether interpolation puts them a hair inside or outside; t >= 0
// keeps the result continuous there. No component of r divides as 0.
vec3 boxProjectedDirection(vec3 p, vec3 r, vec3 boxMin, vec3 boxMax, vec3 capturePosition) {
    p = clamp(p, boxMin, boxMax);
    vec3 safeR = vec3(r.x >= 0.0 ? max(r.x, 1e-6) : min(r.x, -1e-6), r.y >= 0.0 ? max(r.y, 1e-6) : min(r.y, -1e-6),
                      r.z >= 0.0 ? max(r.z, 1e-6) : min(r.z, -1e-6));
    vec3 farthest = max((boxMax - p) / safeR, (boxMin - p) / safeR);
    float t = max(min(min(farthest.x, farthest.y), farthest.z), 0.0);
    vec3 d = p + r * t - capturePosition;
    return dot(d, d) > 1e-12 ? d : r;
}

// rgb: prefiltered radiance of the probes along r at perceptual roughness; a: the weight they
// leave to the sky (1 where no probe reaches). (Returned, not an out parameter: SPIRV-Cross's
// copy of an out parameter makes Mesa's GLSL compiler warn that it is used uninitialised.)
vec4 reflectionProbeRadiance(vec3 p, vec3 r, float perceptualRoughness) {
    float remaining = 1.0;
    vec3 sum = vec3(0.0);
    int count = min(reflectionProbes.probeCount.x, kMaxShownProbes);
    for (int i = 0; i < count; ++i) {
        ReflectionProbe probe = reflectionProbes.probes[i];
        float w = probeInfluence(p, probe.influenceMin.xyz, probe.influenceMax.xyz, probe.influenceMin.w);
        if (w <= 0.0) continue;
        vec3 direction = probe.influenceMax.w > 0.0
                             ? boxProjectedDirection(p, r, probe.parallaxMin.xyz, probe.parallaxMax.xyz, probe.position.xyz)
                             : r;
        float lod = mix(probe.parallaxMin.w, probe.parallaxMax.w, perceptualRoughness);
        sum += remaining * w * probeRadianceLod(int(probe.position.w), direction, lod);
        remaining *= 1.0 - w;
        if (remaining <= 0.0) break;
    }
    return vec4(sum, remaining);
}

#endif
