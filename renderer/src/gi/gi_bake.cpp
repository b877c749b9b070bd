// The GI bake (gi_bake.h, docs/GI.md "Bake").
#include "gi/gi_bake.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <numeric>
#include <optional>
#include <tuple>

#include <fmt/format.h>
#include <glm/gtc/packing.hpp>

#include "core/gpu_util.h"
#include "forward/frame_uniforms.h"
#include "ibl/cube_geometry.h"
#include "ibl/spherical_harmonics.h"
#include "janus/renderer/scene_view.h"
#include "janus/shaders/bindings.h"

namespace janus::renderer {

glm::vec3 giProbeSpacing(const IrradianceVolume& volume) {
    return glm::max(volume.bounds.size() / glm::vec3(volume.probeCounts), glm::vec3(1e-6f));
}

std::vector<glm::vec3> giProbePositions(const IrradianceVolume& volume) {
    const glm::vec3 cell = volume.bounds.size() / glm::vec3(volume.probeCounts);
    std::vector<glm::vec3> positions;
    positions.reserve(size_t(volume.probeCounts.x) * volume.probeCounts.y * volume.probeCounts.z);
    for (uint32_t z = 0; z < volume.probeCounts.z; ++z)
        for (uint32_t y = 0; y < volume.probeCounts.y; ++y)
            for (uint32_t x = 0; x < volume.probeCounts.x; ++x)
                positions.push_back(volume.bounds.min + (glm::vec3(x, y, z) + 0.5f) * cell);
    return positions;
}

std::vector<glm::vec3> giSampleDirections(uint32_t count) {
    // Spherical Fibonacci: equal-area bands in z, golden-angle turns in longitude.
    const double goldenAngle = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
    std::vector<glm::vec3> directions(count);
    for (uint32_t i = 0; i < count; ++i) {
        const double z = 1.0 - (2.0 * i + 1.0) / count;
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double phi = goldenAngle * i;
        directions[i] = glm::vec3(glm::normalize(glm::dvec3(r * std::cos(phi), r * std::sin(phi), z)));
    }
    return directions;
}

glm::vec2 giOctahedralEncode(const glm::vec3& n) {
    const glm::vec3 o = n / (std::abs(n.x) + std::abs(n.y) + std::abs(n.z));
    if (o.z >= 0.0f) return glm::vec2(o.x, o.y);
    auto signNotZero = [](float v) { return v >= 0.0f ? 1.0f : -1.0f; };
    return glm::vec2((1.0f - std::abs(o.y)) * signNotZero(o.x), (1.0f - std::abs(o.x)) * signNotZero(o.y));
}

glm::vec3 giOctahedralDecode(const glm::vec2& e) {
    glm::vec3 n(e.x, e.y, 1.0f - std::abs(e.x) - std::abs(e.y));
    if (n.z < 0.0f) {
        const glm::vec2 folded = (1.0f - glm::abs(glm::vec2(n.y, n.x))) * glm::vec2(n.x >= 0.0f ? 1.0f : -1.0f, n.y >= 0.0f ? 1.0f : -1.0f);
        n.x = folded.x, n.y = folded.y;
    }
    return glm::normalize(n);
}

GiDistanceMomentFilter::GiDistanceMomentFilter(uint32_t faceSize, uint32_t resolution) : m_faceSize(faceSize), m_resolution(resolution) {
    // DDGI's sharpness for distances: a lobe about 10 degrees wide at half its height. Taps below
    // 1e-3 of the peak (beyond about 30 degrees) are dropped.
    constexpr double kExponent = 50.0;
    const double minCosine = std::pow(1e-3, 1.0 / kExponent);
    const size_t faceTexels = size_t(faceSize) * faceSize;
    std::vector<glm::dvec3> directions(6 * faceTexels);
    std::vector<double> solidAngles(faceTexels);
    for (uint32_t face = 0; face < 6; ++face)
        for (uint32_t y = 0; y < faceSize; ++y)
            for (uint32_t x = 0; x < faceSize; ++x) directions[face * faceTexels + y * faceSize + x] = cubeTexelDirection(face, x, y, faceSize);
    for (uint32_t y = 0; y < faceSize; ++y)
        for (uint32_t x = 0; x < faceSize; ++x) solidAngles[y * faceSize + x] = cubeTexelSolidAngle(x, y, faceSize);
    m_firstTap.reserve(size_t(resolution) * resolution + 1);
    for (uint32_t y = 0; y < resolution; ++y)
        for (uint32_t x = 0; x < resolution; ++x) {
            const glm::vec2 point = (glm::vec2(x, y) + 0.5f) / float(resolution) * 2.0f - 1.0f;
            const glm::dvec3 axis(giOctahedralDecode(point));
            m_firstTap.push_back(uint32_t(m_taps.size()));
            double sum = 0.0;
            const size_t first = m_taps.size();
            for (size_t t = 0; t < directions.size(); ++t) {
                const double c = glm::dot(axis, directions[t]);
                if (c < minCosine) continue;
                const double weight = std::pow(c, kExponent) * solidAngles[t % faceTexels];
                m_taps.push_back(Tap{uint32_t(t), float(weight)});
                sum += weight;
            }
            for (size_t i = first; i < m_taps.size(); ++i) m_taps[i].weight = float(m_taps[i].weight / sum);
        }
    m_firstTap.push_back(uint32_t(m_taps.size()));
}

std::vector<glm::vec2> GiDistanceMomentFilter::moments(const std::vector<float>& distances) const {
    if (distances.size() != size_t(6) * m_faceSize * m_faceSize)
        throw RendererError(fmt::format("GI distance moments: {} distances for a cube of 6 x {}^2 texels", distances.size(), m_faceSize));
    std::vector<glm::vec2> result(size_t(m_resolution) * m_resolution);
    for (size_t texel = 0; texel < result.size(); ++texel) {
        double mean = 0.0, meanSquare = 0.0;
        for (uint32_t i = m_firstTap[texel]; i < m_firstTap[texel + 1]; ++i) {
            const double d = distances[m_taps[i].texel];
            mean += m_taps[i].weight * d;
            meanSquare += m_taps[i].weight * d * d;
        }
        result[texel] = glm::vec2(float(mean), float(meanSquare));
    }
    return result;
}

namespace {

// The brick a surfel belongs to: its cell and the axis direction closest to its normal (so a
// thin wall's two sides, and a corner's two walls, are different bricks), and its rendering
// layers (a brick's surfels are lit by the same lights).
using BrickKey = std::tuple<int64_t, int64_t, int64_t, int, uint32_t>;

BrickKey brickKey(const IrradianceVolume& volume, const GiSample& s) {
    const glm::dvec3 cell = glm::floor((glm::dvec3(s.position) - glm::dvec3(volume.bounds.min)) / double(volume.brickSize));
    const glm::vec3 a = glm::abs(s.normal);
    const int axis = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
    const int direction = axis * 2 + (s.normal[axis] < 0.0f ? 1 : 0);
    auto clampCell = [](double c) { return int64_t(std::clamp(c, -1e15, 1e15)); };
    return {clampCell(cell.x), clampCell(cell.y), clampCell(cell.z), direction, s.renderingLayers};
}

void addTransfer(std::array<double, 9>& sum, const glm::vec3& direction, double weight) {
    const std::array<double, 9> y = shBasis(glm::dvec3(direction));
    for (size_t k = 0; k < 9; ++k) sum[k] += y[k] * weight;
}

}  // namespace

uint32_t giBrickSlot(uint32_t rank) {
    // Bands of four 1024-texel rows; in a band, 4 x 4 blocks left to right; in a block, row by row.
    const uint32_t band = rank / (4 * kGiBrickRowTexels), block = (rank / 16) % (kGiBrickRowTexels / 4), inBlock = rank % 16;
    const uint32_t x = block * 4 + inBlock % 4, y = band * 4 + inBlock / 4;
    return y * kGiBrickRowTexels + x;
}

GiBake buildGiBake(const IrradianceVolume& volume, const std::vector<std::vector<GiSample>>& samples, const std::vector<glm::vec3>& positions) {
    GiBake bake;
    bake.probeCounts = volume.probeCounts;
    bake.probePositions = positions.empty() ? giProbePositions(volume) : positions;
    const size_t gridProbes = size_t(volume.probeCounts.x) * volume.probeCounts.y * volume.probeCounts.z;
    if (samples.size() != gridProbes || bake.probePositions.size() != gridProbes)
        throw RendererError(fmt::format("GI bake: {} probes' samples for a {}x{}x{} volume", samples.size(), volume.probeCounts.x,
                                        volume.probeCounts.y, volume.probeCounts.z));
    bake.samplesPerProbe = samples.empty() ? 0 : uint32_t(samples[0].size());

    // Surface bricks (every probe's surfels in a brick share its radiance), then one brick per
    // sky sample. Surfels are kept in brick order.
    std::map<BrickKey, uint32_t> brickOf;
    // With bricks, sky samples share a brick per direction bin (a texel of an 8^2 cube: 384 bins,
    // about 11 degrees across), lit by the sky along the mean of its samples' directions; the
    // per-surfel path keeps one brick per sky sample.
    std::map<std::tuple<uint32_t, uint32_t, uint32_t>, uint32_t> skyBinOf;
    std::vector<glm::dvec3> skyDirectionSums;   // per brick (sky bins only)
    std::vector<std::vector<GiSurfel>> brickSurfels;
    struct Pending {
        uint32_t brick;
        glm::vec3 direction;
    };
    std::vector<std::vector<Pending>> probeHits(samples.size());
    bake.backFaceFraction.assign(samples.size(), 0.0f);
    bake.valid.assign(samples.size(), true);
    for (size_t p = 0; p < samples.size(); ++p) {
        uint32_t backFaces = 0;
        for (const GiSample& s : samples[p]) {
            if (s.kind == GiSample::Kind::BackFace) {
                ++backFaces;   // the inside of something: it sends the probe no light
                continue;
            }
            uint32_t brick;
            if (s.kind == GiSample::Kind::Sky) {
                const CubeTexel bin = cubeTexelOf(glm::dvec3(s.direction), kGiSkyBinsPerFace);
                auto it = volume.bricks ? skyBinOf.find({bin.face, bin.x, bin.y}) : skyBinOf.end();
                if (it == skyBinOf.end()) {
                    brick = uint32_t(brickSurfels.size());
                    brickSurfels.emplace_back();
                    bake.bricks.push_back(GiBrick{0, 0, true, s.direction});
                    if (volume.bricks) skyBinOf.emplace(std::make_tuple(bin.face, bin.x, bin.y), brick);
                } else {
                    brick = it->second;
                }
                skyDirectionSums.resize(bake.bricks.size(), glm::dvec3(0.0));
                skyDirectionSums[brick] += glm::dvec3(s.direction);
            } else {
                auto it = volume.bricks ? brickOf.find(brickKey(volume, s)) : brickOf.end();
                if (it == brickOf.end()) {
                    brick = uint32_t(brickSurfels.size());
                    brickSurfels.emplace_back();
                    bake.bricks.push_back(GiBrick{});
                    if (volume.bricks) brickOf.emplace(brickKey(volume, s), brick);
                } else {
                    brick = it->second;
                }
                brickSurfels[brick].push_back(GiSurfel{s.position, s.normal, s.albedo, s.emission,
                                                        s.faceNormal == glm::vec3(0.0f) ? s.normal : s.faceNormal, s.renderingLayers});
            }
            probeHits[p].push_back(Pending{brick, s.direction});
        }
        const size_t count = samples[p].size();
        bake.backFaceFraction[p] = count ? float(backFaces) / float(count) : 0.0f;
        bake.valid[p] = count > 0 && bake.backFaceFraction[p] <= volume.invalidBackFaceFraction;
    }
    skyDirectionSums.resize(bake.bricks.size(), glm::dvec3(0.0));
    const uint32_t keepAtMost = std::max(1u, volume.maxSurfelsPerBrick);
    auto keptSurfels = [&](size_t b) { return std::min<size_t>(brickSurfels[b].size(), keepAtMost); };
    // The relight lights bricks side by side (a SIMD group of compute invocations, a block of
    // fragments), and a group runs as long as its longest brick: bricks are placed by how many
    // surfels they keep, so neighbours loop alike (giBrickSlot).
    std::vector<uint32_t> byCount(bake.bricks.size());
    std::iota(byCount.begin(), byCount.end(), 0u);
    std::stable_sort(byCount.begin(), byCount.end(), [&](uint32_t a, uint32_t b) { return keptSurfels(a) > keptSurfels(b); });
    std::vector<uint32_t> slotOf(bake.bricks.size());
    uint32_t slots = 0;
    for (uint32_t rank = 0; rank < byCount.size(); ++rank) {
        slotOf[byCount[rank]] = giBrickSlot(rank);
        slots = std::max(slots, slotOf[byCount[rank]] + 1);
    }
    std::vector<GiBrick> placed(slots);   // slots no brick takes: no surfel, no transfer, no light
    for (uint32_t rank = 0; rank < byCount.size(); ++rank) {
        const uint32_t b = byCount[rank];
        GiBrick brick = bake.bricks[b];
        if (brick.sky && glm::length(skyDirectionSums[b]) > 1e-12) brick.skyDirection = glm::vec3(glm::normalize(skyDirectionSums[b]));
        // A brick seen by many probes holds many surfels: its radiance is the mean over at most
        // maxSurfelsPerBrick of them, spread evenly over the list (which is in probe order).
        const std::vector<GiSurfel>& all = brickSurfels[b];
        const size_t keep = keptSurfels(b);
        brick.firstSurfel = uint32_t(bake.surfels.size());
        brick.surfelCount = uint32_t(keep);
        for (size_t i = 0; i < keep; ++i) bake.surfels.push_back(all[(2 * i + 1) * all.size() / (2 * keep)]);
        placed[slotOf[b]] = brick;
    }
    bake.bricks = std::move(placed);
    for (std::vector<Pending>& hits : probeHits)
        for (Pending& hit : hits) hit.brick = slotOf[hit.brick];

    // Transfers: per probe, per brick it sees, the sum of its samples' SH weights.
    bake.probeFirstTransfer.resize(samples.size());
    bake.probeTransferCount.resize(samples.size());
    for (size_t p = 0; p < samples.size(); ++p) {
        const double weight = 4.0 * 3.14159265358979323846 / double(std::max<size_t>(samples[p].size(), 1));
        std::map<uint32_t, std::array<double, 9>> sums;
        for (const Pending& hit : probeHits[p]) addTransfer(sums[hit.brick], hit.direction, weight);
        bake.probeFirstTransfer[p] = uint32_t(bake.transfers.size());
        bake.probeTransferCount[p] = uint32_t(sums.size());
        for (const auto& [brick, sum] : sums) {
            GiTransfer transfer;
            transfer.brick = brick;
            for (size_t k = 0; k < 9; ++k) transfer.sh[k] = float(sum[k]);
            bake.transfers.push_back(transfer);
        }
    }
    return bake;
}

std::optional<glm::vec3> giRelocatedPosition(const std::vector<GiSample>& samples, const glm::vec3& position, const glm::vec3& gridPosition,
                                             const glm::vec3& spacing, float invalidBackFaceFraction) {
    size_t backFaces = 0;
    const GiSample* nearest = nullptr;
    float nearestDistance = 0.0f;
    for (const GiSample& s : samples) {
        if (s.kind != GiSample::Kind::BackFace) continue;
        ++backFaces;
        const float distance = glm::distance(s.position, position);
        if (!nearest || distance < nearestDistance) nearest = &s, nearestDistance = distance;
    }
    if (samples.empty() || float(backFaces) / float(samples.size()) <= invalidBackFaceFraction) return std::nullopt;
    const float margin = 0.1f * std::min({spacing.x, spacing.y, spacing.z});
    const glm::vec3 moved = position + nearest->direction * (nearestDistance + margin);
    return gridPosition + glm::clamp(moved - gridPosition, -0.45f * spacing, 0.45f * spacing);
}

GiBake bakeGiVolume(rhi::IDevice& device, const GpuScene& gpuScene, const IrradianceVolume& volume, PassReport* report) {
    std::vector<glm::vec3> positions = giProbePositions(volume);
    std::vector<std::vector<glm::vec2>> moments;
    std::vector<std::vector<GiSample>> samples = captureGiSamples(device, gpuScene, volume, positions, 32, report, &moments);
    if (volume.relocateProbes) {
        const std::vector<glm::vec3> grid = positions;
        const glm::vec3 spacing = giProbeSpacing(volume);
        // The probes inside something, and where each would go; a move that leaves it inside
        // moves again from there (a thick wall, a corner), three times at most.
        std::vector<size_t> inside;
        for (size_t p = 0; p < positions.size(); ++p) inside.push_back(p);
        for (int attempt = 0; attempt < 3; ++attempt) {
            std::vector<size_t> moving;
            std::vector<glm::vec3> targets;
            for (size_t p : inside)
                if (const std::optional<glm::vec3> target =
                        giRelocatedPosition(samples[p], positions[p], grid[p], spacing, volume.invalidBackFaceFraction);
                    target && *target != positions[p])
                    moving.push_back(p), targets.push_back(*target);
            if (moving.empty()) break;
            std::vector<std::vector<glm::vec2>> movedMoments;
            std::vector<std::vector<GiSample>> moved = captureGiSamples(device, gpuScene, volume, targets, 32, report, &movedMoments);
            for (size_t i = 0; i < moving.size(); ++i)
                positions[moving[i]] = targets[i], samples[moving[i]] = std::move(moved[i]), moments[moving[i]] = std::move(movedMoments[i]);
            inside = std::move(moving);
        }
        // A probe still inside goes back to its grid position and its samples there (invalid).
        std::vector<size_t> failed;
        for (size_t p = 0; p < positions.size(); ++p)
            if (positions[p] != grid[p] && giRelocatedPosition(samples[p], positions[p], grid[p], spacing, volume.invalidBackFaceFraction))
                failed.push_back(p);
        if (!failed.empty()) {
            std::vector<glm::vec3> back;
            for (size_t p : failed) back.push_back(grid[p]);
            std::vector<std::vector<glm::vec2>> originalMoments;
            std::vector<std::vector<GiSample>> original = captureGiSamples(device, gpuScene, volume, back, 32, report, &originalMoments);
            for (size_t i = 0; i < failed.size(); ++i)
                positions[failed[i]] = grid[failed[i]], samples[failed[i]] = std::move(original[i]), moments[failed[i]] = std::move(originalMoments[i]);
        }
    }
    GiBake bake = buildGiBake(volume, samples, positions);
    for (const std::vector<glm::vec2>& probe : moments) bake.distanceMoments.insert(bake.distanceMoments.end(), probe.begin(), probe.end());
    return bake;
}

std::vector<std::vector<GiSample>> captureGiSamples(rhi::IDevice& device, const GpuScene& gpuScene, const IrradianceVolume& volume,
                                                    const std::vector<glm::vec3>& positions, uint32_t faceSize, PassReport* report,
                                                    std::vector<std::vector<glm::vec2>>* distanceMoments) {
    constexpr rhi::Format kFormat = rhi::Format::RGBA16_FLOAT;
    constexpr size_t kTargets = 4;
    std::array<rhi::TextureHandle, kTargets> targets;
    const char* names[kTargets] = {"gi bake albedo+distance", "gi bake normal+facing", "gi bake emission", "gi bake face normal"};
    for (size_t i = 0; i < kTargets; ++i)
        targets[i] = device.createTexture(rhi::TextureDesc{}
                                              .setDimension(rhi::TextureDimension::TextureCube)
                                              .setFormat(kFormat)
                                              .setSize(faceSize, faceSize)
                                              .setUsage(rhi::TextureUsage::RenderTarget | rhi::TextureUsage::Sampled)
                                              .setDebugName(names[i]));
    const rhi::TextureHandle depth = device.createTexture(rhi::TextureDesc{}
                                                               .setFormat(rhi::Format::D32_FLOAT)
                                                               .setSize(faceSize, faceSize)
                                                               .setUsage(rhi::TextureUsage::RenderTarget)
                                                               .setDebugName("gi bake depth"));
    const rhi::ShaderHandle vertex = makeShader(device, rhi::ShaderStage::Vertex, "forward_vert");
    const rhi::ShaderHandle fragment = makeShader(device, rhi::ShaderStage::Fragment, "gi_gbuffer_frag");
    // Cube faces are mirrored views (scene_view.h): the pipelines' winding says so, so
    // gl_FrontFacing tells front from back.
    const GpuScene::MeshPipelines pipelines = gpuScene.createUnculledPipelines(
        vertex, fragment, rhi::DepthState{true, true, rhi::CompareOp::Less}, {kFormat, kFormat, kFormat, kFormat}, rhi::Format::D32_FLOAT, true,
        "gi bake g-buffer");
    const std::vector<glm::vec3> directions = giSampleDirections(volume.surfelsPerProbe);
    std::vector<CubeTexel> texels(directions.size());
    // The ray each texel's distance was measured along: its centre's, not the sample's direction,
    // which may be half a texel away (at grazing angles that puts the surfel centimetres off its
    // surface, half of them below it, where the shadow map shadows them).
    std::vector<glm::vec3> texelRays(directions.size());
    for (size_t i = 0; i < directions.size(); ++i) {
        texels[i] = cubeTexelOf(glm::dvec3(directions[i]), faceSize);
        texelRays[i] = glm::vec3(cubeTexelDirection(texels[i].face, texels[i].x, texels[i].y, faceSize));
    }

    // Rendering layers by instance index (the G-buffer gives each texel's instance).
    std::vector<uint32_t> instanceLayers;
    for (const std::vector<GpuScene::Draw>* draws : {&gpuScene.draws(), &gpuScene.blendedDraws()})
        for (const GpuScene::Draw& draw : *draws) {
            if (draw.instance >= instanceLayers.size()) instanceLayers.resize(size_t(draw.instance) + 1, ~0u);
            instanceLayers[draw.instance] = draw.renderingLayers;
        }

    std::optional<GiDistanceMomentFilter> momentFilter;
    if (distanceMoments) momentFilter.emplace(faceSize), distanceMoments->assign(positions.size(), {});
    std::vector<float> distances;

    const rhi::CommandListHandle cmd = device.createCommandList();
    std::vector<std::vector<GiSample>> result(positions.size());
    std::array<rhi::BufferHandle, 6> uniforms;
    for (uint32_t face = 0; face < 6; ++face)
        uniforms[face] = device.createBuffer(
            rhi::BufferDesc{}.setSize(sizeof(FrameUniforms)).setUsage(rhi::BufferUsage::Uniform).setDebugName("gi bake face"));
    std::array<rhi::BindingSetHandle, 6> bindings;
    for (uint32_t face = 0; face < 6; ++face)
        bindings[face] = device.createBindingSet(
            rhi::BindingSetDesc{}.add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_FRAME_UNIFORMS, uniforms[face])));
    const rhi::TimerQueryHandle timer = device.capabilities().timestampQueries ? device.createTimerQuery() : nullptr;

    // One probe's samples (and distance moments) from its faces as read back: target by target,
    // face by face, each face faceSize^2 RGBA16F texels, row 0 first.
    const uint64_t faceBytes = uint64_t(faceSize) * faceSize * 4 * sizeof(uint16_t);
    const uint64_t probeBytes = faceBytes * 6 * kTargets;
    auto unpackProbe = [&](size_t p, const std::byte* faces) {
        auto texel = [&](size_t target, uint32_t face, size_t index) {
            std::array<uint16_t, 4> h;
            std::memcpy(h.data(), faces + (target * 6 + face) * faceBytes + index * sizeof(h), sizeof(h));
            return glm::vec4(glm::unpackHalf1x16(h[0]), glm::unpackHalf1x16(h[1]), glm::unpackHalf1x16(h[2]), glm::unpackHalf1x16(h[3]));
        };
        auto texelAt = [&](size_t target, const CubeTexel& c) { return texel(target, c.face, size_t(c.y) * faceSize + c.x); };
        if (momentFilter) {
            // Every texel's distance (4th channel of target 0; negative where nothing was hit: the far plane).
            distances.resize(size_t(6) * faceSize * faceSize);
            for (uint32_t face = 0; face < 6; ++face)
                for (size_t t = 0; t < size_t(faceSize) * faceSize; ++t) {
                    const float d = texel(0, face, t).w;
                    distances[face * size_t(faceSize) * faceSize + t] = d >= 0.0f ? std::min(d, volume.farPlane) : volume.farPlane;
                }
            (*distanceMoments)[p] = momentFilter->moments(distances);
        }
        std::vector<GiSample>& out = result[p];
        out.resize(directions.size());
        for (size_t i = 0; i < directions.size(); ++i) {
            GiSample& s = out[i];
            s.direction = directions[i];
            const glm::vec4 albedoDistance = texelAt(0, texels[i]);
            if (!(albedoDistance.w >= 0.0f)) {
                s.kind = GiSample::Kind::Sky;
                continue;
            }
            const glm::vec4 normalFacing = texelAt(1, texels[i]);
            s.kind = normalFacing.w < 0.0f ? GiSample::Kind::BackFace : GiSample::Kind::Surface;
            s.position = positions[p] + texelRays[i] * albedoDistance.w;
            const glm::vec3 n(normalFacing);
            s.normal = glm::dot(n, n) > 1e-12f ? glm::normalize(n) : -directions[i];
            s.albedo = glm::clamp(glm::vec3(albedoDistance), glm::vec3(0.0f), glm::vec3(1.0f));
            const glm::vec4 emissionInstanceLow = texelAt(2, texels[i]);
            s.emission = glm::max(glm::vec3(emissionInstanceLow), glm::vec3(0.0f));
            const glm::vec4 faceInstanceHigh = texelAt(3, texels[i]);
            const glm::vec3 face(faceInstanceHigh);
            s.faceNormal = glm::dot(face, face) > 1e-12f ? glm::normalize(face) : s.normal;
            const double instance = double(faceInstanceHigh.w) * 2048.0 + double(emissionInstanceLow.w);
            s.renderingLayers = instance >= 0.0 && instance < double(instanceLayers.size()) ? instanceLayers[size_t(instance)] : ~0u;
        }
    };

    // Probes are rendered and copied out in batches, one submission and one readback a batch:
    // reading each face of each target on its own (24 a probe) waited for the device 24 times a
    // probe, which cost more than the rendering. The batch's buffer stays under 8 MiB (41 probes
    // at 32^2 faces).
    constexpr uint64_t kReadbackBytes = 8ull << 20;
    const size_t probesPerBatch = size_t(std::clamp<uint64_t>(kReadbackBytes / probeBytes, 1, std::max<size_t>(positions.size(), 1)));
    const rhi::BufferHandle readback =
        device.createBuffer(rhi::BufferDesc{}.setSize(probeBytes * probesPerBatch).setDebugName("gi bake readback"));
    for (size_t first = 0; first < positions.size(); first += probesPerBatch) {
        const size_t count = std::min(probesPerBatch, positions.size() - first);
        cmd->begin();
        if (timer) cmd->beginTimer(timer);
        for (size_t b = 0; b < count; ++b) {
            const glm::vec3 position = positions[first + b];
            const std::array<SceneView, 6> views = makeCubeFaceViews(position, faceSize, volume.nearPlane, volume.farPlane, "gi bake");
            for (uint32_t face = 0; face < 6; ++face) {
                FrameUniforms frame{};
                frame.viewProjection = views[face].viewProjection();
                frame.cameraPosition = glm::vec4(position, 1.0f);
                cmd->writeBuffer(uniforms[face], &frame, sizeof(frame));
                rhi::RenderPassDesc pass;
                pass.addColor(rhi::Attachment::clear(targets[0], {0.0f, 0.0f, 0.0f, -1.0f}, {0, face}))
                    .addColor(rhi::Attachment::clear(targets[1], {0.0f, 0.0f, 0.0f, 0.0f}, {0, face}))
                    .addColor(rhi::Attachment::clear(targets[2], {0.0f, 0.0f, 0.0f, 0.0f}, {0, face}))
                    .addColor(rhi::Attachment::clear(targets[3], {0.0f, 0.0f, 0.0f, 0.0f}, {0, face}))
                    .setDepth(rhi::Attachment::clearDepthTo(depth, 1.0f));
                cmd->beginRenderPass(pass);
                PassReport faceReport;
                gpuScene.drawMeshes(*cmd, views[face], pipelines, bindings[face], faceReport);
                if (report) report->draws += faceReport.draws;
                cmd->endRenderPass();
            }
            for (size_t t = 0; t < kTargets; ++t)
                for (uint32_t face = 0; face < 6; ++face)
                    cmd->copyTextureToBuffer(readback, b * probeBytes + (t * 6 + face) * faceBytes, targets[t], {0, face});
        }
        if (timer) cmd->endTimer(timer);
        cmd->end();
        device.execute(cmd);
        if (timer && report)
            if (const std::optional<double> seconds = device.timerSeconds(timer)) report->gpuMs = report->gpuMs.value_or(0.0) + *seconds * 1e3;
        const std::vector<std::byte> bytes = device.readBuffer(readback, 0, probeBytes * count);
        for (size_t b = 0; b < count; ++b) unpackProbe(first + b, bytes.data() + b * probeBytes);
    }
    return result;
}

}  // namespace janus::renderer
