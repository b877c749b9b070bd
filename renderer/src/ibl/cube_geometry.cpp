#include "ibl/cube_geometry.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "janus/renderer/settings.h"

namespace janus::renderer {
namespace {

double areaElement(double x, double y) { return std::atan2(x * y, std::sqrt(x * x + y * y + 1.0)); }

}  // namespace

glm::dvec3 cubeFacePointDirection(uint32_t face, double u, double v) {
    // Vulkan/GL major-axis table: +X (sc, tc) = (-z, -y), -X (z, -y), +Y (x, z), -Y (x, -z),
    // +Z (x, -y), -Z (-x, -y); s = (sc / |ma| + 1) / 2 = (u + 1) / 2, likewise t and v.
    switch (face) {
        case 0: return {1.0, -v, -u};
        case 1: return {-1.0, -v, u};
        case 2: return {u, 1.0, v};
        case 3: return {u, -1.0, -v};
        case 4: return {u, -v, 1.0};
        case 5: return {-u, -v, -1.0};
        default: throw RendererError(fmt::format("cube face {} does not exist (faces are 0..5)", face));
    }
}

glm::dvec3 cubeTexelDirection(uint32_t face, uint32_t x, uint32_t y, uint32_t size) {
    const double u = 2.0 * (x + 0.5) / size - 1.0;
    const double v = 2.0 * (y + 0.5) / size - 1.0;
    return glm::normalize(cubeFacePointDirection(face, u, v));
}

double cubeTexelSolidAngle(uint32_t x, uint32_t y, uint32_t size) {
    const double x0 = 2.0 * x / size - 1.0, x1 = 2.0 * (x + 1.0) / size - 1.0;
    const double y0 = 2.0 * y / size - 1.0, y1 = 2.0 * (y + 1.0) / size - 1.0;
    return areaElement(x0, y0) - areaElement(x0, y1) - areaElement(x1, y0) + areaElement(x1, y1);
}

CubeTexel cubeTexelOf(const glm::dvec3& d, uint32_t size) {
    const glm::dvec3 a = glm::abs(d);
    uint32_t face;
    double sc, tc, ma;
    if (a.x >= a.y && a.x >= a.z) {
        face = d.x >= 0.0 ? 0 : 1;
        ma = a.x, sc = d.x >= 0.0 ? -d.z : d.z, tc = -d.y;
    } else if (a.y >= a.z) {
        face = d.y >= 0.0 ? 2 : 3;
        ma = a.y, sc = d.x, tc = d.y >= 0.0 ? d.z : -d.z;
    } else {
        face = d.z >= 0.0 ? 4 : 5;
        ma = a.z, sc = d.z >= 0.0 ? d.x : -d.x, tc = -d.y;
    }
    auto texel = [&](double c) {
        const double s = 0.5 * (c / std::max(ma, 1e-300) + 1.0);
        return uint32_t(std::clamp(std::floor(s * size), 0.0, double(size - 1)));
    };
    return CubeTexel{face, texel(sc), texel(tc)};
}

}  // namespace janus::renderer
