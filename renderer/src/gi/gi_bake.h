// The GI bake (internal to the renderer; docs/GI.md, "Bake"): what a relight needs, made once per
// scene.
//
//   1. Each probe of the volume's grid renders a G-buffer cube (gi_gbuffer.frag: albedo and
//      distance, normal and facing, emission, the triangle's plane) with the scene's meshes, no
//      face culling.
//   2. `surfelsPerProbe` stratified directions (a spherical Fibonacci set) read it: each becomes a
//      sample — a surfel on a front face, a back-face hit (the probe is inside something), or sky.
//   3. buildGiBake groups the surfels into bricks (cells of `brickSize` metres x the six axis
//      directions of the normal x rendering layers, each lit from at most maxSurfelsPerBrick of its surfels; or one
//      brick per surfel on the per-surfel path), groups sky samples into direction bins (a brick
//      per bin, lit by the sky along the bin's mean direction; per-surfel: a brick per sample),
//      and keeps per
//      (probe, brick) the SH9 transfer T_k = sum over the probe's samples in the brick of
//      Y_k(direction) * 4 pi / N. Probe SH = sum over its bricks of radiance(brick) * T.
//   4. A probe with more than `invalidBackFaceFraction` of its samples on back faces is inside
//      something. With `relocateProbes` it moves out through the nearest inside face (at most 45 %
//      of a cell from its grid position) and steps 1-2 run again there, up to three times; it
//      keeps the first position where it is valid, else its grid position, and is invalid.
// Steps 3-4 are CPU functions of the samples, so tests can feed them analytic surfels.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "core/gpu_scene.h"
#include "janus/renderer/scene.h"

namespace janus::renderer {

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
};

// Sky samples' direction bins on the brick path: texels of a cube this many texels wide.
inline constexpr uint32_t kGiSkyBinsPerFace = 8;

// Probe i of the grid sits at the centre of cell i of `bounds` split into probeCounts cells.
std::vector<glm::vec3> giProbePositions(const IrradianceVolume& volume);
glm::vec3 giProbeSpacing(const IrradianceVolume& volume);
// N unit directions, evenly spread over the sphere (spherical Fibonacci).
std::vector<glm::vec3> giSampleDirections(uint32_t count);

// Steps 3-4 above. `samples[p]` are probe p's samples (all of the same count), taken at
// `positions[p]` (empty: the grid positions).
GiBake buildGiBake(const IrradianceVolume& volume, const std::vector<std::vector<GiSample>>& samples,
                   const std::vector<glm::vec3>& positions = {});

// Where a probe at `position` whose samples are `samples` moves to get out of what it is inside:
// through the nearest back face it sees, a tenth of the smallest spacing beyond it, the offset
// from `gridPosition` clamped to 45 % of `spacing` per axis. nullopt when the probe is not inside
// anything (back faces at most `invalidBackFaceFraction` of its samples).
std::optional<glm::vec3> giRelocatedPosition(const std::vector<GiSample>& samples, const glm::vec3& position, const glm::vec3& gridPosition,
                                             const glm::vec3& spacing, float invalidBackFaceFraction);

// Steps 1-2 on the GPU: renders every probe's G-buffer cube and reads the samples back.
// `faceSize` is the cube's face size (32 gives 6144 texels for up to 4096 directions). With
// timestamp queries, `report` gets the G-buffer draws' GPU time and their draw count.
std::vector<std::vector<GiSample>> captureGiSamples(rhi::IDevice& device, const GpuScene& gpuScene, const IrradianceVolume& volume,
                                                    const std::vector<glm::vec3>& positions, uint32_t faceSize = 32,
                                                    PassReport* report = nullptr);

// The whole bake: steps 1-4 with relocation (when the volume asks for it) on a 32^2 G-buffer.
GiBake bakeGiVolume(rhi::IDevice& device, const GpuScene& gpuScene, const IrradianceVolume& volume, PassReport* report = nullptr);

}  // namespace janus::renderer
