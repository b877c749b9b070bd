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
#include "gi/gi_bake_data.h"
#include "janus/renderer/scene.h"

namespace janus::renderer {

// Sky samples' direction bins on the brick path: texels of a cube this many texels wide.
inline constexpr uint32_t kGiSkyBinsPerFace = 8;

// A unit vector as a point of the octahedron unfolded onto [-1, 1]^2, and back (both mirror
// gi_access.glsl / gi_relight_common.glsl).
glm::vec2 giOctahedralEncode(const glm::vec3& direction);
glm::vec3 giOctahedralDecode(const glm::vec2& point);

// Distance moments for visibility (DDGI, Majercik et al. 2019): texel t of an N x N octahedral map
// (centre direction giOctahedralDecode((t + 0.5) / N * 2 - 1)) gets the mean and mean square of
// the distances a cube of faceSize^2 texels measured, weighted by max(0, cos)^50 to t's direction
// and the cube texel's solid angle. Built once per cube size; `moments` is then cheap per probe.
class GiDistanceMomentFilter {
public:
    explicit GiDistanceMomentFilter(uint32_t faceSize, uint32_t resolution = kGiVisibilityResolution);
    // `distances`: 6 faces x faceSize^2 texels (row 0 first), each >= 0. Returns resolution^2
    // (mean, mean square) pairs, row by row.
    std::vector<glm::vec2> moments(const std::vector<float>& distances) const;

private:
    struct Tap {
        uint32_t texel;
        float weight;   // normalised per map texel
    };
    uint32_t m_faceSize, m_resolution;
    std::vector<uint32_t> m_firstTap;   // per map texel, then one past the last
    std::vector<Tap> m_taps;
};

// Probe i of the grid sits at the centre of cell i of `bounds` split into probeCounts cells.
std::vector<glm::vec3> giProbePositions(const IrradianceVolume& volume);
glm::vec3 giProbeSpacing(const IrradianceVolume& volume);
// N unit directions, evenly spread over the sphere (spherical Fibonacci).
std::vector<glm::vec3> giSampleDirections(uint32_t count);

// Where the brick of rank `rank` (bricks ranked by how many surfels they keep, most first) is
// stored: its index, and so its texel (index % 1024, index / 1024) of the relight's brick data.
// Ranks 16k .. 16k + 15 fill a 4 x 4 block of texels, blocks fill bands of four rows: bricks that
// are lit side by side (a fragment block, a SIMD group) loop over about as many surfels. Indices
// no rank takes hold empty bricks.
inline constexpr uint32_t kGiBrickRowTexels = 1024;   // gi_relight_common.glsl kGiDataWidth
uint32_t giBrickSlot(uint32_t rank);

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
// timestamp queries, `report` gets the G-buffer draws' GPU time and their draw count. With
// `distanceMoments`, each probe's GiDistanceMomentFilter map of its cube (a texel that sees nothing
// counts as the far plane).
std::vector<std::vector<GiSample>> captureGiSamples(rhi::IDevice& device, const GpuScene& gpuScene, const IrradianceVolume& volume,
                                                    const std::vector<glm::vec3>& positions, uint32_t faceSize = 32,
                                                    PassReport* report = nullptr,
                                                    std::vector<std::vector<glm::vec2>>* distanceMoments = nullptr);

// The whole bake: steps 1-4 with relocation (when the volume asks for it) on a 32^2 G-buffer, and
// every probe's distance moments from where it ends up.
GiBake bakeGiVolume(rhi::IDevice& device, const GpuScene& gpuScene, const IrradianceVolume& volume, PassReport* report = nullptr);

}  // namespace janus::renderer
