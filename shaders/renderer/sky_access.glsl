// The sky's image-based lighting for forward shading (docs/IBL.md): the GGX-prefiltered cube,
// the split-sum DFG table and the SH9 irradiance. frame.skyParams: x 1 when the scene has a sky,
// y the prefiltered cube's last mip (roughness 1), z intensity. Without a sky the bindings hold
// stand-ins and x is 0. The SH coefficients are a storage buffer on the compute path and a 9x1
// RGBA32F texture on the fallback path (LIGHTS_IN_TEXTURES, as light_access.glsl).
#ifndef JANUS_SKY_ACCESS_GLSL
#define JANUS_SKY_ACCESS_GLSL

#include "ibl/sh_basis.glsl"

layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_SKY_SPECULAR) uniform samplerCube skySpecular;
layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_DFG) uniform sampler2D dfgTable;

#ifdef LIGHTS_IN_TEXTURES
layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_SKY_SH) uniform highp sampler2D skyShTexture;
vec3 skyShCoefficient(int k) { return texelFetch(skyShTexture, ivec2(k, 0), 0).rgb; }
#else
layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_SKY_SH, std430) readonly buffer SkySh { vec4 skyShCoefficients[9]; };
vec3 skyShCoefficient(int k) { return skyShCoefficients[k].rgb; }
#endif

// Irradiance / pi at normal n (what Lambert multiplies albedo by), clamped at 0: a band-limited
// reconstruction rings negative behind very bright, small sources (docs/IBL.md).
vec3 skyIrradianceOverPi(vec3 n) {
    ShBasis y = shEvalBasis(n);
    vec3 sum = skyShCoefficient(0) * y.a.x + skyShCoefficient(1) * y.a.y + skyShCoefficient(2) * y.a.z +
               skyShCoefficient(3) * y.a.w + skyShCoefficient(4) * y.b.x + skyShCoefficient(5) * y.b.y +
               skyShCoefficient(6) * y.b.z + skyShCoefficient(7) * y.b.w + skyShCoefficient(8) * y.c;
    return max(sum, vec3(0.0));
}

// The same for a shading normal n on a surface whose triangle's plane has normal g: only the sky
// above that plane counts (the surface hides the rest; docs/GI.md "Bent normals", the volume's
// lookup does the same). n == g is the plain evaluation.
vec3 skyIrradianceOverPi(vec3 n, vec3 g) {
    if (n == g) return skyIrradianceOverPi(n);
    vec3 e[9] = vec3[9](skyShCoefficient(0), skyShCoefficient(1), skyShCoefficient(2), skyShCoefficient(3), skyShCoefficient(4),
                        skyShCoefficient(5), skyShCoefficient(6), skyShCoefficient(7), skyShCoefficient(8));
    return max(shIrradianceAboveSurface(e, n, g), vec3(0.0));
}

// Split-sum specular (docs/IBL.md): prefiltered radiance along the reflection at the roughness's
// mip, times f0 * A + f90 * B from the DFG table (f90 1 but for KHR_materials_specular dielectrics).
vec3 skyPrefilteredRadiance(vec3 reflected, float perceptualRoughness, float lastMip) {
    return textureLod(skySpecular, reflected, perceptualRoughness * lastMip).rgb;
}
vec3 splitSumScale(float NoV, float perceptualRoughness, vec3 f0, float f90) {
    // Level 0 explicitly: this runs after the alpha test's discard and in branches, where implicit
    // derivatives are undefined; the table has one level.
    vec2 dfg = textureLod(dfgTable, vec2(NoV, perceptualRoughness), 0.0).rg;
    return f0 * dfg.x + f90 * dfg.y;
}

// Specular occlusion from the material's ambient occlusion (Lagarde & de Rousiers 2014).
float specularOcclusion(float NoV, float ao, float perceptualRoughness) {
    return clamp(pow(NoV + ao, exp2(-16.0 * perceptualRoughness - 1.0)) - 1.0 + ao, 0.0, 1.0);
}

#endif
