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

// dot(e, basis(n)) per channel, unclamped.
vec3 shEvaluate(vec3 e[9], vec3 n) {
    ShBasis y = shEvalBasis(n);
    return e[0] * y.a.x + e[1] * y.a.y + e[2] * y.a.z + e[3] * y.a.w + e[4] * y.b.x + e[5] * y.b.y + e[6] * y.b.z + e[7] * y.b.w + e[8] * y.c;
}

// u^T P v for the quadratic part P of a band-2 radiance (l4..l8: its coefficients 4..8; the
// 3 z^2 term only, Y20's constant belongs to the caller's p0).
vec3 shQuadraticForm(vec3 l4, vec3 l5, vec3 l6, vec3 l7, vec3 l8, vec3 u, vec3 v) {
    return 0.54627422 * l8 * (u.x * v.x - u.y * v.y) + 3.0 * 0.31539157 * l6 * (u.z * v.z) +
           0.54627422 * (l4 * (u.x * v.y + u.y * v.x) + l5 * (u.y * v.z + u.z * v.y) + l7 * (u.x * v.z + u.z * v.x));
}

// Irradiance / pi from irradiance-/-pi coefficients `e` (the basis order above) at a surface
// whose shading normal n leans away from the normal of its plane g (smoothed vertex normals,
// normal maps): the clamped cosine about n over the directions above the plane only, since the
// surface hides what lies below it. Exact for the band-limited radiance the coefficients hold;
// the plain evaluation at n when the normals agree, 0 when n points straight into the surface.
// Unit vectors (a normal a little off unit length reads as a small lean). Unclamped. The closed
// form and its derivation: shEvaluateAboveSurface (renderer/src/ibl/spherical_harmonics.cpp),
// which tests check against quadrature.
vec3 shIrradianceAboveSurface(vec3 e[9], vec3 n, vec3 g) {
    const float kPi = 3.14159265;
    float c = clamp(dot(n, g), -1.0, 1.0);
    float s = sqrt(max(1.0 - c * c, 0.0));
    float theta = acos(c);
    vec3 t = n - c * g;
    float tangentLengthSq = dot(t, t);
    // Normals that agree leave the tangent free: any perpendicular gives the same moments.
    t = tangentLengthSq > 1e-12 ? t * inversesqrt(tangentLengthSq) : normalize(cross(g, abs(g.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0)));
    // Radiance SH (undo the clamped-cosine convolution: 1, 2/3, 1/4), as p0 + p.w + w^T P w.
    vec3 l1 = e[1] * 1.5, l2 = e[2] * 1.5, l3 = e[3] * 1.5;
    vec3 l4 = e[4] * 4.0, l5 = e[5] * 4.0, l6 = e[6] * 4.0, l7 = e[7] * 4.0, l8 = e[8] * 4.0;
    vec3 p0 = 0.28209479 * e[0] - 0.31539157 * l6;
    vec3 pg = 0.48860251 * (l3 * g.x + l1 * g.y + l2 * g.z), pt = 0.48860251 * (l3 * t.x + l1 * t.y + l2 * t.z);
    vec3 traceP = 3.0 * 0.31539157 * l6;
    vec3 pgg = shQuadraticForm(l4, l5, l6, l7, l8, g, g), ptt = shQuadraticForm(l4, l5, l6, l7, l8, t, t),
         pgt = shQuadraticForm(l4, l5, l6, l7, l8, g, t);
    // The clipped lobe's moments over pi.
    float ic = 0.5 * (s + (kPi - theta) * c), is = 0.5 * (kPi - theta) * s;
    float jgg = c * (2.0 / 3.0 + c - c * c * c / 3.0) + s * s * s * s / 3.0, jgt = s * (1.0 + c) / 3.0, jtt = 1.0 + c - jgg;
    return p0 * (0.5 * (1.0 + c)) + (4.0 / (3.0 * kPi)) * (ic * pg + is * pt) + (1.0 + c) / 8.0 * (traceP - pgg - ptt) +
           0.375 * (jgg * pgg + jtt * ptt + 2.0 * jgt * pgt);
}

#endif
