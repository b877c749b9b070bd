// Cube-map geometry shared by the IBL modules and their CPU references (docs/IBL.md): texel
// directions and exact texel solid angles, in double precision. Faces +X, -X, +Y, -Y, +Z, -Z
// with the Vulkan/GL face table (docs/ARCHITECTURE.md, "Cube maps"); row 0 is t = 0.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

namespace janus::renderer {

// The (unnormalised) direction of a point of face `face` at face coordinates u, v in [-1, 1]
// (u = -1 at column 0's left edge, v = -1 at row 0's top edge): the inverse of the spec's
// major-axis table, so sampling a cube along it lands at (u, v) of that face. Mirrors
// ggx_common.glsl. Throws RendererError for a face outside 0..5.
glm::dvec3 cubeFacePointDirection(uint32_t face, double u, double v);
// The same at (s, t) = ((u + 1) / 2, (v + 1) / 2) in [0, 1]^2.
inline glm::dvec3 cubeDirection(uint32_t face, double s, double t) { return cubeFacePointDirection(face, 2.0 * s - 1.0, 2.0 * t - 1.0); }
// The unit direction through the centre of texel (x, y) of a face `size` texels wide.
glm::dvec3 cubeTexelDirection(uint32_t face, uint32_t x, uint32_t y, uint32_t size);
// The face and texel a cube lookup along `direction` (any length > 0) lands in: the spec's
// major-axis table (ties go to x, then y). The inverse of cubeTexelDirection at texel centres.
struct CubeTexel {
    uint32_t face = 0, x = 0, y = 0;
};
CubeTexel cubeTexelOf(const glm::dvec3& direction, uint32_t size);
// The exact solid angle of texel (x, y) of a face `size` texels wide (the same on every face;
// sums to 4 pi over the cube): the area-element integral atan2(uv, sqrt(u^2 + v^2 + 1)) taken at
// the texel's four corners.
double cubeTexelSolidAngle(uint32_t x, uint32_t y, uint32_t size);

}  // namespace janus::renderer
