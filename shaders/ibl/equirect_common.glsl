// Shared by equirect_to_cube.comp / .frag: the equirectangular source and the face parameters.
#ifndef JANUS_IBL_EQUIRECT_COMMON_GLSL
#define JANUS_IBL_EQUIRECT_COMMON_GLSL

#include "ibl/ggx_common.glsl"

// std140 mirror: renderer/src/ibl/environment_map.cpp.
layout(std140, set = 0, binding = JANUS_BINDING_EQUIRECT_PARAMS) uniform EquirectParams {
    ivec4 equirectParams;   // x face (fallback path), y face size (texels)
};
layout(set = 0, binding = JANUS_BINDING_EQUIRECT_SOURCE) uniform sampler2D equirectSource;

// Bilinear sample of the equirect (the sampler repeats in u, clamps in v) along the centre of
// `texel` of face `face`. Non-finite or negative radiance never reaches the cube (the loader
// already refuses it); values are clamped to the largest half.
vec4 equirectTexel(int face, ivec2 texel) {
    vec3 d = cubeTexelDirection(face, texel, equirectParams.y);
    vec3 c = textureLod(equirectSource, equirectUv(d), 0.0).rgb;
    return vec4(clamp(c, vec3(0.0), vec3(65504.0)), 1.0);
}

#endif
