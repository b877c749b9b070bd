// What the GI bake makes (internal to the renderer; gi_bake.h makes it, gi_bake_file.h stores
// it, ProbeGi relights with it): plain data, no GPU type, so that the bake file's reader builds
// without the renderer's GPU half (the fuzz build, fuzz/CMakeLists.txt).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace janus::renderer {

// What a probe sees around each direction, for shading's visibility test (DDGI's Chebyshev test,
// gi_access.glsl): an N x N octahedral map (giOctahedralEncode) per probe.
inline constexpr uint32_t kGiVisibilityResolution = 16;

// One direction of one probe's G-buffer.
struct GiSample {
    enum class Kind : uint8_t { Surface, BackFace, Sky };
    Kind kind = Kind::Sky;
    glm::vec3 direction{0.0f, 0.0f, 1.0f};   // unit, from the probe
    glm::vec3 position{0.0f}, normal{0.0f, 0.0f, 1.0f}, albedo{0.0f}, emission{0.0f};   // surfaces
    // The plane of the triangle seen, on the probe's side (unit); 0: the shading normal's.
    glm::vec3 faceNormal{0.0f};
    uint32_t renderingLayers = ~0u;   // its instance's: the lights that light it (every one by default)
};

struct GiSurfel {
    glm::vec3 position{0.0f}, normal{0.0f, 0.0f, 1.0f}, albedo{0.0f}, emission{0.0f};
    // The relight counts no light from below this plane (a shading normal may lean away from it).
    glm::vec3 faceNormal{0.0f, 0.0f, 1.0f};
    uint32_t renderingLayers = ~0u;   // lit by the lights whose layers share a bit with these
};

struct GiBrick {
    uint32_t firstSurfel = 0, surfelCount = 0;
    bool sky = false;
    glm::vec3 skyDirection{0.0f};
    // False for the empty slots the bake's placement leaves (gi_bake.h giBrickSlot).
    bool holdsLight() const { return sky || surfelCount > 0; }
};

struct GiTransfer {
    uint32_t brick = 0;
    std::array<float, 9> sh{};
};

struct GiBake {
    glm::uvec3 probeCounts{1, 1, 1};
    std::vector<glm::vec3> probePositions;   // grid order: x + X (y + Y z)
    std::vector<float> backFaceFraction;     // per probe
    std::vector<bool> valid;                 // per probe
    std::vector<GiSurfel> surfels;           // grouped by brick
    std::vector<GiBrick> bricks;
    std::vector<GiTransfer> transfers;       // grouped by probe
    std::vector<uint32_t> probeFirstTransfer, probeTransferCount;
    uint32_t samplesPerProbe = 0;
    // Per probe (grid order) kGiVisibilityResolution^2 texels, row by row: the mean distance and
    // mean squared distance to what the probe sees about the texel's direction (GiDistanceMomentFilter).
    // Empty: no visibility (every probe counts wherever it is).
    std::vector<glm::vec2> distanceMoments;
};

}  // namespace janus::renderer
