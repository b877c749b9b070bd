// `janus bench gi SCENE`: accuracy vs time of the probe GI (docs/GI.md, "Accuracy vs time").
// Sweeps one setting at a time around the scene's irradiance volume (surfels per probe with bricks
// and per-surfel, brick size, probe spacing, L1/L2, bounces, probes per frame, the SH reduction)
// on each path and backend. Per configuration: the bake's time, the relight's time (all its frames)
// and per frame, and the error against the Embree reference (GiReference): relative RMSE of the
// probes' irradiance and of the image's indirect term (a `--debug gi-light` frame), against the
// reference with the same bounces and against the converged one, and the image with the converged
// reference's probes written into the volume (the lookup's own error). Writes gi.md, gi.json, gi.png.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "janus/renderer/gi_reference.h"
#include "janus/renderer/renderer.h"
#include "plot.h"

namespace janus::cli {
namespace {

const std::vector<std::string> kSweeps = {"surfels", "bricks", "brick-size", "surfels-per-brick", "spacing", "order", "bounces",
                                          "probes-per-frame", "reduction", "normal-bias", "validity", "relocation", "visibility"};

struct GiOptions {
    std::string scene;
    std::string sweeps = fmt::format("{}", fmt::join(kSweeps, ","));   // all
    BenchTargets targets{"compute,fallback", "vulkan"};
    std::string size = "96x96";
    uint32_t runs = 3;
    uint32_t referenceDirections = 4096;
    uint32_t referenceSamples = 512;
    bool allowOutsidePaths = false;
    bool quick = false;
};

// One configuration of the sweep: the volume to measure and how it differs from the scene's.
struct Variant {
    std::string sweep;    // "default" for the scene's own volume
    std::string label;    // e.g. "surfels 64"
    renderer::IrradianceVolume volume;
};

std::vector<Variant> makeVariants(const renderer::IrradianceVolume& base, const std::vector<std::string>& sweeps, bool quick) {
    std::vector<Variant> variants{{"default", "default", base}};
    auto add = [&](const std::string& sweep, const std::string& label, auto&& change) {
        renderer::IrradianceVolume v = base;
        change(v);
        variants.push_back({sweep, label, v});
    };
    auto wanted = [&](const char* sweep) { return std::find(sweeps.begin(), sweeps.end(), sweep) != sweeps.end(); };
    const std::vector<uint32_t> surfels = quick ? std::vector<uint32_t>{64} : std::vector<uint32_t>{64, 128, 256, 512, 1024};
    if (wanted("surfels"))
        for (uint32_t n : surfels)
            if (n != base.surfelsPerProbe || !base.bricks) add("surfels", fmt::format("bricks, {} surfels", n), [&](auto& v) { v.surfelsPerProbe = n, v.bricks = true; });
    if (wanted("bricks"))
        for (uint32_t n : surfels.size() > 1 ? std::vector<uint32_t>{64, 128, 256, 512, 1024} : surfels)
            add("bricks", fmt::format("per-surfel, {} surfels", n), [&](auto& v) { v.surfelsPerProbe = n, v.bricks = false; });
    if (wanted("brick-size"))
        for (float size : quick ? std::vector<float>{1.0f} : std::vector<float>{0.25f, 1.0f, 2.0f})
            if (size != base.brickSize) add("brick-size", fmt::format("brick size {} m", size), [&](auto& v) { v.brickSize = size; });
    if (wanted("surfels-per-brick"))
        for (uint32_t n : quick ? std::vector<uint32_t>{4} : std::vector<uint32_t>{4, 8, 64})
            if (n != base.maxSurfelsPerBrick)
                add("surfels-per-brick", fmt::format("at most {} surfels per brick", n), [&](auto& v) { v.maxSurfelsPerBrick = n; });
    if (wanted("spacing"))
        for (uint32_t n : quick ? std::vector<uint32_t>{2} : std::vector<uint32_t>{2, 3, 6, 8})
            if (glm::uvec3(n) != base.probeCounts)
                add("spacing", fmt::format("{0}x{0}x{0} probes", n), [&](auto& v) { v.probeCounts = glm::uvec3(n); });
    if (wanted("order"))
        add("order", base.shOrder == 2 ? "L1" : "L2", [&](auto& v) { v.shOrder = base.shOrder == 2 ? 1 : 2; });
    if (wanted("bounces"))
        for (uint32_t b : quick ? std::vector<uint32_t>{1} : std::vector<uint32_t>{1, 2, 3, 6})
            if (b != base.bounces) add("bounces", fmt::format("{} bounce{}", b, b == 1 ? "" : "s"), [&](auto& v) { v.bounces = b; });
    if (wanted("probes-per-frame"))
        for (uint32_t k : quick ? std::vector<uint32_t>{16} : std::vector<uint32_t>{4, 16})
            if (k != base.probesPerFrame) add("probes-per-frame", fmt::format("{} probes per frame", k), [&](auto& v) { v.probesPerFrame = k; });
    if (wanted("reduction"))
        add("reduction", base.parallelReduction ? "serial SH sum" : "parallel SH reduction",
            [&](auto& v) { v.parallelReduction = !base.parallelReduction; });
    // Where shading looks the volume up (further bounces read it the same way, so the probes' light
    // moves a little too), and which probes shading weighs.
    if (wanted("normal-bias"))
        for (float bias : quick ? std::vector<float>{0.0f} : std::vector<float>{0.0f, 0.05f, 0.2f, 0.4f})
            if (bias != base.normalBias) add("normal-bias", fmt::format("normal bias {} m", bias), [&](auto& v) { v.normalBias = bias; });
    if (wanted("validity"))
        for (float fraction : quick ? std::vector<float>{0.25f} : std::vector<float>{0.1f, 0.25f, 0.75f, 1.0f})
            if (fraction != base.invalidBackFaceFraction)
                add("validity", fmt::format("invalid above {} back faces", fraction), [&](auto& v) { v.invalidBackFaceFraction = fraction; });
    if (wanted("relocation"))
        add("relocation", base.relocateProbes ? "probes not relocated" : "probes relocated", [&](auto& v) { v.relocateProbes = !base.relocateProbes; });
    if (wanted("visibility"))
        add("visibility", base.visibility ? "no visibility test" : "visibility test", [&](auto& v) { v.visibility = !base.visibility; });
    return variants;
}

struct RelightTime {
    double totalMs = 0.0;        // a whole relight (every cycle, every frame of it)
    uint32_t frames = 0;         // frames the relight took
    double brickMs = 0.0, shMs = 0.0;   // the relight's two passes, summed over its frames
};

struct Row {
    std::string backend, path, sweep, label;
    renderer::IrradianceVolume volume;
    double bakeMs = 0.0;           // the gi-bake step: G-buffer cubes, readback, bricks (CPU wall time)
    RelightTime relight;           // median over runs (by total)
    std::vector<double> relightRuns;
    bool gpuTimed = true;
    uint32_t probes = 0, validProbes = 0;
    uint64_t bricks = 0;
    renderer::GiError probeSame, probeConverged, imageSame, imageConverged;
    // The image with the converged reference's probes written into the volume: what the lookup
    // (grid, interpolation, L2, normal bias) loses on its own, whatever the relight's error.
    renderer::GiError imageReferenceProbes;
};

// The relight's passes of one frame (view "gi relight"), in GPU ms (CPU recording ms without timers).
// The main light's shadow map it reads is the frame's own (not view-specific): not counted.
void addRelight(const renderer::FrameReport& report, RelightTime& time, bool& gpuTimed) {
    bool any = false;
    for (const renderer::PassReport& pass : report.passes) {
        if (pass.view != "gi relight") continue;
        any = true;
        if (!pass.gpuMs) gpuTimed = false;
        const double ms = pass.gpuMs.value_or(pass.cpuMs);
        time.totalMs += ms;
        if (pass.name.rfind("gi-brick-radiance", 0) == 0) time.brickMs += ms;
        else if (pass.name.rfind("gi-probe-sh", 0) == 0) time.shMs += ms;
    }
    if (any) ++time.frames;
}

std::string percent(double value) { return std::isfinite(value) ? fmt::format("{:.1f}", 100.0 * value) : "inf"; }
std::string signedPercent(double value) { return std::isfinite(value) ? fmt::format("{:+.1f}", 100.0 * value) : value > 0 ? "+inf" : "-inf"; }
// "8.2 (-1.3)": relative RMSE and, in brackets, the signed bias, both in percent.
std::string errorCell(const renderer::GiError& e) { return fmt::format("{} ({})", percent(e.relativeRmse), signedPercent(e.relativeBias)); }
double finiteForJson(double value) { return std::isfinite(value) ? value : std::copysign(1e30, value); }

nlohmann::json errorJson(const renderer::GiError& e) {
    return {{"relativeRmse", finiteForJson(e.relativeRmse)}, {"relativeBias", finiteForJson(e.relativeBias)}, {"maxAbsolute", e.maxAbsolute},
            {"compared", e.compared}};
}

int runGi(const GiOptions& options) {
    std::vector<std::string> sweeps = splitList(options.sweeps);
    for (const std::string& s : sweeps)
        if (std::find(kSweeps.begin(), kSweeps.end(), s) == kSweeps.end())
            throw UsageError(fmt::format("--sweeps: unknown sweep '{}'; choose from {}", s, fmt::join(kSweeps, ", ")));
    const auto [paths, backends] = parseBenchTargets(options.targets, options.quick, "compute");
    if (options.runs < 1 || options.runs > 100) throw UsageError(fmt::format("--runs {} must be 1..100", options.runs));
    if (options.referenceDirections < 64 || options.referenceDirections > 1u << 20)
        throw UsageError(fmt::format("--reference-directions {} must be 64..1048576", options.referenceDirections));
    if (options.referenceSamples < 1 || options.referenceSamples > 1u << 16)
        throw UsageError(fmt::format("--reference-samples {} must be 1..65536", options.referenceSamples));
    const ImageSize size = options.quick ? ImageSize{32, 32} : parseSize(options.size);
    const std::filesystem::path outDir = benchOutputDir(options.targets.out, "gi");

    const std::optional<std::filesystem::path> scenePath =
        options.scene.empty() ? std::nullopt : std::optional<std::filesystem::path>(options.scene);
    const renderer::Scene scene = loadSceneOrDefault(scenePath, options.allowOutsidePaths);
    if (!scene.irradianceVolume)
        throw InputError(fmt::format("{} has no irradiance volume: give it one (a scene file's \"irradianceVolume\", or a glTF node "
                                     "named IrradianceVolume...; docs/GI.md)",
                                     sceneLabel(scenePath)));
    const uint32_t runs = options.quick ? 1 : options.runs;
    const uint32_t directions = options.quick ? 256 : options.referenceDirections;
    const uint32_t samples = options.quick ? 16 : options.referenceSamples;
    const std::vector<Variant> variants = makeVariants(*scene.irradianceVolume, sweeps, options.quick);
    {
        // What this bench writes in --out (gi.md/json/png and the default row's pictures) must not be
        // the scene or a file it reads.
        std::vector<std::string> outputs{"gi.md", "gi.json", "gi.png", "gi-reference.pfm",
                                         fmt::format("gi-reference-{}-bounces.pfm", variants.front().volume.bounces)};
        for (rhi::Backend backend : backends)
            for (renderer::FeaturePath path : paths) outputs.push_back(fmt::format("gi-{}-{}.pfm", rhi::toString(backend), renderer::toString(path)));
        checkFolderOutputs(outDir, "--out", outputs, sceneInputFiles(scenePath));
    }

    // The reference: per probe layout and bounce count (0 = converged), computed when first needed.
    const auto referenceStart = std::chrono::steady_clock::now();
    const renderer::GiReference reference(scene);   // Embree's BVH over the scene
    double referenceMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - referenceStart).count();
    std::map<std::pair<std::string, uint32_t>, std::vector<renderer::GiReferenceProbe>> referenceProbes;
    std::map<uint32_t, renderer::ImageRGBAF> referenceImages;
    std::map<uint32_t, double> referenceImageNoise;   // the reference image's relative noise: RMS of the two seeds' difference / 2
    auto timed = [&](auto&& body) {
        const auto start = std::chrono::steady_clock::now();
        body();
        referenceMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    };
    auto probesFor = [&](const std::vector<renderer::IrradianceProbe>& probes, const renderer::IrradianceVolume& v, uint32_t bounces)
        -> const std::vector<renderer::GiReferenceProbe>& {
        const std::string layout = fmt::format("{} {} {} {} {} {} {} {} {}", v.probeCounts.x, v.probeCounts.y, v.probeCounts.z, v.bounds.min.x,
                                               v.bounds.min.y, v.bounds.min.z, v.bounds.max.x, v.bounds.max.y, v.bounds.max.z);
        auto key = std::make_pair(layout, bounces);
        auto it = referenceProbes.find(key);
        if (it == referenceProbes.end()) {
            std::vector<glm::vec3> positions;
            for (const renderer::IrradianceProbe& p : probes) positions.push_back(p.position);
            timed([&] {
                it = referenceProbes.emplace(key, reference.probes(positions, renderer::GiReferenceSettings{}.setBounces(bounces).setDirectionsPerProbe(directions))).first;
            });
            std::fprintf(stderr, "  reference: %zu probes, %s, %u directions each\n", positions.size(),
                         bounces == 0 ? "converged" : fmt::format("{} bounces", bounces).c_str(), directions);
        }
        return it->second;
    };
    auto imageFor = [&](uint32_t bounces) -> const renderer::ImageRGBAF& {
        auto it = referenceImages.find(bounces);
        if (it == referenceImages.end()) {
            // Two halves with different seeds: their mean is the reference, their difference its noise.
            renderer::GiReferenceSettings settings = renderer::GiReferenceSettings{}.setBounces(bounces).setSamplesPerPixel(std::max(1u, samples / 2));
            renderer::ImageRGBAF a, b;
            timed([&] {
                a = reference.indirectIrradiance(scene.camera, size.width, size.height, settings.setSeed(1));
                b = reference.indirectIrradiance(scene.camera, size.width, size.height, settings.setSeed(2));
            });
            renderer::ImageRGBAF mean = a;
            for (size_t i = 0; i < mean.pixels.size(); ++i) mean.pixels[i] = 0.5f * (a.pixels[i] + b.pixels[i]);
            // RMS(a - b) / sqrt 2 is one half's noise; the mean of two halves has 1 / sqrt 2 of that.
            referenceImageNoise[bounces] = renderer::compareIndirectImage(a, b).relativeRmse / 2.0;
            it = referenceImages.emplace(bounces, std::move(mean)).first;
            std::fprintf(stderr, "  reference: %ux%u indirect image, %s, %u paths per pixel (noise %.1f %%)\n", size.width, size.height,
                         bounces == 0 ? "converged" : fmt::format("{} bounces", bounces).c_str(), std::max(1u, samples / 2) * 2,
                         100.0 * referenceImageNoise[bounces]);
        }
        return it->second;
    };

    std::vector<Row> rows;
    std::vector<std::string> skipped;
    for (rhi::Backend backend : backends) {
        rhi::DeviceDesc desc;
        desc.setBackend(backend).setGLPlatform(parseGLPlatformOption(options.targets.glPlatform));
        std::unique_ptr<rhi::IDevice> device = rhi::createDevice(desc);
        for (renderer::FeaturePath path : paths) {
            if (path == renderer::FeaturePath::Compute && !device->capabilities().has(rhi::Capability::Compute)) {
                skipped.push_back(fmt::format("{}: no compute", configurationLabel(backend, path)));
                continue;
            }
            for (const Variant& variant : variants) {
                if (variant.sweep == "reduction" && path != renderer::FeaturePath::Compute) continue;   // a compute-path option
                renderer::Scene configured = scene;
                configured.irradianceVolume = variant.volume;
                renderer::RenderSettings settings;
                settings.width = size.width, settings.height = size.height;
                settings.path = path;
                settings.debugView = renderer::DebugView::GiLight;   // the HDR image is the indirect term alone, no probe drawn
                Row row{rhi::toString(backend), renderer::toString(path), variant.sweep, variant.label, variant.volume};
                renderer::Renderer renderer(*device, configured, settings);
                // Run 0 is the first relight, from a black volume: after it the volume holds exactly
                // `bounces` bounces, and its errors are measured then. It is not timed (it pays for
                // first use: pipeline compiles in the driver). Later runs (markIrradianceDirty) start
                // from the last one's light, as a relight after a light moves does: the same passes,
                // the same cost, but their light accumulates further bounces.
                std::vector<RelightTime> times;
                std::vector<renderer::IrradianceProbe> probes;
                renderer::ImageRGBAF image;
                for (uint32_t run = 0; run <= runs; ++run) {
                    if (run > 0) renderer.markIrradianceDirty();
                    RelightTime time;
                    for (uint32_t frame = 0; frame < 4096; ++frame) {
                        const renderer::FrameReport report = renderer.renderFrame();
                        for (const renderer::PassReport& pass : report.passes)
                            if (pass.name == "gi-bake") row.bakeMs = pass.cpuMs;
                        addRelight(report, time, row.gpuTimed);
                        if (!renderer.irradiancePending()) break;
                    }
                    if (run == 0) {
                        probes = renderer.readIrradianceProbes();
                        image = renderer.readHdrImage();
                        continue;
                    }
                    times.push_back(time);
                    row.relightRuns.push_back(time.totalMs);
                }
                {
                    const std::vector<renderer::GiReferenceProbe>& truth = probesFor(probes, variant.volume, 0);
                    std::vector<renderer::IrradianceProbe> written = probes;
                    for (size_t i = 0; i < written.size(); ++i)
                        for (size_t k = 0; k < 9; ++k)   // an L1 volume holds no L2 terms
                            written[i].sh[k] = k >= 4 && variant.volume.shOrder < 2 ? glm::vec3(0.0f) : glm::vec3(truth[i].irradianceSh[k]);
                    renderer.writeIrradianceProbes(written);
                    renderer.renderFrame();
                    row.imageReferenceProbes = renderer::compareIndirectImage(renderer.readHdrImage(), imageFor(0));
                }
                std::sort(times.begin(), times.end(), [](const RelightTime& a, const RelightTime& b) { return a.totalMs < b.totalMs; });
                row.relight = times[times.size() / 2];
                row.probes = uint32_t(probes.size());
                row.validProbes = uint32_t(std::count_if(probes.begin(), probes.end(), [](const auto& p) { return p.valid; }));
                row.probeSame = renderer::compareProbeIrradiance(probes, probesFor(probes, variant.volume, variant.volume.bounces));
                row.probeConverged = renderer::compareProbeIrradiance(probes, probesFor(probes, variant.volume, 0));
                row.imageSame = renderer::compareIndirectImage(image, imageFor(variant.volume.bounces));
                row.imageConverged = renderer::compareIndirectImage(image, imageFor(0));
                if (variant.sweep == "default") {
                    // The pictures behind the default row's image errors, side by side in one PFM each.
                    renderer::writePFM(outDir / fmt::format("gi-{}-{}.pfm", row.backend, row.path), image);
                    renderer::writePFM(outDir / "gi-reference.pfm", imageFor(0));
                    renderer::writePFM(outDir / fmt::format("gi-reference-{}-bounces.pfm", variant.volume.bounces), imageFor(variant.volume.bounces));
                }
                std::fprintf(stderr, "  %s %-28s bake %8.1f ms, relight %8.3f ms in %u frame(s); probes %s (converged %s), image %s (converged %s, reference probes %s) %% (bias)\n",
                             configurationLabel(backend, path).c_str(), variant.label.c_str(), row.bakeMs, row.relight.totalMs, row.relight.frames,
                             errorCell(row.probeSame).c_str(), errorCell(row.probeConverged).c_str(), errorCell(row.imageSame).c_str(),
                             errorCell(row.imageConverged).c_str(), errorCell(row.imageReferenceProbes).c_str());
                rows.push_back(std::move(row));
            }
        }
        reportDebugMessages(rhi::toString(backend), device->takeDebugMessages());
    }
    if (rows.empty()) throw UnavailableError(fmt::format("bench gi: no configuration could run ({})", fmt::join(skipped, "; ")));

    // ---- Report ----
    const bool gpuTimed = std::all_of(rows.begin(), rows.end(), [](const Row& r) { return r.gpuTimed; });
    const char* unit = gpuTimed ? "GPU ms" : "ms";
    const renderer::IrradianceVolume& base = *scene.irradianceVolume;
    std::string md = fmt::format(
        "# Probe GI: accuracy vs time\n\n"
        "Scene: {}. Its volume: {}x{}x{} probes, {} surfels per probe, {}, brick size {} m, {} bounce(s), L{}, {} probes per frame. "
        "Each row changes one setting. Image: {}x{}, the `--debug gi-light` frame's HDR (irradiance / pi of the volume alone).\n\n"
        "- **bake**: the `gi-bake` step (G-buffer cubes, readback, bricks and transfers), CPU wall ms.\n"
        "- **relight**: a whole relight (every bounce cycle, over every frame it takes), {} (median of {} run(s) after the first); "
        "**per frame** = relight / frames; **brick** and **SH**: its two passes.\n"
        "- **probes**: after the first relight (from a black volume: exactly `bounces` bounces), relative RMSE of the valid probes' irradiance (64 normals each) against the Embree reference with the same bounces "
        "(the method's own error) and against the converged reference (what the light really is); **image**: the same for the "
        "image's indirect term, over the pixels the reference sees a surface at; **image % (ref. probes)**: the image against the converged "
        "reference with the converged reference's probes written into the volume (validity kept): what the lookup alone (grid, "
        "interpolation, L2, normal bias) loses. In brackets after each: the signed bias, sum of (renderer - reference) / sum of "
        "reference over every channel (< 0 too dark, > 0 too bright), which the RMSE does not tell.\n"
        "- Reference (`GiReference`, docs/GI.md): {} directions per probe, {} paths per pixel; image noise (two seeds): {}. "
        "Reference time: {:.0f} ms.\n\n",
        sceneLabel(scenePath), base.probeCounts.x, base.probeCounts.y, base.probeCounts.z, base.surfelsPerProbe,
        base.bricks ? "bricks" : "per-surfel", base.brickSize, base.bounces, base.shOrder, base.probesPerFrame == 0 ? std::string("all") : std::to_string(base.probesPerFrame),
        size.width, size.height, unit, runs, directions, std::max(1u, samples / 2) * 2,
        [&] {
            std::string s;
            for (const auto& [b, noise] : referenceImageNoise) s += fmt::format("{}{} {:.1f} %", s.empty() ? "" : ", ", b == 0 ? "converged" : fmt::format("{} bounces", b), 100.0 * noise);
            return s;
        }(),
        referenceMs);
    nlohmann::json json = {{"scene", sceneLabel(scenePath)}, {"width", size.width}, {"height", size.height}, {"runs", runs},
                           {"gpuTimed", gpuTimed}, {"referenceDirections", directions}, {"referenceSamplesPerPixel", std::max(1u, samples / 2) * 2},
                           {"referenceMs", referenceMs}, {"configurations", nlohmann::json::array()}, {"skipped", skipped}};
    for (const auto& [b, noise] : referenceImageNoise) json["referenceImageNoise"][b == 0 ? "converged" : std::to_string(b)] = noise;
    md += "| backend | path | sweep | configuration | valid probes | bake ms | relight " + std::string(unit) +
          " | frames | per frame | brick | SH | probes % | probes % (conv.) | image % | image % (conv.) | image % (ref. probes) |\n"
          "|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    std::vector<PlotSeries> series;
    for (const Row& r : rows) {
        md += fmt::format("| {} | {} | {} | {} | {} / {} | {:.1f} | {:.3f} | {} | {:.3f} | {:.3f} | {:.3f} | {} | {} | {} | {} | {} |\n", r.backend, r.path,
                          r.sweep, r.label, r.validProbes, r.probes, r.bakeMs, r.relight.totalMs, r.relight.frames,
                          r.relight.frames ? r.relight.totalMs / r.relight.frames : 0.0, r.relight.brickMs, r.relight.shMs, errorCell(r.probeSame),
                          errorCell(r.probeConverged), errorCell(r.imageSame), errorCell(r.imageConverged), errorCell(r.imageReferenceProbes));
        json["configurations"].push_back(
            {{"backend", r.backend}, {"path", r.path}, {"sweep", r.sweep}, {"label", r.label},
             {"volume", {{"probes", {r.volume.probeCounts.x, r.volume.probeCounts.y, r.volume.probeCounts.z}}, {"surfelsPerProbe", r.volume.surfelsPerProbe},
                         {"bricks", r.volume.bricks}, {"brickSize", r.volume.brickSize}, {"bounces", r.volume.bounces}, {"shOrder", r.volume.shOrder},
                         {"probesPerFrame", r.volume.probesPerFrame}, {"parallelReduction", r.volume.parallelReduction},
                         {"normalBias", r.volume.normalBias}, {"invalidBackFaceFraction", r.volume.invalidBackFaceFraction},
                         {"relocateProbes", r.volume.relocateProbes},
                         {"visibility", r.volume.visibility}}},
             {"probes", r.probes}, {"validProbes", r.validProbes}, {"bakeMs", r.bakeMs},
             {"relight", {{"totalMs", r.relight.totalMs}, {"frames", r.relight.frames}, {"brickMs", r.relight.brickMs}, {"shMs", r.relight.shMs},
                          {"runsMs", r.relightRuns}}},
             {"probeError", errorJson(r.probeSame)}, {"probeErrorConverged", errorJson(r.probeConverged)},
             {"imageError", errorJson(r.imageSame)}, {"imageErrorConverged", errorJson(r.imageConverged)},
             {"imageErrorReferenceProbes", errorJson(r.imageReferenceProbes)}});
    }

    // Plot: probe error against the converged reference vs relight time for the first backend and
    // path (the others are in the table), one line per sweep through the default row.
    const Row* defaultRow = nullptr;
    for (const Row& r : rows)
        if (r.sweep == "default" && r.backend == rows.front().backend && r.path == rows.front().path) defaultRow = &r;
    for (const Row& r : rows) {
        if (r.sweep == "default" || r.backend != rows.front().backend || r.path != rows.front().path) continue;
        if (!(r.relight.totalMs > 0.0 && r.probeConverged.relativeRmse > 0.0)) continue;
        PlotSeries& line = seriesNamed(series, r.sweep);
        if (line.points.empty() && defaultRow)   // each sweep's line starts at the default row
            line.points.push_back({defaultRow->relight.totalMs, 100.0 * defaultRow->probeConverged.relativeRmse});
        line.points.push_back({r.relight.totalMs, 100.0 * r.probeConverged.relativeRmse});
    }

    // ---- Goals (docs/GI.md): measured in this run ----
    md += "\n## Goals\n\n";
    nlohmann::json goals = nlohmann::json::array();
    for (const Row& d : rows) {
        if (d.sweep != "default") continue;
        auto same = [&](const Row& r) { return r.backend == d.backend && r.path == d.path; };
        // 1. Bricks vs per-surfel at equal error (probe error against the same-bounce reference):
        // the cheapest per-surfel row whose error is at most the bricks' + 0.5 points (the errors
        // level off at the method's floor, where a strict comparison would pick on noise).
        for (const Row& r : rows) {
            if (!same(r) || !(r.sweep == "surfels" || r.sweep == "default") || !r.volume.bricks)
                continue;
            const Row* cheapest = nullptr;
            for (const Row& p : rows)
                if (same(p) && p.sweep == "bricks" && p.probeSame.relativeRmse <= r.probeSame.relativeRmse + 0.005 &&
                    (!cheapest || p.relight.totalMs < cheapest->relight.totalMs))
                    cheapest = &p;
            std::string line = fmt::format("- {}/{} bricks, {} surfels: {} % in {:.3f} {};", d.backend, d.path, r.volume.surfelsPerProbe,
                                           percent(r.probeSame.relativeRmse), r.relight.totalMs, unit);
            if (cheapest)
                line += fmt::format(" per-surfel needs {} surfels for {} %: {:.3f} {}, **{:.1f}x** the time", cheapest->volume.surfelsPerProbe,
                                    percent(cheapest->probeSame.relativeRmse), cheapest->relight.totalMs, unit,
                                    cheapest->relight.totalMs / std::max(1e-9, r.relight.totalMs));
            else
                line += " no per-surfel row reaches that error";
            md += line + "\n";
            goals.push_back({{"goal", "bricks vs per-surfel at equal error"}, {"backend", d.backend}, {"path", d.path}, {"surfels", r.volume.surfelsPerProbe},
                             {"bricksMs", r.relight.totalMs}, {"bricksRmse", r.probeSame.relativeRmse},
                             {"perSurfelMs", cheapest ? nlohmann::json(cheapest->relight.totalMs) : nlohmann::json(nullptr)},
                             {"perSurfelSurfels", cheapest ? nlohmann::json(cheapest->volume.surfelsPerProbe) : nlohmann::json(nullptr)}});
        }
        // 2. The parallel reduction vs a serial sum (the SH pass alone; compute path).
        for (const Row& r : rows)
            if (same(r) && r.sweep == "reduction") {
                const double parallel = d.volume.parallelReduction ? d.relight.shMs : r.relight.shMs;
                const double serial = d.volume.parallelReduction ? r.relight.shMs : d.relight.shMs;
                md += fmt::format("- {}/{} SH pass: parallel reduction {:.3f} {}, serial sum {:.3f} {}: the reduction is **{:.1f}x** faster\n", d.backend,
                                  d.path, parallel, unit, serial, unit, serial / std::max(1e-9, parallel));
                goals.push_back({{"goal", "parallel reduction vs serial"}, {"backend", d.backend}, {"path", d.path}, {"parallelMs", parallel}, {"serialMs", serial}});
            }
        // 3. The visibility test: what it changes in the image, and what it costs a relight (its
        // further bounces read the volume through it).
        for (const Row& r : rows)
            if (same(r) && r.sweep == "visibility") {
                const Row& with = d.volume.visibility ? d : r;
                const Row& without = d.volume.visibility ? r : d;
                md += fmt::format("- {}/{} visibility test: image {} % ({}) with it, {} % ({}) without, against the converged reference; "
                                  "with the reference's own probes {} % and {} %; relight {:.3f} and {:.3f} {}\n",
                                  d.backend, d.path, percent(with.imageConverged.relativeRmse), signedPercent(with.imageConverged.relativeBias),
                                  percent(without.imageConverged.relativeRmse), signedPercent(without.imageConverged.relativeBias),
                                  percent(with.imageReferenceProbes.relativeRmse), percent(without.imageReferenceProbes.relativeRmse),
                                  with.relight.totalMs, without.relight.totalMs, unit);
                goals.push_back({{"goal", "visibility test"}, {"backend", d.backend}, {"path", d.path},
                                 {"imageRmseWith", with.imageConverged.relativeRmse}, {"imageRmseWithout", without.imageConverged.relativeRmse},
                                 {"imageRmseReferenceProbesWith", with.imageReferenceProbes.relativeRmse},
                                 {"imageRmseReferenceProbesWithout", without.imageReferenceProbes.relativeRmse},
                                 {"relightMsWith", with.relight.totalMs}, {"relightMsWithout", without.relight.totalMs}});
            }
        // 4. The default settings against the converged reference.
        // With the reference's own probes the image shows what the grid allows at best.
        md += fmt::format("- {}/{} default settings vs the converged reference: probes **{} %**, image **{} %** relative RMSE (goal: within 10 %); "
                          "with the reference's own probes the image is {} % (what this grid allows)\n",
                          d.backend, d.path, percent(d.probeConverged.relativeRmse), percent(d.imageConverged.relativeRmse),
                          percent(d.imageReferenceProbes.relativeRmse));
        goals.push_back({{"goal", "defaults vs converged reference"}, {"backend", d.backend}, {"path", d.path},
                         {"probeRmse", d.probeConverged.relativeRmse}, {"imageRmse", d.imageConverged.relativeRmse},
                         {"imageRmseReferenceProbes", d.imageReferenceProbes.relativeRmse}});
    }
    json["goals"] = goals;
    if (!skipped.empty()) {
        md += "\nSkipped:\n\n";
        for (const std::string& s : skipped) md += "- " + s + "\n";
    }
    md += fmt::format("\nPlot (gi.png): probe irradiance relative RMSE (%) against the converged reference vs relight ms on {}/{}, "
                      "log-log, one line per sweep through the default row.\n",
                      rows.front().backend, rows.front().path);
    writeBenchOutputs(outDir, "gi", md, json, drawLogXPlot(series, fmt::format("RELIGHT {}", gpuTimed ? "GPU MS" : "MS"), "PROBE RELATIVE RMSE (PERCENT)"));
    return 0;
}

}  // namespace

std::function<int()> addBenchGiCommand(CLI::App& bench) {
    auto options = std::make_shared<GiOptions>();
    CLI::App* gi = bench.add_subcommand(
        "gi", "Probe GI: error against the Embree reference vs bake and relight time, one setting swept at a time around the scene's "
              "irradiance volume; writes gi.md, gi.json, gi.png to --out");
    addSceneArgument(*gi, options->scene);
    gi->add_option("--sweeps", options->sweeps, "Comma-separated sweeps: " + fmt::format("{}", fmt::join(kSweeps, ", ")))->default_str(options->sweeps);
    gi->add_option("--size", options->size, "Image size WxH for the indirect-term error")->default_str(options->size);
    gi->add_option("--runs", options->runs, "Relights timed per configuration (median)")->default_str("3");
    gi->add_option("--reference-directions", options->referenceDirections, "Reference: directions (paths) per probe")->default_str("4096");
    gi->add_option("--reference-samples", options->referenceSamples, "Reference: paths per pixel")->default_str("512");
    gi->add_flag("--quick", options->quick,
                 "Tiny run for tests: 32x32, one value per sweep, 1 run, a coarse reference, the compute path unless --paths is given");
    addAllowOutsidePathsFlag(*gi, options->allowOutsidePaths);
    addBenchTargetOptions(*gi, options->targets);
    gi->footer(kExitCodeHelp);
    return [options, gi] {
        noteBenchTargetsGiven(*gi, options->targets);
        return runGi(*options);
    };
}

}  // namespace janus::cli
