// `janus bench probes`: GGX prefilter accuracy against GgxReference vs. its GPU time
// (janus/renderer/ibl_bench.h).
#include "janus/renderer/ibl_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "core/parallel.h"
#include "ibl/cube_geometry.h"
#include "ibl/environment_map.h"
#include "ibl/ggx_prefilter.h"
#include "ibl/ggx_samples.h"

namespace janus::renderer {

static_assert(kMaxProbeSamplesPerMip == kMaxGgxSamples, "ibl_bench.h mirrors ggx_samples.h");
static_assert(kDefaultProbeBrightTexels == kDefaultGgxBrightTexels && kMaxProbeBrightTexels == kMaxGgxBrightTexels,
              "ibl_bench.h mirrors ggx_samples.h");

namespace {

struct ReferenceTexel {
    uint32_t face, x, y;
    glm::dvec3 value;
};

// Per face, at most grid^2 texels on a regular grid (every texel when size <= grid).
std::vector<ReferenceTexel> subsetTexels(uint32_t size, uint32_t grid) {
    std::vector<ReferenceTexel> texels;
    const uint32_t n = std::min(size, grid);
    for (uint32_t face = 0; face < 6; ++face)
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i)
                texels.push_back({face, uint32_t((i + 0.5) * size / n), uint32_t((j + 0.5) * size / n), glm::dvec3(0.0)});
    return texels;
}

double medianOf(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const size_t mid = values.size() / 2;
    return values.size() % 2 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
}

}  // namespace

const std::vector<uint32_t>& defaultProbeSamplesPerMip() { return defaultGgxSamplesPerMip(); }

ImageRGBAF syntheticProbeSky(uint32_t width, uint32_t height) {
    ImageRGBAF image;
    image.width = width;
    image.height = height;
    image.pixels.resize(size_t(width) * height * 4);
    const glm::dvec3 sun = glm::normalize(glm::dvec3(0.4, 0.7, -0.6));
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            const glm::dvec3 d = equirectDirection({(x + 0.5) / width, (y + 0.5) / height});
            const double lobe = std::pow(std::max(0.0, glm::dot(d, sun)), 8.0);
            const glm::dvec3 c = glm::dvec3(0.2) + 0.3 * (0.5 + 0.5 * d) + glm::dvec3(4.0, 3.0, 2.0) * lobe;
            float* p = image.pixels.data() + (size_t(y) * width + x) * 4;
            p[0] = float(c.x), p[1] = float(c.y), p[2] = float(c.z), p[3] = 1.0f;
        }
    return image;
}

std::optional<std::string> probeBenchUnsupported(const rhi::IDevice& device, FeaturePath path) {
    const rhi::Capabilities& caps = device.capabilities();
    if (path == FeaturePath::Compute && !caps.compute) return "no Capability::Compute";
    if (path == FeaturePath::Compute && !caps.storageImages) return "no Capability::StorageImages";
    if (path == FeaturePath::Fallback && !caps.renderToCubeFaceMip) return "no Capability::RenderToCubeFaceMip";
    return std::nullopt;
}

struct ProbeAccuracyBench::Impl {
    rhi::IDevice& device;
    FeaturePath path;
    std::unique_ptr<EnvironmentMap> environment;
    uint32_t faceSize = 0, mipCount = 0;
    std::vector<std::vector<ReferenceTexel>> reference;   // index = mip (0 empty)
    double referenceMs = 0.0;
    Impl(rhi::IDevice& d, FeaturePath p) : device(d), path(p) {}
};

ProbeAccuracyBench::ProbeAccuracyBench(rhi::IDevice& device, const ImageRGBAF& sky, uint32_t faceSize, FeaturePath path,
                                       uint32_t gridPerFace)
    : m_impl(std::make_unique<Impl>(device, path)) {
    if (std::optional<std::string> why = probeBenchUnsupported(device, path))
        throw RendererError(fmt::format("probe bench: the {} path cannot run here: {}", toString(path), *why));
    if (gridPerFace == 0) throw RendererError("probe bench: gridPerFace must be > 0");
    Impl& m = *m_impl;
    m.faceSize = faceSize;
    m.environment = std::make_unique<EnvironmentMap>(device, sky, faceSize, path);
    m.environment->convert();
    m.mipCount = m.environment->cube()->desc().mipLevels;
    const FloatCube source = readCube(device, m.environment->cube(), 0);

    const auto start = std::chrono::steady_clock::now();
    const GgxReference reference(source);
    // Every (mip, texel) the errors look at, evaluated on all cores (the reference is const).
    m.reference.assign(m.mipCount, {});
    std::vector<std::pair<uint32_t, size_t>> work;
    for (uint32_t mip = 1; mip < m.mipCount; ++mip) {
        m.reference[mip] = subsetTexels(std::max(1u, faceSize >> mip), gridPerFace);
        for (size_t i = 0; i < m.reference[mip].size(); ++i) work.emplace_back(mip, i);
    }
    parallelFor(work.size(), parallelThreads(0, work.size()), [&](size_t k) {
        const auto [mip, i] = work[k];
        ReferenceTexel& texel = m.reference[mip][i];
        const uint32_t size = std::max(1u, faceSize >> mip);
        texel.value = reference.radiance(cubeTexelDirection(texel.face, texel.x, texel.y, size), ggxRoughnessForMip(mip, m.mipCount));
    });
    m.referenceMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

ProbeAccuracyBench::~ProbeAccuracyBench() = default;

uint32_t ProbeAccuracyBench::faceSize() const { return m_impl->faceSize; }
uint32_t ProbeAccuracyBench::mipCount() const { return m_impl->mipCount; }
double ProbeAccuracyBench::referenceCpuMs() const { return m_impl->referenceMs; }

ProbeMeasurement ProbeAccuracyBench::measure(const std::vector<uint32_t>& samplesPerMip, uint32_t runs, uint32_t warmup,
                                             uint32_t brightTexels) {
    Impl& m = *m_impl;
    GgxPrefilterSettings settings;
    settings.samplesPerMip = samplesPerMip;   // the constructor checks 1..kMaxGgxSamples
    settings.brightTexels = brightTexels;     // and 0..kMaxGgxBrightTexels
    GgxPrefilter prefilter(m.device, m.path, settings);
    ProbeMeasurement result;
    runs = std::max(runs, 1u);
    for (uint32_t i = 0; i < warmup + runs; ++i) {
        const PassReport report = prefilter.run(m.environment->cube());
        if (i < warmup) continue;
        if (report.gpuMs) {
            result.gpuMsRuns.push_back(*report.gpuMs);
        } else {
            result.gpuTimed = false;
            result.gpuMsRuns.push_back(report.cpuMs);
        }
    }
    result.gpuMs = medianOf(result.gpuMsRuns);
    if (prefilter.brightSplit()) {
        const GgxBrightTexels bright = prefilter.readBrightTexels();
        result.brightTexels = brightTexels;
        result.brightFound = bright.found;
        result.brightOverflow = bright.overflow;
    }
    for (uint32_t mip = 1; mip < prefilter.mipCount(); ++mip) {
        const FloatCube got = readCube(m.device, prefilter.prefiltered(), mip);
        double squared = 0.0, magnitude = 0.0, maxRel = 0.0;
        for (const ReferenceTexel& texel : m.reference[mip]) {
            const glm::dvec3 error = got.texel(texel.face, texel.x, texel.y) - texel.value;
            squared += glm::dot(error, error);
            magnitude += glm::length(texel.value);
            const double len = glm::length(texel.value);
            maxRel = std::max(maxRel, len > 0.0 ? glm::length(error) / len : (glm::length(error) > 0.0 ? INFINITY : 0.0));
        }
        const double n = double(std::max<size_t>(m.reference[mip].size(), 1));
        ProbeMipError e;
        e.mip = mip;
        e.roughness = prefilter.roughnessForMip(mip);
        e.samplesRequested = prefilter.sampleSets()[mip].requested;
        e.samplesUsed = uint32_t(prefilter.sampleSets()[mip].samples.size());
        e.texelsCompared = uint32_t(m.reference[mip].size());
        e.rmse = magnitude > 0.0 ? std::sqrt(squared / n) / (magnitude / n) : std::sqrt(squared / n);
        e.maxRel = maxRel;
        result.mips.push_back(e);
    }
    return result;
}

ProbeMeasurement measureProbePrefilter(rhi::IDevice& device, const ImageRGBAF& environment, uint32_t faceSize, FeaturePath path,
                                       const std::vector<uint32_t>& samplesPerMip, uint32_t runs, uint32_t brightTexels) {
    return ProbeAccuracyBench(device, environment, faceSize, path).measure(samplesPerMip, runs, 1, brightTexels);
}

}  // namespace janus::renderer
