#include "ibl/spherical_harmonics.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "janus/renderer/settings.h"

namespace janus::renderer {

std::array<double, 9> shBasis(const glm::dvec3& n) {
    return {
        kShY00,
        kShY1 * n.y,
        kShY1 * n.z,
        kShY1 * n.x,
        kShY2a * n.x * n.y,
        kShY2a * n.y * n.z,
        kShY20 * (3.0 * n.z * n.z - 1.0),
        kShY2a * n.x * n.z,
        kShY22 * (n.x * n.x - n.y * n.y),
    };
}

CubeImage CubeImage::filled(uint32_t size, const glm::vec4& value) {
    CubeImage cube;
    cube.size = size;
    for (auto& face : cube.faces) face.assign(size_t(size) * size, value);
    return cube;
}

ShRgb shProjectRadiance(const CubeImage& cube) {
    ShRgb sum{};
    std::vector<double> solidAngles(size_t(cube.size) * cube.size);
    for (uint32_t y = 0; y < cube.size; ++y)
        for (uint32_t x = 0; x < cube.size; ++x) solidAngles[size_t(y) * cube.size + x] = cubeTexelSolidAngle(x, y, cube.size);
    for (uint32_t face = 0; face < 6; ++face)
        for (uint32_t y = 0; y < cube.size; ++y)
            for (uint32_t x = 0; x < cube.size; ++x) {
                const glm::dvec3 weighted = glm::dvec3(glm::vec3(cube.at(face, x, y))) * solidAngles[size_t(y) * cube.size + x];
                const std::array<double, 9> basis = shBasis(cubeTexelDirection(face, x, y, cube.size));
                for (uint32_t i = 0; i < 9; ++i) sum[i] += weighted * basis[i];
            }
    return sum;
}

ShRgb shConvolveIrradiance(const ShRgb& radiance) {
    ShRgb out;
    for (uint32_t i = 0; i < 9; ++i) out[i] = radiance[i] * kShCosineOverPi[shBand(i)];
    return out;
}

glm::dvec3 shEvaluate(const ShRgb& coefficients, const glm::dvec3& n) {
    const std::array<double, 9> basis = shBasis(n);
    glm::dvec3 sum(0.0);
    for (uint32_t i = 0; i < 9; ++i) sum += coefficients[i] * basis[i];
    return sum;
}

glm::dvec3 shEvaluateIrradiance(const ShRgb& irradianceOverPi, const glm::dvec3& n) {
    return glm::max(shEvaluate(irradianceOverPi, n), glm::dvec3(0.0));
}

glm::dvec3 shEvaluateAboveSurface(const ShRgb& irradianceOverPi, const glm::dvec3& n, const glm::dvec3& surfaceNormal) {
    // The clipped lobe K(w) = max(0, n.w) [g.w > 0], g the surface normal, meets a band-limited
    // radiance L(w) = p0 + p.w + w^T P w only through its moments: E = p0 M0 + p.m + tr(P S).
    // With c = cos(theta) between n and g, t the unit tangent from g towards n and b = g x t, the
    // lobe lives on a lune of angle pi - theta, and (integrating about b):
    //   M0 = pi (1 + c) / 2
    //   m  = 4/3 (Ic g + Is t),  Ic = (s + (pi - theta) c) / 2,  Is = (pi - theta) s / 2
    //   S  = pi (1 + c) / 8 b b^T + 3 pi / 8 (Jgg g g^T + Jtt t t^T + Jgt (g t^T + t g^T))
    //   Jgg = c (2/3 + c - c^3 / 3) + s^4 / 3,  Jgt = s (1 + c) / 3,  Jtt = 1 + c - Jgg
    // At theta = 0 these are the clamped cosine's moments, whatever t is.
    const double pi = std::numbers::pi;
    const glm::dvec3& g = surfaceNormal;
    const double c = std::clamp(glm::dot(n, g), -1.0, 1.0);
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    const double theta = std::acos(c);
    glm::dvec3 t = n - c * g;
    const double tangentLength = glm::length(t);
    t = tangentLength > 1e-9 ? t / tangentLength
                             : glm::normalize(glm::cross(g, std::abs(g.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    // Radiance SH from irradiance / pi, then its polynomial form.
    ShRgb L{};
    for (uint32_t i = 0; i < 9; ++i) L[i] = irradianceOverPi[i] / kShCosineOverPi[shBand(i)];
    const glm::dvec3 p0 = kShY00 * L[0] - kShY20 * L[6];
    auto linear = [&](const glm::dvec3& u) { return kShY1 * (L[3] * u.x + L[1] * u.y + L[2] * u.z); };
    auto quadratic = [&](const glm::dvec3& u, const glm::dvec3& v) {
        return kShY22 * L[8] * (u.x * v.x - u.y * v.y) + 3.0 * kShY20 * L[6] * (u.z * v.z) +
               0.5 * kShY2a * (L[4] * (u.x * v.y + u.y * v.x) + L[5] * (u.y * v.z + u.z * v.y) + L[7] * (u.x * v.z + u.z * v.x));
    };
    const glm::dvec3 traceP = 3.0 * kShY20 * L[6];
    const double ic = 0.5 * (s + (pi - theta) * c), is = 0.5 * (pi - theta) * s;
    const double jgg = c * (2.0 / 3.0 + c - c * c * c / 3.0) + s * s * s * s / 3.0, jgt = s * (1.0 + c) / 3.0, jtt = 1.0 + c - jgg;
    const glm::dvec3 pgg = quadratic(g, g), ptt = quadratic(t, t), pgt = quadratic(g, t);
    const glm::dvec3 e = p0 * (0.5 * pi * (1.0 + c)) + (4.0 / 3.0) * (ic * linear(g) + is * linear(t)) +
                         (pi / 8.0) * (1.0 + c) * (traceP - pgg - ptt) + (3.0 * pi / 8.0) * (jgg * pgg + jtt * ptt + 2.0 * jgt * pgt);
    return e / pi;
}

ShRgb shConstantRadiance(const glm::dvec3& color) {
    ShRgb out{};
    out[0] = color * (2.0 * std::sqrt(std::numbers::pi));   // integral of Y00 = 4 pi / (2 sqrt pi)
    return out;
}

ShRgb shClampedCosineRadiance(const glm::dvec3& axis, const glm::dvec3& color) {
    const double pi = std::numbers::pi;
    const std::array<double, 3> a = {pi, 2.0 * pi / 3.0, pi / 4.0};
    const std::array<double, 9> basis = shBasis(glm::normalize(axis));
    ShRgb out;
    for (uint32_t i = 0; i < 9; ++i) out[i] = color * (a[shBand(i)] * basis[i]);
    return out;
}

ShRgb shLinearGradientRadiance(uint32_t axis, const glm::dvec3& color) {
    if (axis > 2) throw RendererError(fmt::format("linear gradient axis {} does not exist (0, 1, 2 = x, y, z)", axis));
    ShRgb out{};
    // Y_1,-1 = k y (index 1), Y_1,0 = k z (index 2), Y_1,1 = k x (index 3); integral of k w_a^2 = k 4 pi / 3.
    const uint32_t index = axis == 0 ? 3 : axis == 1 ? 1 : 2;
    out[index] = color * std::sqrt(4.0 * std::numbers::pi / 3.0);
    return out;
}

glm::dvec3 cubeIrradianceOverPi(const CubeImage& cube, const glm::dvec3& n) {
    glm::dvec3 sum(0.0);
    for (uint32_t face = 0; face < 6; ++face)
        for (uint32_t y = 0; y < cube.size; ++y)
            for (uint32_t x = 0; x < cube.size; ++x) {
                const double cosine = glm::dot(n, cubeTexelDirection(face, x, y, cube.size));
                if (cosine > 0.0) sum += glm::dvec3(glm::vec3(cube.at(face, x, y))) * (cosine * cubeTexelSolidAngle(x, y, cube.size));
            }
    return sum / std::numbers::pi;
}

}  // namespace janus::renderer
