// The irradiance volume as shading reads it (docs/GI.md): forward shading and the relight's
// further bounces. Probes sit at origin + i * spacing (i in [0, counts)); the volume texture holds
// probe i's SH9 irradiance / pi at texel (i.x, i.z, i.y * 9 + k), k the coefficient (basis order
// of ibl/sh_basis.glsl); coefficient 0's alpha is the probe's validity (0 inside geometry).
// With visibility (counts.w = N > 0), probe p's tile of the visibility texture, (N + 2) x (N + 3)
// texels at ((p % tilesPerRow) (N + 2), (p / tilesPerRow) (N + 3)), holds in rg its N x N
// octahedral map of distance moments (mean, mean square; giOctahedralEncode) inside a one-texel
// border that repeats the map across its folds (so bilinear taps never leave the tile), and in
// texel (0, N + 2) the probe's position (where relocation put it: what it saw is from there).
#ifndef JANUS_GI_ACCESS_GLSL
#define JANUS_GI_ACCESS_GLSL
#include "janus/shaders/bindings.h"
#include "ibl/sh_basis.glsl"
#include "gi/gi_octahedral.glsl"

layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_GI_VOLUME) uniform highp sampler3D giVolumeTexture;
layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_GI_UNIFORMS, std140) uniform GiVolumeUniforms {
    vec4 origin;    // xyz probe (0, 0, 0), w 1 when the volume lights the scene (0: no volume, stand-ins bound)
    vec4 spacing;   // xyz between probes (> 0), w normal bias (world units)
    ivec4 counts;   // xyz probes per axis, w the visibility maps' size N (0: no visibility test)
} giVolume;
layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_GI_VISIBILITY) uniform highp sampler2D giVisibilityTexture;

// How much of probe `probe`'s light reaches `point` (DDGI's Chebyshev test, Majercik et al. 2019):
// 1 where the point is no further from the probe than what the probe saw in its direction on
// average; beyond that, the one-sided Chebyshev bound on the chance it is still in view, cubed
// (as DDGI, to darken light leaking through walls faster).
float giProbeVisibility(int probe, vec3 point) {
    int n = giVolume.counts.w;
    if (n <= 0) return 1.0;
    ivec2 tile = ivec2(n + 2, n + 3);
    int perRow = max(textureSize(giVisibilityTexture, 0).x / tile.x, 1);
    ivec2 origin = ivec2(probe % perRow, probe / perRow) * tile;
    vec3 toPoint = point - texelFetch(giVisibilityTexture, origin + ivec2(0, n + 2), 0).xyz;
    float distance = length(toPoint);
    if (distance <= 1e-6) return 1.0;
    // Texel centres of the map at (i + 0.5) / N of [0, 1]^2, shifted by the border.
    vec2 t = clamp((giOctahedralEncode(toPoint / distance) * 0.5 + 0.5) * float(n) + 0.5, vec2(0.5), vec2(float(n) + 0.5));
    vec2 cell = floor(t);
    vec2 f = t - cell;
    ivec2 b = origin + ivec2(cell);
    vec2 moments = mix(mix(texelFetch(giVisibilityTexture, b, 0).xy, texelFetch(giVisibilityTexture, b + ivec2(1, 0), 0).xy, f.x),
                       mix(texelFetch(giVisibilityTexture, b + ivec2(0, 1), 0).xy, texelFetch(giVisibilityTexture, b + ivec2(1, 1), 0).xy, f.x),
                       f.y);
    if (distance <= moments.x) return 1.0;
    // A floor on the variance keeps a flat wall's own texels from shadowing points on it.
    float variance = max(moments.y - moments.x * moments.x, 1e-4 * moments.x * moments.x);
    float beyond = distance - moments.x;
    float chebyshev = variance / (variance + beyond * beyond);
    return chebyshev * chebyshev * chebyshev;
}

// Irradiance / pi at `position` for `normal` on a surface whose plane has normal `surfaceNormal`
// (light from below that plane does not count: shIrradianceAboveSurface; the same vector twice is
// the plain evaluation),
// rgb clamped at 0, and how much the volume covers the point (a): 1 inside the volume's bounds
// (the probes' cells: half a spacing beyond the outer probes, so a room's walls are covered),
// falling to 0 one probe spacing outside them, and 0 where every probe around is invalid.
// Trilinear over the 8 surrounding probes (each axis's weight at least 0.001), each weighted by its
// validity and its visibility of the point (giProbeVisibility, at least 1e-6, and a weight under
// 0.2 crushed towards 0 as DDGI does), weights renormalised; beyond the outer probes, their values.
vec4 giIrradianceOverPi(vec3 position, vec3 normal, vec3 surfaceNormal) {
    if (giVolume.origin.w <= 0.0) return vec4(0.0);
    ivec3 counts = giVolume.counts.xyz;
    vec3 lookup = position + normal * giVolume.spacing.w;
    vec3 g = (lookup - giVolume.origin.xyz) / giVolume.spacing.xyz;
    vec3 last = vec3(counts - 1);
    vec3 outside = max(max(-0.5 - g, g - (last + 0.5)), vec3(0.0));
    float coverage = clamp(1.0 - max(outside.x, max(outside.y, outside.z)), 0.0, 1.0);
    if (coverage <= 0.0) return vec4(0.0);
    g = clamp(g, vec3(0.0), last);
    ivec3 base = min(ivec3(floor(g)), max(counts - 2, ivec3(0)));
    vec3 f = g - vec3(base);
    vec3 c0 = vec3(0.0), c1 = vec3(0.0), c2 = vec3(0.0), c3 = vec3(0.0), c4 = vec3(0.0), c5 = vec3(0.0), c6 = vec3(0.0),
         c7 = vec3(0.0), c8 = vec3(0.0);
    float weightSum = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
        ivec3 o = ivec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
        ivec3 p = min(base + o, counts - 1);
        // Never quite 0 per axis: beyond the outer probes the clamp puts every weight on one layer,
        // and where those probes are invalid the valid neighbours must still take over (the
        // cornell box's floor beside Suzanne, whose nearest probe is inside her, was black).
        vec3 w3 = max(mix(vec3(1.0) - f, f, vec3(o)), vec3(0.001));
        int z0 = p.y * 9;
        vec4 first = texelFetch(giVolumeTexture, ivec3(p.x, p.z, z0), 0);
        if (first.a <= 0.0) continue;
        float visibility = max(giProbeVisibility(p.x + counts.x * (p.y + counts.y * p.z), lookup), 1e-6);
        if (visibility < 0.2) visibility *= visibility * visibility / (0.2 * 0.2);
        float w = w3.x * w3.y * w3.z * first.a * visibility;
        weightSum += w;
        c0 += w * first.rgb;
        c1 += w * texelFetch(giVolumeTexture, ivec3(p.x, p.z, z0 + 1), 0).rgb;
        c2 += w * texelFetch(giVolumeTexture, ivec3(p.x, p.z, z0 + 2), 0).rgb;
        c3 += w * texelFetch(giVolumeTexture, ivec3(p.x, p.z, z0 + 3), 0).rgb;
        c4 += w * texelFetch(giVolumeTexture, ivec3(p.x, p.z, z0 + 4), 0).rgb;
        c5 += w * texelFetch(giVolumeTexture, ivec3(p.x, p.z, z0 + 5), 0).rgb;
        c6 += w * texelFetch(giVolumeTexture, ivec3(p.x, p.z, z0 + 6), 0).rgb;
        c7 += w * texelFetch(giVolumeTexture, ivec3(p.x, p.z, z0 + 7), 0).rgb;
        c8 += w * texelFetch(giVolumeTexture, ivec3(p.x, p.z, z0 + 8), 0).rgb;
    }
    if (weightSum <= 0.0) return vec4(0.0);
    vec3 coefficients[9] = vec3[9](c0, c1, c2, c3, c4, c5, c6, c7, c8);
    vec3 sum = surfaceNormal == normal ? shEvaluate(coefficients, normal) : shIrradianceAboveSurface(coefficients, normal, surfaceNormal);
    return vec4(max(sum / weightSum, vec3(0.0)), coverage);
}
#endif
