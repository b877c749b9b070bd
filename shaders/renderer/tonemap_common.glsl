// Tonemapping shared by tonemap.comp (compute path) and tonemap.frag (fallback path), so both
// paths run the same math on the same inputs.
#include "janus/shaders/bindings.h"

layout(set = 0, binding = JANUS_BINDING_TONEMAP_UNIFORMS, std140) uniform TonemapUniforms {
    vec4 params;   // x exposure
} tonemap;

layout(set = 0, binding = JANUS_BINDING_TONEMAP_HDR) uniform sampler2D hdrImage;

// ACES filmic curve, Narkowicz's fit.
vec3 acesFitted(vec3 x) {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

vec3 encodeSrgb(vec3 linear) {
    vec3 low = linear * 12.92;
    vec3 high = 1.055 * pow(linear, vec3(1.0 / 2.4)) - 0.055;
    return mix(high, low, lessThanEqual(linear, vec3(0.0031308)));
}

// Display colour of one HDR texel, already on the 8-bit grid: rounding here, rather than in the
// unorm conversion of the store / attachment write, keeps both paths bit-identical.
vec4 tonemapTexel(ivec2 texel) {
    vec3 hdr = max(texelFetch(hdrImage, texel, 0).rgb, vec3(0.0));
    vec3 display = encodeSrgb(acesFitted(hdr * tonemap.params.x));
    return vec4(floor(display * 255.0 + 0.5) / 255.0, 1.0);
}
