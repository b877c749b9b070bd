// L2 spherical harmonics on the CPU (internal to the renderer): the real basis, projection of a
// cube map in double precision with exact texel solid angles, the clamped-cosine convolution and
// closed forms for tests. Conventions: docs/IBL.md, "Spherical harmonics (L2)". The GPU version
// (ShIrradiance, sh_irradiance.h) evaluates the same basis in shaders/ibl/sh_common.glsl.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "ibl/cube_geometry.h"

namespace janus::renderer {

inline constexpr uint32_t kShCoefficientCount = 9;

// Basis order: index = l * (l + 1) + m: (0,0); (1,-1), (1,0), (1,1); (2,-2), (2,-1), (2,0), (2,1), (2,2).
// Constants: the usual sqrt((2l+1)/(4 pi) (l-|m|)!/(l+|m|)!) (times sqrt 2 for m != 0), to double precision.
inline constexpr double kShY00 = 0.28209479177387814;   // 1 / (2 sqrt(pi))
inline constexpr double kShY1 = 0.48860251190291992;    // sqrt(3 / (4 pi))
inline constexpr double kShY2a = 1.0925484305920792;    // sqrt(15 / (4 pi))   (xy, yz, xz)
inline constexpr double kShY20 = 0.31539156525252005;   // sqrt(5 / (16 pi))   (3z^2 - 1)
inline constexpr double kShY22 = 0.54627421529603959;   // sqrt(15 / (16 pi))  (x^2 - y^2)
// Clamped-cosine convolution A_l divided by pi: A0 = pi, A1 = 2 pi / 3, A2 = pi / 4.
inline constexpr std::array<double, 3> kShCosineOverPi = {1.0, 2.0 / 3.0, 0.25};

// The nine basis functions at a unit direction: one expression per term, no branches.
std::array<double, 9> shBasis(const glm::dvec3& n);
// Band l of coefficient i (0, 1 or 2).
inline constexpr uint32_t shBand(uint32_t i) { return i == 0 ? 0 : i < 4 ? 1 : 2; }

// Nine RGB coefficients. What they mean (radiance SH or irradiance / pi) is up to the producer;
// see shProjectRadiance / shConvolveIrradiance.
using ShRgb = std::array<glm::dvec3, 9>;

// A cube map on the CPU: six faces (+X, -X, +Y, -Y, +Z, -Z) of size x size RGBA texels, row 0
// first, in the Vulkan/GL face orientation (docs/ARCHITECTURE.md, "Cube maps").
struct CubeImage {
    uint32_t size = 0;
    std::array<std::vector<glm::vec4>, 6> faces;

    static CubeImage filled(uint32_t size, const glm::vec4& value);
    glm::vec4& at(uint32_t face, uint32_t x, uint32_t y) { return faces[face][size_t(y) * size + x]; }
    const glm::vec4& at(uint32_t face, uint32_t x, uint32_t y) const { return faces[face][size_t(y) * size + x]; }
};

// L_lm = sum over texels of radiance (rgb) * Y_lm(direction) * solid angle, in double.
ShRgb shProjectRadiance(const CubeImage& cube);
// c_lm = (A_l / pi) * L_lm: then dot(c, shBasis(n)) is irradiance(n) / pi, what Lambert
// diffuse multiplies albedo by. This is what ShIrradiance stores.
ShRgb shConvolveIrradiance(const ShRgb& radiance);
inline ShRgb shProjectIrradiance(const CubeImage& cube) { return shConvolveIrradiance(shProjectRadiance(cube)); }

// dot(coefficients, basis(n)) per channel, unclamped (may be negative: L2 truncation rings).
glm::dvec3 shEvaluate(const ShRgb& coefficients, const glm::dvec3& n);
// What shading uses: shEvaluate clamped to >= 0 per channel (docs/IBL.md, "Clamping").
glm::dvec3 shEvaluateIrradiance(const ShRgb& irradianceOverPi, const glm::dvec3& n);
// Irradiance / pi at a surface whose shading normal `n` leans away from the normal of its plane
// `surfaceNormal` (smoothed vertex normals, normal maps): the clamped cosine about n, over the
// directions above the plane only, since the surface hides what lies below it. Exact for the
// band-limited radiance the coefficients hold (the clipped lobe's moments up to order 2 in
// closed form, docs/GI.md "Bent normals"); shEvaluate(irradianceOverPi, n) when the normals
// agree; 0 when n points straight into the surface. Unclamped. Unit vectors.
glm::dvec3 shEvaluateAboveSurface(const ShRgb& irradianceOverPi, const glm::dvec3& n, const glm::dvec3& surfaceNormal);

// Closed forms of the radiance SH (exact integrals, not projections of a sampled cube):
// L(w) = color.
ShRgb shConstantRadiance(const glm::dvec3& color);
// L(w) = color * max(0, dot(axis, w)), unit axis: L_lm = A_l Y_lm(axis) (zonal rotation).
ShRgb shClampedCosineRadiance(const glm::dvec3& axis, const glm::dvec3& color);
// L(w) = color * w[axis] (axis 0, 1, 2 = x, y, z): only the matching l = 1 term, sqrt(4 pi / 3).
ShRgb shLinearGradientRadiance(uint32_t axis, const glm::dvec3& color);

// Reference irradiance / pi at n by brute force over the cube's texels (double):
// (1/pi) sum radiance * max(0, dot(n, w)) * solid angle. For tests of the SH approximation.
glm::dvec3 cubeIrradianceOverPi(const CubeImage& cube, const glm::dvec3& n);

}  // namespace janus::renderer
