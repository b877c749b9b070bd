// `janus bench msaa [SCENE]`: anti-aliasing's accuracy vs time (docs/LIGHTING.md, "Anti-aliasing").
// Per backend and path, the main view with 1, 2, 4, 8... samples per pixel (RenderSettings::
// msaaSamples) and supersampled (rendered at k times the size with one sample, box-filtered down),
// each against a reference supersampled at a larger scale: the error over every pixel and over the
// pixels the one-sample image aliases, how many of those stay wrong, the frame's time and the
// resolve's, and the memory the view's targets take. Where the scene has reflection probes, their
// captures too (Renderer::renderCubeCapture, as a probe update captures them; docs/PROBES.md,
// "Multisampled captures"): each face's error against a supersampled capture, and the capture's
// time. Writes msaa.md, msaa.json, msaa.png and msaa-error-<backend>-<path>.png (one sample beside
// the largest count measured).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <glm/gtc/packing.hpp>
#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "janus/renderer/renderer.h"
#include "plot.h"

namespace janus::cli {
namespace {

struct MsaaOptions {
    std::string scene;
    std::string samples = "1,2,4,8";
    std::string supersample = "2";
    uint32_t referenceScale = 4;
    BenchTargets targets{"compute,fallback", "vulkan,gl,gles"};
    std::string size = "256x256";
    uint32_t runs = 5;
    bool allowOutsidePaths = false;
    bool quick = false;
    bool samplesGiven = false, supersampleGiven = false;
};

constexpr uint32_t kMaxSamples = 16;          // RenderSettings::msaaSamples
constexpr uint32_t kMaxReferenceScale = 8;    // 64 samples a pixel: enough for any edge's coverage
// A pixel counts as wrong when a channel differs from the reference by more than two 8-bit steps
// of the error's scale (below).
constexpr double kWrongThreshold = 2.0 / 255.0;

// Per channel, x / (1 + x) of linear radiance: 0..1 like a display value, so a sky or an emitter
// of radiance 50 weighs no more than white at an edge, and a dark edge is not lost beside it. The
// renderer's own tonemap is not used: the metric must not change when its curve or exposure does.
double compressed(float x) { return std::isfinite(x) ? double(std::max(x, 0.0f)) / (1.0 + double(std::max(x, 0.0f))) : 2.0; }

// Per pixel, the largest channel's difference in compressed radiance (a non-finite channel: 1).
std::vector<double> pixelErrors(const renderer::ImageRGBAF& image, const renderer::ImageRGBAF& reference) {
    std::vector<double> errors(size_t(reference.width) * reference.height, 0.0);
    for (size_t p = 0; p < errors.size(); ++p)
        for (size_t c = 0; c < 3; ++c) {
            const double a = compressed(image.pixels[p * 4 + c]), b = compressed(reference.pixels[p * 4 + c]);
            errors[p] = std::max(errors[p], a > 1.0 ? 1.0 : std::abs(a - b));
        }
    return errors;
}

// `image` (scale x the size) box-filtered to width x height: each pixel the mean of its scale x
// scale pixels, a regular grid of that many samples.
renderer::ImageRGBAF boxFiltered(const renderer::ImageRGBAF& image, uint32_t scale) {
    renderer::ImageRGBAF out{image.width / scale, image.height / scale, {}};
    out.pixels.assign(size_t(out.width) * out.height * 4, 0.0f);
    const double weight = 1.0 / double(scale * scale);
    for (uint32_t y = 0; y < out.height; ++y)
        for (uint32_t x = 0; x < out.width; ++x)
            for (uint32_t c = 0; c < 4; ++c) {
                double sum = 0.0;
                for (uint32_t sy = 0; sy < scale; ++sy)
                    for (uint32_t sx = 0; sx < scale; ++sx)
                        sum += image.pixels[((size_t(y) * scale + sy) * image.width + size_t(x) * scale + sx) * 4 + c];
                out.pixels[(size_t(y) * out.width + x) * 4 + c] = float(sum * weight);
            }
    return out;
}

struct Error {
    double meanAll = 0.0;        // mean over every pixel
    double meanAliased = 0.0;    // mean over the pixels the one-sample image gets wrong
    uint64_t aliasedLeft = 0;    // of those, the ones still wrong
    double maxError = 0.0;
};

Error measure(const std::vector<double>& errors, const std::vector<uint8_t>& aliased) {
    Error result;
    double sumAliased = 0.0;
    uint64_t aliasedCount = 0;
    for (size_t p = 0; p < errors.size(); ++p) {
        result.meanAll += errors[p];
        result.maxError = std::max(result.maxError, errors[p]);
        if (!aliased[p]) continue;
        ++aliasedCount;
        sumAliased += errors[p];
        result.aliasedLeft += errors[p] > kWrongThreshold;
    }
    result.meanAll /= double(std::max<size_t>(errors.size(), 1));
    result.meanAliased = aliasedCount > 0 ? sumAliased / double(aliasedCount) : 0.0;
    return result;
}

// Msaa: RenderSettings::msaaSamples (alpha-masked materials with alpha to coverage, the default);
// MsaaCutOff: the same with alphaToCoverage off (measured where the scene has masked materials);
// Supersample: rendered larger with one sample, box-filtered.
enum class Method { Msaa, MsaaCutOff, Supersample };
bool multisampled(Method method) { return method != Method::Supersample; }

struct Row {
    std::string backend, path;
    Method method = Method::Msaa;
    uint32_t samples = 1;        // per pixel: the MSAA count, or scale^2
    uint32_t scale = 1;          // supersampling: rendered at scale x the size
    double frameMs = 0.0, forwardMs = 0.0, resolveMs = 0.0;   // medians over runs
    bool gpuTimed = true;
    uint64_t targetBytes = 0;    // the main view's colour (RGBA16F) and depth (D32F) at their samples, plus the resolved colour
    Error error;
};

std::string methodLabel(const Row& row) {
    if (row.method == Method::Supersample) return fmt::format("ssaa {}x{}", row.scale, row.scale);
    if (row.samples == 1) return "1 sample";
    return fmt::format("msaa {}{}", row.samples, row.method == Method::MsaaCutOff ? ", cut-off" : "");
}

struct Timing {
    double frameMs = 0.0, forwardMs = 0.0, resolveMs = 0.0;
    bool gpuTimed = true;
};

// Renders until reflection probes and the irradiance volume are settled (as `janus render`), then
// `runs` timed frames: the frame's passes summed, the main view's forward pass and msaa-resolve.
Timing timeFrames(renderer::Renderer& renderer, uint32_t runs) {
    renderer.renderFrame();   // first use: pipeline compiles, first uploads; not timed
    for (uint32_t frame = 0; (renderer.probesPending() || renderer.irradiancePending()) && frame < kMaxWarmUpFrames; ++frame)
        renderer.renderFrame();
    Timing timing;
    std::vector<double> frame, forward, resolve;
    for (uint32_t run = 0; run < runs; ++run) {
        const renderer::FrameReport report = renderer.renderFrame();
        double frameMs = 0.0, forwardMs = 0.0, resolveMs = 0.0;
        for (const renderer::PassReport& pass : report.passes) {
            if (!pass.gpuMs) timing.gpuTimed = false;
            const double ms = pass.gpuMs.value_or(pass.cpuMs);
            frameMs += ms;
            if (pass.name == "forward" && pass.view == "main") forwardMs += ms;
            if (pass.name == "msaa-resolve") resolveMs += ms;
        }
        frame.push_back(frameMs), forward.push_back(forwardMs), resolve.push_back(resolveMs);
    }
    timing.frameMs = median(frame), timing.forwardMs = median(forward), timing.resolveMs = median(resolve);
    return timing;
}

// ---- Reflection-probe captures ----

constexpr size_t kMaxCapturedProbes = 4;   // of the scene's, in its order: enough to see the trend, bounded time
// The largest reference face: 6 x 2048^2 texels are 400 MB as floats on the host, and 2048 is the
// least cube size any backend allows (GLES 3.0). Larger probes are skipped, saying so.
constexpr uint32_t kMaxReferenceFace = 2048;

struct CaptureRow {
    std::string backend, path, probe;
    uint32_t faceSize = 0;
    Method method = Method::Msaa;   // Msaa or Supersample
    uint32_t samples = 1, scale = 1;
    double captureMs = 0.0;         // median over runs
    bool gpuTimed = true;
    Error error;
};

struct Capture {
    double ms = 0.0;
    bool gpuTimed = true;
    renderer::ImageRGBAF faces;   // +X .. -Z stacked top to bottom, faceSize wide, box-filtered from scale x
};

// Captures `probe` as its updates do, at `scale` x its face size with `samples`: one capture not
// timed (first use), then `runs` timed (every pass of the capture summed); the faces of the last.
Capture captureProbe(rhi::IDevice& device, renderer::Renderer& renderer, const renderer::ReflectionProbe& probe, uint32_t samples,
                     uint32_t scale, uint32_t runs) {
    const uint32_t size = probe.resolution * scale;
    const rhi::TextureHandle cube = device.createTexture(rhi::TextureDesc{}
                                                             .setDimension(rhi::TextureDimension::TextureCube)
                                                             .setFormat(rhi::Format::RGBA16_FLOAT)
                                                             .setSize(size, size)
                                                             .setUsage(rhi::TextureUsage::RenderTarget | rhi::TextureUsage::Sampled)
                                                             .setDebugName(fmt::format("bench capture {}", probe.name)));
    renderer::CubeCaptureDesc desc = renderer::cubeCaptureOf(probe);
    desc.target = cube;
    desc.msaaSamples = samples;
    desc.viewPrefix = fmt::format("probe {}", probe.name);
    Capture capture;
    renderer.renderCubeCapture(desc);
    std::vector<double> times;
    for (uint32_t run = 0; run < runs; ++run) {
        double ms = 0.0;
        for (const renderer::PassReport& pass : renderer.renderCubeCapture(desc).passes) {
            if (!pass.gpuMs) capture.gpuTimed = false;
            ms += pass.gpuMs.value_or(pass.cpuMs);
        }
        times.push_back(ms);
    }
    capture.ms = median(times);
    renderer::ImageRGBAF faces{size, size * 6, {}};
    faces.pixels.reserve(size_t(size) * size * 6 * 4);
    for (uint32_t face = 0; face < 6; ++face) {
        const std::vector<std::byte> bytes = device.readTexture(cube, {0, face});
        for (size_t offset = 0; offset + 2 <= bytes.size(); offset += 2) {
            uint16_t half;
            std::memcpy(&half, bytes.data() + offset, 2);
            faces.pixels.push_back(glm::unpackHalf1x16(half));
        }
    }
    // Faces are stacked whole, so scale x scale blocks never straddle two of them.
    capture.faces = scale > 1 ? boxFiltered(faces, scale) : std::move(faces);
    return capture;
}

std::string captureMethodLabel(const CaptureRow& row) {
    if (row.method == Method::Supersample) return fmt::format("ssaa {}x{}", row.scale, row.scale);
    return row.samples == 1 ? "1 sample" : fmt::format("msaa {}", row.samples);
}

// Every probe (at most kMaxCapturedProbes) on one configuration: one sample, each count of
// `samples`, each supersampling scale, against the reference scale's capture. Counts the device
// lacks go to `skipped` with the renderer's reason.
void measureCaptures(rhi::IDevice& device, const renderer::Scene& scene, rhi::Backend backend, renderer::FeaturePath path,
                     const std::vector<uint32_t>& samples, const std::vector<uint32_t>& scales, uint32_t referenceScale, uint32_t runs,
                     std::vector<CaptureRow>& rows, std::vector<std::string>& skipped) {
    const std::string label = configurationLabel(backend, path);
    renderer::RenderSettings settings;
    settings.width = settings.height = 16;   // the main view is not rendered
    settings.path = path;
    renderer::Renderer renderer(device, scene, settings);
    const size_t probes = std::min(scene.reflectionProbes.size(), kMaxCapturedProbes);
    for (size_t index = 0; index < probes; ++index) {
        const renderer::ReflectionProbe& probe = scene.reflectionProbes[index];
        if (uint64_t(probe.resolution) * referenceScale > kMaxReferenceFace) {
            skipped.push_back(fmt::format("{} probe '{}': its {}x{} reference faces would exceed {}^2; give a smaller --reference-scale",
                                          label, probe.name, probe.resolution * referenceScale, probe.resolution * referenceScale,
                                          kMaxReferenceFace));
            continue;
        }
        const Capture reference = captureProbe(device, renderer, probe, 1, referenceScale, 1);
        std::vector<uint8_t> aliased;
        auto addRow = [&](Method method, uint32_t count, uint32_t scale) {
            std::optional<Capture> measured;
            try {
                measured = captureProbe(device, renderer, probe, count, scale, runs);
            } catch (const renderer::RendererError& e) {   // a count the device lacks: the message names it
                skipped.push_back(fmt::format("{} probe '{}': {}", label, probe.name, e.what()));
                return;
            }
            const std::vector<double> errors = pixelErrors(measured->faces, reference.faces);
            if (aliased.empty()) {   // the one-sample row, first
                aliased.resize(errors.size());
                for (size_t p = 0; p < errors.size(); ++p) aliased[p] = errors[p] > kWrongThreshold;
            }
            CaptureRow row{rhi::toString(backend), renderer::toString(path), probe.name, probe.resolution, method,
                           method == Method::Supersample ? scale * scale : count, scale};
            row.captureMs = measured->ms;
            row.gpuTimed = measured->gpuTimed && reference.gpuTimed;
            row.error = measure(errors, aliased);
            std::fprintf(stderr, "  %s probe '%s' %-9s capture %8.3f ms; error %6.2f %% (aliased texels %6.2f %%, %llu still wrong)\n",
                         label.c_str(), probe.name.c_str(), captureMethodLabel(row).c_str(), row.captureMs, 100.0 * row.error.meanAll,
                         100.0 * row.error.meanAliased, static_cast<unsigned long long>(row.error.aliasedLeft));
            rows.push_back(std::move(row));
        };
        addRow(Method::Msaa, 1, 1);
        for (uint32_t count : samples)
            if (count > 1) addRow(Method::Msaa, count, 1);
        for (uint32_t scale : scales) addRow(Method::Supersample, 1, scale);
    }
}

// Where the error is, the one-sample image (left) beside the largest count measured (right), two
// dark blue columns between: grey as the reference's brightness, red where a pixel is wrong,
// brighter the larger the error.
renderer::ImageRGBA8 errorPicture(const renderer::ImageRGBAF& reference, const std::vector<double>& left, const std::vector<double>& right) {
    const uint32_t w = reference.width, h = reference.height, gap = 2;
    renderer::ImageRGBA8 image{2 * w + gap, h, std::vector<uint8_t>(size_t(2 * w + gap) * h * 4, 255)};
    for (uint32_t y = 0; y < h; ++y) {
        for (uint32_t x = 0; x < gap; ++x) {
            uint8_t* out = &image.pixels[(size_t(y) * image.width + w + x) * 4];
            out[0] = 16, out[1] = 16, out[2] = 48;
        }
        for (uint32_t side = 0; side < 2; ++side)
            for (uint32_t x = 0; x < w; ++x) {
                const size_t p = size_t(y) * w + x;
                const float* in = &reference.pixels[p * 4];
                const double luminance = compressed(0.2126f * in[0] + 0.7152f * in[1] + 0.0722f * in[2]);
                const double grey = 16.0 + 90.0 * std::sqrt(std::min(1.0, luminance));   // dark scenes stay readable
                const double error = (side == 0 ? left : right)[p];
                // Every wrong pixel shows; full red from 0.05 (13 steps of 255) on.
                const double strength = error > kWrongThreshold ? 0.3 + 0.7 * std::min(1.0, error / 0.05) : 0.0;
                uint8_t* out = &image.pixels[(size_t(y) * image.width + side * (w + gap) + x) * 4];
                out[0] = uint8_t(std::lround(grey + (255.0 - grey) * strength));
                out[1] = out[2] = uint8_t(std::lround(grey * (1.0 - strength)));
            }
    }
    return image;
}

std::string percent(double value) { return fmt::format("{:.2f}", 100.0 * value); }
std::string mebibytes(uint64_t bytes) { return fmt::format("{:.2f}", double(bytes) / (1024.0 * 1024.0)); }

// The captures' table, what it says per configuration and probe, and their JSON ("captures",
// "captureSummary").
void appendCaptureReport(const std::vector<CaptureRow>& rows, uint32_t referenceScale, uint32_t runs, const char* unit, std::string& md,
                         nlohmann::json& json) {
    md += fmt::format(
        "\n## Reflection-probe captures\n\n"
        "Each reflection probe of the scene (the first {}) captured as its updates capture it (`Renderer::renderCubeCapture` "
        "at its position, planes and face size) with N samples per pixel (the probe's `msaa`, `--probe-msaa`; docs/PROBES.md, "
        "\"Multisampled captures\") or supersampled, against the same capture at {}x the face size with one sample, "
        "box-filtered. Error as above over the six faces' texels (mip 0: what mirror-like surfaces reflect); **aliased**: the "
        "texels the one-sample capture gets wrong. **capture**: every pass of one capture (six faces, the shadow map where "
        "the probe has shadows), {} (median of {} after one not timed).\n\n"
        "| backend | path | probe | face | method | samples | capture {} | error all % | error aliased % | still wrong |\n"
        "|---|---|---|---:|---|---:|---:|---:|---:|---:|\n",
        kMaxCapturedProbes, referenceScale, unit, runs, unit);
    json["captures"] = nlohmann::json::array();
    for (const CaptureRow& r : rows) {
        md += fmt::format("| {} | {} | {} | {} | {} | {} | {:.3f} | {} | {} | {} |\n", r.backend, r.path, r.probe, r.faceSize,
                          captureMethodLabel(r), r.samples, r.captureMs, percent(r.error.meanAll), percent(r.error.meanAliased),
                          r.error.aliasedLeft);
        json["captures"].push_back({{"backend", r.backend}, {"path", r.path}, {"probe", r.probe}, {"faceSize", r.faceSize},
                                    {"method", multisampled(r.method) ? "msaa" : "ssaa"}, {"samples", r.samples}, {"scale", r.scale},
                                    {"captureMs", r.captureMs}, {"gpuTimed", r.gpuTimed},
                                    {"error", {{"meanAll", r.error.meanAll}, {"meanAliased", r.error.meanAliased},
                                               {"aliasedLeft", r.error.aliasedLeft}, {"max", r.error.maxError}}}});
    }
    md += "\nWhat they say:\n\n";
    nlohmann::json summary = nlohmann::json::array();
    for (const CaptureRow& base : rows) {
        if (base.method != Method::Msaa || base.samples != 1) continue;
        std::vector<std::string> parts;
        for (const CaptureRow& r : rows) {
            if (r.backend != base.backend || r.path != base.path || r.probe != base.probe || &r == &base) continue;
            const double errorRatio = r.error.meanAliased / std::max(1e-12, base.error.meanAliased);
            const double timeRatio = r.captureMs / std::max(1e-9, base.captureMs);
            parts.push_back(fmt::format("{}: **{:.2f}x** the aliased texels' error for **{:.2f}x** the capture", captureMethodLabel(r),
                                        errorRatio, timeRatio));
            summary.push_back({{"backend", r.backend}, {"path", r.path}, {"probe", r.probe}, {"method", multisampled(r.method) ? "msaa" : "ssaa"},
                               {"samples", r.samples}, {"aliasedErrorRatio", errorRatio}, {"captureTimeRatio", timeRatio}});
        }
        md += fmt::format("- {}/{} probe '{}' ({}²): one sample: aliased texels' error {} % ({:.3f} {}). {}.\n", base.backend, base.path,
                          base.probe, base.faceSize, percent(base.error.meanAliased), base.captureMs, unit,
                          parts.empty() ? std::string("nothing else ran") : fmt::format("{}", fmt::join(parts, "; ")));
    }
    json["captureSummary"] = summary;
}

int runMsaa(const MsaaOptions& options) {
    const auto [paths, backends] = parseBenchTargets(options.targets, options.quick, "compute");
    std::vector<uint32_t> samples = parseCountList(options.quick && !options.samplesGiven ? "1,4" : options.samples, "--samples", 1, kMaxSamples, true);
    // The one-sample image is what the others are measured against (which pixels alias): always measured.
    if (samples.front() != 1) samples.insert(samples.begin(), 1);
    const uint32_t referenceScale = options.referenceScale;
    if (referenceScale < 2 || referenceScale > kMaxReferenceScale)
        throw UsageError(fmt::format("--reference-scale {} must be 2..{} (the reference's samples per pixel are its square)",
                                     referenceScale, kMaxReferenceScale));
    std::vector<uint32_t> scales;
    if (!(options.supersampleGiven && options.supersample.empty()) && options.supersample != "none") {
        scales = parseCountList(options.supersample, "--supersample", 2, kMaxReferenceScale, false);
        if (scales.back() >= referenceScale)
            throw UsageError(fmt::format("--supersample {} must stay below --reference-scale {}: supersampling at the reference's "
                                         "own scale is the reference",
                                         scales.back(), referenceScale));
    }
    if (options.runs < 1 || options.runs > 100) throw UsageError(fmt::format("--runs {} must be 1..100", options.runs));
    const ImageSize size = options.quick ? ImageSize{64, 64} : parseSize(options.size);
    const uint32_t runs = options.quick ? 1 : options.runs;
    const std::filesystem::path outDir = benchOutputDir(options.targets.out, "msaa");

    const std::optional<std::filesystem::path> scenePath =
        options.scene.empty() ? std::nullopt : std::optional<std::filesystem::path>(options.scene);
    const renderer::Scene scene = loadSceneOrDefault(scenePath, options.allowOutsidePaths);
    {
        std::vector<std::string> outputs{"msaa.md", "msaa.json", "msaa.png"};
        for (rhi::Backend backend : backends)
            for (renderer::FeaturePath path : paths) outputs.push_back(fmt::format("msaa-error-{}.png", configurationFileStem(backend, path)));
        checkFolderOutputs(outDir, "--out", outputs, sceneInputFiles(scenePath));
    }
    const auto maskedMaterials = std::count_if(scene.materials.begin(), scene.materials.end(),
                                               [](const renderer::Material& m) { return m.alphaMode == renderer::AlphaMode::Mask; });
    const uint64_t pixels = uint64_t(size.width) * size.height;
    auto targetBytes = [&](uint32_t sampleCount, uint32_t scale) {
        const uint64_t sampled = pixels * scale * scale * sampleCount * (8 + 4);
        return sampled + (sampleCount > 1 ? pixels * 8 : 0);
    };

    std::vector<Row> rows;
    std::vector<CaptureRow> captureRows;
    std::vector<std::string> skipped;
    nlohmann::json references = nlohmann::json::array();
    uint64_t aliasedPixels = 0;   // of the first configuration measured (they agree within parity)
    for (rhi::Backend backend : backends) {
        rhi::DeviceDesc desc;
        desc.setBackend(backend).setGLPlatform(parseGLPlatformOption(options.targets.glPlatform));
        std::unique_ptr<rhi::IDevice> device = rhi::createDevice(desc);
        for (renderer::FeaturePath path : paths) {
            const std::string label = configurationLabel(backend, path);
            if (path == renderer::FeaturePath::Compute && !device->capabilities().has(rhi::Capability::Compute)) {
                skipped.push_back(fmt::format("{}: no compute", label));
                continue;
            }
            // Renders at `scale` x the size with `sampleCount` samples; nullopt (and a skipped
            // entry) where the device cannot.
            auto render = [&](uint32_t sampleCount, uint32_t scale, const std::string& what, bool alphaToCoverage = true)
                -> std::optional<std::pair<Timing, renderer::ImageRGBAF>> {
                renderer::RenderSettings settings;
                settings.width = size.width * scale, settings.height = size.height * scale;
                settings.path = path;
                settings.msaaSamples = sampleCount;
                settings.alphaToCoverage = alphaToCoverage;
                std::optional<renderer::Renderer> frameRenderer;
                try {
                    frameRenderer.emplace(*device, scene, settings);
                } catch (const renderer::RendererError& e) {   // a count the device lacks, a size past its limit
                    // The renderer's refusal of a sample count names the count itself.
                    skipped.push_back(sampleCount > 1 ? fmt::format("{}: {}", label, e.what()) : fmt::format("{} {}: {}", label, what, e.what()));
                    return std::nullopt;
                }
                Timing timing = timeFrames(*frameRenderer, runs);
                renderer::ImageRGBAF hdr = frameRenderer->readHdrImage();
                return std::make_pair(timing, scale > 1 ? boxFiltered(hdr, scale) : std::move(hdr));
            };
            const auto reference = render(1, referenceScale, fmt::format("reference ({}x{} supersampled)", referenceScale, referenceScale));
            if (!reference) continue;
            references.push_back({{"backend", rhi::toString(backend)}, {"path", renderer::toString(path)}, {"scale", referenceScale},
                                  {"frameMs", reference->first.frameMs}});

            std::vector<uint8_t> aliased;
            std::vector<double> oneSampleErrors, largestErrors;
            auto addRow = [&](Method method, uint32_t sampleCount, uint32_t scale) {
                const std::string what = multisampled(method) ? fmt::format("msaa {}", sampleCount) : fmt::format("ssaa {}x{}", scale, scale);
                const auto measured = render(multisampled(method) ? sampleCount : 1, scale, what, method != Method::MsaaCutOff);
                if (!measured) return false;
                const std::vector<double> errors = pixelErrors(measured->second, reference->second);
                if (aliased.empty()) {   // the one-sample row, first
                    aliased.resize(errors.size());
                    for (size_t p = 0; p < errors.size(); ++p) aliased[p] = errors[p] > kWrongThreshold;
                    oneSampleErrors = errors;
                    if (aliasedPixels == 0) aliasedPixels = uint64_t(std::count(aliased.begin(), aliased.end(), uint8_t(1)));
                } else if (method == Method::Msaa) {
                    largestErrors = errors;
                }
                Row row{rhi::toString(backend), renderer::toString(path), method, multisampled(method) ? sampleCount : scale * scale, scale};
                row.frameMs = measured->first.frameMs, row.forwardMs = measured->first.forwardMs, row.resolveMs = measured->first.resolveMs;
                row.gpuTimed = measured->first.gpuTimed && reference->first.gpuTimed;
                row.targetBytes = targetBytes(multisampled(method) ? sampleCount : 1, scale);
                row.error = measure(errors, aliased);
                std::fprintf(stderr, "  %s %-9s frame %8.3f ms (forward %.3f, resolve %.3f); error %6.2f %% (aliased pixels %6.2f %%, %llu still wrong)\n",
                             label.c_str(), methodLabel(row).c_str(), row.frameMs, row.forwardMs, row.resolveMs, 100.0 * row.error.meanAll,
                             100.0 * row.error.meanAliased, static_cast<unsigned long long>(row.error.aliasedLeft));
                rows.push_back(std::move(row));
                return true;
            };
            // Without the one-sample image there is nothing to measure the others against.
            if (!addRow(Method::Msaa, 1, 1)) continue;
            for (uint32_t count : samples) {
                if (count == 1) continue;
                // What alpha to coverage buys at this count, where there are cut-outs for it to smooth.
                if (addRow(Method::Msaa, count, 1) && maskedMaterials > 0) addRow(Method::MsaaCutOff, count, 1);
            }
            for (uint32_t scale : scales) addRow(Method::Supersample, 1, scale);
            if (!scene.reflectionProbes.empty())
                measureCaptures(*device, scene, backend, path, samples, scales, referenceScale, runs, captureRows, skipped);
            renderer::writePNG(outDir / fmt::format("msaa-error-{}.png", configurationFileStem(backend, path)),
                               errorPicture(reference->second, oneSampleErrors, largestErrors.empty() ? oneSampleErrors : largestErrors));
        }
        reportDebugMessages(rhi::toString(backend), device->takeDebugMessages());
    }
    if (rows.empty()) throw UnavailableError(fmt::format("bench msaa: no configuration could run ({})", fmt::join(skipped, "; ")));

    // ---- Report ----
    const bool gpuTimed = std::all_of(rows.begin(), rows.end(), [](const Row& r) { return r.gpuTimed; });
    const char* unit = gpuTimed ? "GPU ms" : "ms";
    std::string md = fmt::format(
        "# Anti-aliasing: accuracy vs time\n\n"
        "Scene: {}. Image: {}x{}. Each row renders the main view and compares its HDR image with a reference: the same "
        "configuration at {}x the size with one sample, box-filtered ({} samples a pixel on a regular grid).\n\n"
        "- **msaa N**: `--msaa N`, shaded once per pixel, depth-tested per sample, averaged by `msaa-resolve` "
        "(docs/LIGHTING.md, \"Anti-aliasing\"), alpha-masked materials covering samples by alpha; **msaa N, cut-off**: the same "
        "with `--alpha-to-coverage off` (where the scene has alpha-masked materials: what alpha to coverage buys). **ssaa KxK**: "
        "rendered at K times the size with one sample and box-filtered on the CPU (not timed): shading too is sampled K^2 times.\n"
        "- **error**: per pixel the largest channel's |difference| in x/(1+x) of linear radiance (0..1, so one bright "
        "emitter cannot outweigh every edge). **all**: its mean over every pixel. **aliased**: its mean over the {} pixels "
        "the one-sample image gets wrong (> 2/255); **still wrong**: how many of those stay so.\n"
        "- **frame**: every pass of the frame, {} (median of {} frame(s) after the first and after probes settle); "
        "**resolve**: the `msaa-resolve` pass. **targets**: the main view's RGBA16F colour and D32F depth at their samples "
        "(and scale), plus the resolved colour.\n\n",
        sceneLabel(scenePath), size.width, size.height, referenceScale, referenceScale * referenceScale, aliasedPixels, unit, runs);
    nlohmann::json json = {{"scene", sceneLabel(scenePath)}, {"width", size.width}, {"height", size.height}, {"runs", runs},
                           {"gpuTimed", gpuTimed}, {"referenceScale", referenceScale}, {"wrongThreshold", kWrongThreshold},
                           {"aliasedPixels", aliasedPixels}, {"references", references},
                           {"configurations", nlohmann::json::array()}, {"skipped", skipped}};
    md += fmt::format("| backend | path | method | samples | frame {0} | forward {0} | resolve {0} | targets MiB | error all % | "
                      "error aliased % | still wrong |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
                      unit);
    std::vector<PlotSeries> series;
    for (const Row& r : rows) {
        md += fmt::format("| {} | {} | {} | {} | {:.3f} | {:.3f} | {} | {} | {} | {} | {} |\n", r.backend, r.path, methodLabel(r), r.samples,
                          r.frameMs, r.forwardMs, multisampled(r.method) && r.samples > 1 ? fmt::format("{:.3f}", r.resolveMs) : "-",
                          mebibytes(r.targetBytes), percent(r.error.meanAll), percent(r.error.meanAliased), r.error.aliasedLeft);
        nlohmann::json row = {{"backend", r.backend}, {"path", r.path}, {"method", multisampled(r.method) ? "msaa" : "ssaa"},
                              {"samples", r.samples}, {"scale", r.scale}, {"frameMs", r.frameMs}, {"forwardMs", r.forwardMs},
                              {"targetBytes", r.targetBytes},
                              {"error", {{"meanAll", r.error.meanAll}, {"meanAliased", r.error.meanAliased},
                                         {"aliasedLeft", r.error.aliasedLeft}, {"max", r.error.maxError}}}};
        if (multisampled(r.method) && r.samples > 1) {
            row["resolveMs"] = r.resolveMs;
            row["alphaToCoverage"] = r.method == Method::Msaa;
        }
        json["configurations"].push_back(row);
        // Plot: the aliased pixels' error against the frame's time; a line per configuration and
        // method, each starting at the one-sample row.
        if (!(r.frameMs > 0.0) || !(r.error.meanAliased > 0.0)) continue;
        const std::string name = fmt::format("{}/{}", r.backend, r.path);
        if (r.samples == 1) {
            seriesNamed(series, name + " msaa").points.push_back({r.frameMs, 100.0 * r.error.meanAliased});
            if (!scales.empty()) seriesNamed(series, name + " ssaa").points.push_back({r.frameMs, 100.0 * r.error.meanAliased});
            if (maskedMaterials > 0) seriesNamed(series, name + " msaa cut-off").points.push_back({r.frameMs, 100.0 * r.error.meanAliased});
        } else {
            const char* line = r.method == Method::Msaa ? " msaa" : r.method == Method::MsaaCutOff ? " msaa cut-off" : " ssaa";
            seriesNamed(series, name + line).points.push_back({r.frameMs, 100.0 * r.error.meanAliased});
        }
    }

    // What the sweep says, per configuration: what each method removes of the one-sample image's
    // edge error, and what it costs in frame time and memory.
    md += "\n## What it says\n\n";
    nlohmann::json summary = nlohmann::json::array();
    for (const Row& base : rows) {
        if (base.method != Method::Msaa || base.samples != 1) continue;
        std::vector<std::string> parts;
        for (const Row& r : rows) {
            if (r.backend != base.backend || r.path != base.path || &r == &base) continue;
            const double errorRatio = r.error.meanAliased / std::max(1e-12, base.error.meanAliased);
            const double timeRatio = r.frameMs / std::max(1e-9, base.frameMs);
            parts.push_back(fmt::format("{}: **{:.2f}x** the aliased pixels' error ({} still wrong of {}) for **{:.2f}x** the frame "
                                        "and {:.1f}x the targets' memory",
                                        methodLabel(r), errorRatio, r.error.aliasedLeft, base.error.aliasedLeft, timeRatio,
                                        double(r.targetBytes) / double(base.targetBytes)));
            summary.push_back({{"backend", r.backend}, {"path", r.path}, {"method", multisampled(r.method) ? "msaa" : "ssaa"},
                               {"alphaToCoverage", r.method != Method::MsaaCutOff},
                               {"samples", r.samples}, {"aliasedErrorRatio", errorRatio}, {"frameTimeRatio", timeRatio}});
        }
        md += fmt::format("- {}/{}: one sample: aliased pixels' error {} % ({:.3f} {}). {}.\n", base.backend, base.path,
                          percent(base.error.meanAliased), base.frameMs, unit, parts.empty() ? std::string("nothing else ran") : fmt::format("{}", fmt::join(parts, "; ")));
    }
    json["summary"] = summary;
    if (!captureRows.empty()) appendCaptureReport(captureRows, referenceScale, runs, unit, md, json);
    if (!skipped.empty()) {
        md += "\nSkipped:\n\n";
        for (const std::string& s : skipped) md += "- " + s + "\n";
    }
    md += fmt::format("\nPlot (msaa.png): the aliased pixels' mean error (%) vs the frame's {}, log-log, one line per configuration "
                      "and method from its one-sample point. Pictures: msaa-error-<backend>-<path>.png, one sample (left) beside the "
                      "largest sample count measured (right): red where a pixel is wrong, brighter the larger the error.\n",
                      unit);
    writeBenchOutputs(outDir, "msaa", md, json, drawLogXPlot(series, fmt::format("FRAME {}", gpuTimed ? "GPU MS" : "MS"), "ALIASED PIXELS ERROR (PERCENT)"));
    return 0;
}

}  // namespace

std::function<int()> addBenchMsaaCommand(CLI::App& bench) {
    auto options = std::make_shared<MsaaOptions>();
    CLI::App* msaa = bench.add_subcommand(
        "msaa", "Anti-aliasing: error against a supersampled reference vs the frame's time, per sample count (and supersampling); "
                "writes msaa.md, msaa.json, msaa.png and pictures to --out");
    addSceneArgument(*msaa, options->scene);
    msaa->add_option("--samples", options->samples, "Comma-separated samples per pixel (powers of two 1..16; 1 is always measured)")
        ->default_str(options->samples);
    msaa->add_option("--supersample", options->supersample,
                     "Comma-separated supersampling scales (2..7, below --reference-scale), or 'none'")
        ->default_str(options->supersample);
    msaa->add_option("--reference-scale", options->referenceScale, "The reference's scale: rendered at N times the size, box-filtered (2..8)")
        ->default_str("4");
    msaa->add_option("--size", options->size, "Image size WxH")->default_str(options->size);
    msaa->add_option("--runs", options->runs, "Frames timed per row (median)")->default_str("5");
    msaa->add_flag("--quick", options->quick,
                   "Tiny run for tests: 64x64, samples 1 and 4, ssaa 2x2, reference 4x4, 1 run, the compute path; options given win");
    addAllowOutsidePathsFlag(*msaa, options->allowOutsidePaths);
    addBenchTargetOptions(*msaa, options->targets);
    msaa->footer(kExitCodeHelp);
    return [options, msaa] {
        noteBenchTargetsGiven(*msaa, options->targets);
        options->samplesGiven = msaa->count("--samples") > 0;
        options->supersampleGiven = msaa->count("--supersample") > 0;
        return runMsaa(*options);
    };
}

}  // namespace janus::cli
