// Accuracy vs. time of the GGX prefilter that updates an environment / reflection probe
// (`janus bench probes`, docs/BENCHMARKS.md "Reflection probes: accuracy vs time").
//
// One configuration = an equirect sky converted to an RGBA16F cube of `faceSize`^2 (full chain) on
// `path`, then GGX-prefiltered with given samples per mip. Per prefiltered mip (1..N-1, roughness
// m / (N - 1)) the GPU result is compared with the double-precision CPU reference (GgxReference,
// brute force over every texel of the converted cube's mip 0) on a deterministic subset of output
// texels: per face, a regular grid of at most `gridPerFace`^2 texels, x = floor((i + 0.5) * size /
// grid), every texel when the mip is at most grid^2. The reference is computed once per
// ProbeAccuracyBench and reused for every sample count.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "janus/renderer/image.h"
#include "janus/renderer/settings.h"
#include "janus/rhi/rhi.h"

namespace janus::renderer {

// Largest samples per mip the prefilter takes (its sample block is 16 KiB, the minimum uniform
// block size of GLES 3.0 / GL / Vulkan).
inline constexpr uint32_t kMaxProbeSamplesPerMip = 1024;
// The prefilter's bright-texel split (docs/IBL.md, "Bright texels"): the list capacity the sky's
// prefilter uses (the bench's default) and the most it takes; 0 = off.
inline constexpr uint32_t kDefaultProbeBrightTexels = 64;
inline constexpr uint32_t kMaxProbeBrightTexels = 1023;
// The prefilter's default samples per mip (mips 1, 2, ...; the last entry repeats): 21, 34, 55, 89, 89, 89.
const std::vector<uint32_t>& defaultProbeSamplesPerMip();

struct ProbeMipError {
    uint32_t mip = 0;
    float roughness = 0.0f;            // perceptual
    uint32_t samplesRequested = 0;     // Hammersley points
    uint32_t samplesUsed = 0;          // those above the horizon
    uint32_t texelsCompared = 0;       // over the six faces
    double rmse = 0.0;                 // relative RMSE: RMS |gpu - ref| / mean |ref| (RGB vector lengths)
    double maxRel = 0.0;               // max over compared texels of |gpu - ref| / |ref|
};

struct ProbeMeasurement {
    std::vector<ProbeMipError> mips;   // mips 1..N-1
    double gpuMs = 0.0;                // median over runs of the prefilter pass's GPU time (CPU ms without timers)
    std::vector<double> gpuMsRuns;
    bool gpuTimed = true;              // false: the device has no timers, the times are CPU recording ms
    uint32_t brightTexels = 0;         // the split's list capacity (0: off)
    uint32_t brightFound = 0;          // bright texels the split found in the source
    bool brightOverflow = false;       // more than the capacity: that update ran without the split
};

// The default synthetic sky, equirect `width` x `height`: a smooth gradient 0.2 + 0.3 (0.5 + 0.5 d)
// per channel plus a soft bright lobe (4, 3, 2) max(0, d.s)^8 around s = normalize(0.4, 0.7, -0.6)
// (the sky of the GGX accuracy tests, docs/IBL.md).
ImageRGBAF syntheticProbeSky(uint32_t width = 512, uint32_t height = 256);

// Why `path` cannot run the prefilter on `device` (a missing capability), or nullopt.
std::optional<std::string> probeBenchUnsupported(const rhi::IDevice& device, FeaturePath path);

class ProbeAccuracyBench {
public:
    // Converts `environment` (equirect, linear radiance) to the cube, reads its mip 0 back and
    // evaluates the reference. Throws RendererError for an empty sky, a face size of 0 or above the
    // device's cube limit, or a path the device cannot run.
    ProbeAccuracyBench(rhi::IDevice& device, const ImageRGBAF& environment, uint32_t faceSize, FeaturePath path,
                       uint32_t gridPerFace = 8);
    ~ProbeAccuracyBench();
    ProbeAccuracyBench(const ProbeAccuracyBench&) = delete;
    ProbeAccuracyBench& operator=(const ProbeAccuracyBench&) = delete;

    // Prefilters `warmup` + `runs` times with `samplesPerMip` (mip 1, 2, ...; the last entry repeats;
    // each 1..kMaxProbeSamplesPerMip, else RendererError) and `brightTexels` (the split's capacity,
    // 0..kMaxProbeBrightTexels; 0 = off) and measures the last result.
    ProbeMeasurement measure(const std::vector<uint32_t>& samplesPerMip, uint32_t runs = 5, uint32_t warmup = 1,
                             uint32_t brightTexels = kDefaultProbeBrightTexels);

    uint32_t faceSize() const;
    uint32_t mipCount() const;             // of the prefiltered cube (full chain)
    double referenceCpuMs() const;         // wall time spent evaluating the reference

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

// One measurement without keeping the reference: ProbeAccuracyBench(...).measure(...).
ProbeMeasurement measureProbePrefilter(rhi::IDevice& device, const ImageRGBAF& environment, uint32_t faceSize, FeaturePath path,
                                       const std::vector<uint32_t>& samplesPerMip, uint32_t runs = 5,
                                       uint32_t brightTexels = kDefaultProbeBrightTexels);

}  // namespace janus::renderer
