// L2 spherical harmonics shared by sh_project.comp, sh_reduce.comp, sh_gather.frag,
// sh_gather_final.frag and (later) shading. Conventions (docs/IBL.md, "Spherical harmonics
// (L2)"): real basis, order l = 0; l = 1 m = -1, 0, 1; l = 2 m = -2..2, the same constants as
// renderer/src/ibl/spherical_harmonics.h. Needs "janus/shaders/bindings.h" for the uniforms.
#ifndef JANUS_IBL_SH_COMMON_GLSL
#define JANUS_IBL_SH_COMMON_GLSL

// x: face size in texels (of the mip projected); y: per-group partial sums (compute path).
layout(set = 0, binding = JANUS_BINDING_SH_UNIFORMS, std140) uniform ShUniforms {
    uvec4 shParams;
};

#include "ibl/cube_geometry.glsl"
#include "ibl/sh_basis.glsl"

// Term k (0..8) of a basis, selected with masks rather than branches.
float shBasisAt(ShBasis basis, int k) {
    vec4 maskA = vec4(equal(ivec4(0, 1, 2, 3), ivec4(k)));
    vec4 maskB = vec4(equal(ivec4(4, 5, 6, 7), ivec4(k)));
    return dot(basis.a, maskA) + dot(basis.b, maskB) + basis.c * float(k == 8);
}

// A_l / pi of coefficient k's band: 1, 2/3, 1/4 (the clamped-cosine convolution over pi).
float shCosineOverPi(int k) {
    return k == 0 ? 1.0 : (k < 4 ? 2.0 / 3.0 : 0.25);
}

// The projection shaders sample `cube` with a nearest sampler at texel centres (level 0 of the
// bound mip view) and take solid angles (the same on every face) from an R32F size x size texture
// made in double on the CPU: the exact corner formula cancels badly in float for small texels.
#endif
