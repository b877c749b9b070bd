#include "ibl/spherical_harmonics.h"

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
