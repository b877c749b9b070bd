// The L2 spherical-harmonic basis (docs/IBL.md, "Spherical harmonics (L2)"), shared by the SH
// projection shaders (sh_common.glsl) and shading (renderer/sky_access.glsl). Declares no
// resources, so any shader can include it.
#ifndef JANUS_IBL_SH_BASIS_GLSL
#define JANUS_IBL_SH_BASIS_GLSL

// The nine basis values: a = (0..3), b = (4..7), c = 8.
struct ShBasis {
    vec4 a;
    vec4 b;
    float c;
};

// One vectorised evaluation of all nine terms at a unit direction (no per-coefficient branches).
ShBasis shEvalBasis(vec3 n) {
    ShBasis basis;
    basis.a = vec4(0.28209479, 0.48860251, 0.48860251, 0.48860251) * vec4(1.0, n.y, n.z, n.x);
    basis.b = vec4(1.09254843, 1.09254843, 0.31539157, 1.09254843) * vec4(n.x * n.y, n.y * n.z, 3.0 * n.z * n.z - 1.0, n.x * n.z);
    basis.c = 0.54627422 * (n.x * n.x - n.y * n.y);
    return basis;
}

#endif
