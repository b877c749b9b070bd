// Directional shadow lookups (see docs/SHADOWS.md). Include from a fragment shader that binds the
// map as a sampler2DShadow with DirectionalShadowMap's compare sampler (LessOrEqual, linear).
#ifndef JANUS_SHADOW_SAMPLING_GLSL
#define JANUS_SHADOW_SAMPLING_GLSL

// Shadow-map coordinates (u, v, depth) of a world position, pushed along the surface normal by
// `normalOffset` world units first. The push moves the lookup out of the surface by about a
// texel, which removes the acne that depth bias alone leaves at grazing light angles.
// `normal` need not be unit length; a zero normal means no offset.
vec3 shadowCoordFor(mat4 worldToShadow, vec3 worldPos, vec3 normal, float normalOffset) {
    float len = length(normal);
    vec3 offset = len > 0.0 ? normal * (normalOffset / len) : vec3(0.0);
    vec4 p = worldToShadow * vec4(worldPos + offset, 1.0);
    return p.xyz / p.w;
}

// Fraction of light reaching `shadowCoord` (1 lit, 0 shadowed): 3x3 taps one texel apart, each a
// hardware 2x2 bilinear comparison, so the kernel covers 4x4 texels with tent weights and the
// shadow edge is smooth. Outside the map (u, v or depth outside [0, 1]) nothing is known to block
// the light, so the result is 1.
float sampleShadowPCF(sampler2DShadow map, vec3 shadowCoord, float texelSize) {
    if (any(lessThan(shadowCoord, vec3(0.0))) || any(greaterThan(shadowCoord, vec3(1.0)))) return 1.0;
    float lit = 0.0;
    for (int y = -1; y <= 1; ++y) {
        for (int x = -1; x <= 1; ++x) {
            vec2 uv = shadowCoord.xy + vec2(float(x), float(y)) * texelSize;
            // Explicit level 0: the map has one level, and callers may sample under non-uniform
            // control flow, where implicit derivatives are undefined.
            lit += textureLod(map, vec3(uv, shadowCoord.z), 0.0);
        }
    }
    return lit * (1.0 / 9.0);
}

#endif
