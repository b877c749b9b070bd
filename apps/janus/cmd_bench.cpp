// `janus bench forward`: the many-lights scene at several light counts, culling modes, feature
// paths and backends; frame time, culling time and culling efficiency, with ratios against naive
// from the same run; the intensity cut-off's error (with a picture of where it is, for the
// smallest cut-off); the tile size and the tile list cap against their time and their error (a
// capped list drops lights); forward.md / forward.json / forward.png / cutoff-error-<backend>-<path>.png.
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <memory>

#include <fmt/format.h>

#include "cli_common.h"
#include "janus/renderer/light_grid.h"
#include "plot.h"

namespace janus::cli {
namespace {

struct BenchOptions {
    std::string lights = "0,8,32,128,512,2048";
    std::string modes = "naive,tiles-2d,tiles-depth";
    std::string paths = "compute,fallback";
    std::string backends = "vulkan,gl";
    std::string cutoffs = "0.1,0.03,0.01,0.003,0.001";
    std::string tileSizes = "16,32,64,128";
    std::string tileCaps = "16,64,256";
    std::string size = "256x256";
    std::string out;
    uint32_t frames = 5;
    uint32_t warmup = 2;
    std::string glPlatform = "egl";
    bool quick = false;
    std::set<std::string> given;   // the options given on the command line (--quick does not override them)
};

struct Measurement {
    double frameGpuMs = 0.0, frameWallMs = 0.0, cullMs = 0.0;
    bool gpuTimed = true;
    renderer::FrameReport report;
    std::optional<renderer::ImageRGBAF> hdr;
    std::optional<renderer::CullingEfficiency> efficiency;
};

// Renders warmup + frames frames of one configuration; medians of the frame GPU time (sum of the
// passes), the CPU wall time of renderFrame, and the culling time (light-cull pass: GPU time of
// the compute dispatch, CPU time of the CPU builder).
Measurement measure(rhi::IDevice& device, const renderer::Scene& scene, const renderer::RenderSettings& settings, uint32_t warmup,
                    uint32_t frames, bool wantHdr, bool wantEfficiency) {
    renderer::Renderer frameRenderer(device, scene, settings);
    Measurement result;
    std::vector<double> gpu, wall, cull;
    for (uint32_t i = 0; i < warmup + frames; ++i) {
        const auto start = std::chrono::steady_clock::now();
        renderer::FrameReport report = frameRenderer.renderFrame();
        const double wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        if (i < warmup) continue;
        double gpuMs = 0.0, cullMs = 0.0;
        for (const renderer::PassReport& pass : report.passes) {
            const bool culling = pass.name.rfind("light-cull", 0) == 0;
            // The CPU builder runs between submissions, so its CPU time is part of the frame.
            if (pass.gpuMs) gpuMs += *pass.gpuMs;
            else if (culling) gpuMs += pass.cpuMs;
            else result.gpuTimed = false;
            if (culling) cullMs += pass.gpuMs ? *pass.gpuMs : pass.cpuMs;
        }
        gpu.push_back(gpuMs);
        wall.push_back(wallMs);
        cull.push_back(cullMs);
        result.report = std::move(report);
    }
    result.frameGpuMs = median(gpu);
    result.frameWallMs = median(wall);
    result.cullMs = median(cull);
    if (wantHdr) result.hdr = frameRenderer.readHdrImage();
    if (wantEfficiency && result.report.lightCulling) {
        const renderer::LightCullingReport& c = *result.report.lightCulling;
        const std::vector<float> depth = frameRenderer.readDepth();
        const renderer::PackedLights packed =
            renderer::packLocalLights(scene, settings.lighting.intensityCutoff.value_or(0.01f));
        const bool tiled = c.mode != renderer::LightCulling::Naive;
        const renderer::TileGrid grid = renderer::makeTileGrid(scene.camera, settings.width, settings.height,
                                                               tiled ? c.tileSize : 16, tiled ? c.maxLightsPerTile : 1);
        if (tiled) {
            const renderer::TileLists lists = frameRenderer.readTileLists();
            result.efficiency = renderer::measureCullingEfficiency(grid, packed.lights, &lists, depth);
        } else {
            result.efficiency = renderer::measureCullingEfficiency(grid, packed.lights, nullptr, depth);
        }
    }
    return result;
}

// Frame time used for ratios: GPU time where the device has timers, CPU wall time otherwise.
double frameMs(const Measurement& m) { return m.gpuTimed ? m.frameGpuMs : m.frameWallMs; }

// An HDR image against a reference of the same size, over the colour channels.
struct ImageError {
    double maxError = 0.0, meanError = 0.0, psnr = INFINITY;
    uint32_t maxX = 0, maxY = 0;     // the pixel with the largest error (row 0 on top)
    std::vector<double> perPixel;   // the largest channel error per pixel, when asked for
};
ImageError compareHdr(const renderer::ImageRGBAF& reference, const renderer::ImageRGBAF& image, bool perPixel) {
    ImageError result;
    const std::vector<float>& a = reference.pixels;
    const std::vector<float>& b = image.pixels;
    if (perPixel) result.perPixel.assign(a.size() / 4, 0.0);
    double sumSq = 0.0, sum = 0.0, peak = 0.0;
    size_t samples = 0;
    for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
        if (i % 4 == 3) continue;   // alpha carries no radiance
        const double error = std::abs(double(a[i]) - double(b[i]));
        if (error > result.maxError) {
            result.maxX = uint32_t(i / 4 % reference.width);
            result.maxY = uint32_t(i / 4 / reference.width);
        }
        if (perPixel) result.perPixel[i / 4] = std::max(result.perPixel[i / 4], error);
        result.maxError = std::max(result.maxError, error);
        sum += error;
        sumSq += error * error;
        peak = std::max(peak, double(a[i]));
        ++samples;
    }
    result.meanError = sum / double(std::max<size_t>(samples, 1));
    const double mse = sumSq / double(std::max<size_t>(samples, 1));
    // PSNR against the reference's brightest channel (HDR has no fixed peak).
    result.psnr = mse > 0 ? 10.0 * std::log10(peak * peak / mse) : INFINITY;
    return result;
}

struct Row {
    std::string backend, path, mode;
    uint32_t lights = 0;
    Measurement m;
    double speedupVsNaive = 0.0;   // naive frame ms / this frame ms, same backend, path and count
};

// A comma-separated option's items: a UsageError for a list with none (`--lights ''`), which
// would otherwise run nothing and write empty tables.
std::vector<std::string> listItems(const std::string& text, std::string_view option, std::string_view example) {
    std::vector<std::string> items = splitList(text);
    if (items.empty()) throw UsageError(fmt::format("{} '{}' is empty; give at least one entry, such as {}", option, text, example));
    return items;
}

int runForward(const BenchOptions& options) {
    // --quick sets small defaults for tests; an option given explicitly wins over them (and is
    // checked like any other value).
    const bool quick = options.quick;
    auto given = [&](const char* name) { return options.given.count(name) > 0; };
    const std::string lightsText = quick && !given("--lights") ? "0,64" : options.lights;
    std::vector<uint32_t> counts;
    for (const std::string& item : listItems(lightsText, "--lights", "0,64")) {
        uint32_t n = 0;
        const auto [end, error] = std::from_chars(item.data(), item.data() + item.size(), n);
        if (error != std::errc() || end != item.data() + item.size() || n > renderer::kMaxLocalLights) throw UsageError(fmt::format("--lights '{}' must be a comma-separated list of light counts 0..16384", lightsText));
        counts.push_back(n);
    }
    std::vector<renderer::LightCulling> modes;
    for (const std::string& item : listItems(options.modes, "--modes", "naive,tiles-depth")) {
        const std::optional<renderer::LightCulling> mode = renderer::parseLightCulling(item);
        if (!mode || *mode == renderer::LightCulling::Auto)
            throw UsageError(fmt::format("--modes '{}': each mode must be naive, tiles-2d or tiles-depth", options.modes));
        modes.push_back(*mode);
    }
    std::vector<renderer::FeaturePath> paths;
    for (const std::string& item : listItems(options.paths, "--paths", "compute,fallback")) paths.push_back(parsePathOption(item));
    std::vector<rhi::Backend> backends;
    for (const std::string& item : listItems(options.backends, "--backends", "vulkan,gl")) backends.push_back(parseBackendOption(item));
    const std::string cutoffsText = quick && !given("--cutoffs") ? "0.01" : options.cutoffs;
    std::vector<float> cutoffs;
    for (const std::string& item : listItems(cutoffsText, "--cutoffs", "0.01,0.001")) {
        float cutoff = 0.0f;
        const auto [end, error] = std::from_chars(item.data(), item.data() + item.size(), cutoff);
        if (error != std::errc() || end != item.data() + item.size() || !std::isfinite(cutoff) || cutoff <= 0.0f)
            throw UsageError(fmt::format("--cutoffs '{}': each cut-off must be a finite number > 0 (lux; 0 is the reference), "
                                         "such as 0.01,0.001",
                                         cutoffsText));
        cutoffs.push_back(cutoff);
    }
    const std::vector<uint32_t> tileSizes =
        parseCountList(quick && !given("--tile-sizes") ? "16,64" : options.tileSizes, "--tile-sizes", 16, 256, true);
    const std::vector<uint32_t> tileCaps = parseCountList(quick && !given("--tile-caps") ? "4" : options.tileCaps, "--tile-caps", 1, 1024, false);
    const ImageSize size = parseSize(quick && !given("--size") ? "64x64" : options.size);
    if (options.frames < 1 || options.frames > 1000)
        throw UsageError(fmt::format("--frames {} is not allowed; measure 1..1000 frames per row", options.frames));
    if (options.warmup > 1000) throw UsageError(fmt::format("--warmup {} is not allowed; use 0..1000 frames", options.warmup));
    const uint32_t frames = quick && !given("--frames") ? 1 : options.frames;
    const uint32_t warmup = quick && !given("--warmup") ? 1 : options.warmup;
    const rhi::GLPlatform glPlatform = parseGLPlatformOption(options.glPlatform);
    const std::filesystem::path outDir = benchOutputDir(options.out, "forward");

    // Every row's settings: the image size, a path and a culling mode; the rest the scene's.
    auto settingsFor = [&](renderer::FeaturePath path, renderer::LightCulling culling) {
        renderer::RenderSettings settings;
        settings.width = size.width;
        settings.height = size.height;
        settings.path = path;
        settings.lighting.culling = culling;
        return settings;
    };
    std::vector<Row> rows;
    struct CutoffRow {
        std::string backend, path;
        float cutoff = 0.0f;
        double maxError = 0.0, meanError = 0.0, psnr = 0.0, ms = 0.0, referenceMs = 0.0;
        uint32_t maxX = 0, maxY = 0;   // the pixel with the largest error (row 0 on top)
    };
    std::vector<CutoffRow> cutoffRows;
    const uint32_t cutoffLights = std::min<uint32_t>(*std::max_element(counts.begin(), counts.end()), 128);
    // The tile knobs: at the largest light count, one changed at a time from the renderer's default.
    struct KnobRow {
        std::string backend, path, knob;
        uint32_t tileSize = 0, cap = 0;
        Measurement m;
        ImageError error;   // against naive with the same lights and cut-off
        double referenceMs = 0.0;
    };
    std::vector<KnobRow> knobRows;
    const uint32_t knobLights = *std::max_element(counts.begin(), counts.end());
    renderer::LightingSettings defaults;
    {
        renderer::ManyLightsOptions sceneOptions;
        sceneOptions.lightCount = knobLights;
        defaults = renderer::resolveLightingSettings({}, renderer::manyLightsScene(sceneOptions));
    }
    std::vector<std::string> skipped;   // configurations that cannot run here, and why
    for (rhi::Backend backend : backends) {
        rhi::DeviceDesc desc;
        desc.setBackend(backend).setGLPlatform(glPlatform);
        std::unique_ptr<rhi::IDevice> device = rhi::createDevice(desc);
        for (renderer::FeaturePath path : paths) {
            if (path == renderer::FeaturePath::Compute && !device->capabilities().has(rhi::Capability::Compute)) {
                skipped.push_back(fmt::format("{}: the {} backend lacks the 'compute' capability", configurationLabel(backend, path),
                                              rhi::toString(backend)));
                continue;
            }
            for (uint32_t count : counts) {
                renderer::ManyLightsOptions sceneOptions;
                sceneOptions.lightCount = count;
                const renderer::Scene scene = renderer::manyLightsScene(sceneOptions);
                size_t naiveRow = SIZE_MAX;
                for (renderer::LightCulling mode : modes) {
                    const renderer::RenderSettings settings = settingsFor(path, mode);
                    // Naive at the tile knobs' count keeps its image: the knobs' reference (below).
                    const bool knobReference = mode == renderer::LightCulling::Naive && count == knobLights;
                    Row row{rhi::toString(backend), renderer::toString(path), renderer::toString(mode), count,
                            measure(*device, scene, settings, warmup, frames, knobReference, count > 0)};
                    if (mode == renderer::LightCulling::Naive) naiveRow = rows.size();
                    std::fprintf(stderr, "  %s/%s %5u lights %-11s %9.3f ms\n", row.backend.c_str(), row.path.c_str(), count,
                                 row.mode.c_str(), frameMs(row.m));
                    rows.push_back(std::move(row));
                }
                if (naiveRow != SIZE_MAX)
                    for (size_t r = naiveRow; r < rows.size(); ++r)
                        if (rows[r].lights == count && rows[r].path == rows[naiveRow].path && rows[r].backend == rows[naiveRow].backend)
                            rows[r].speedupVsNaive = frameMs(rows[naiveRow].m) / std::max(frameMs(rows[r].m), 1e-9);
            }
            // Intensity cut-off error: lights without a range, tiles-depth at each cut-off vs the
            // infinite-range naive reference (cut-off 0), on the HDR image.
            renderer::ManyLightsOptions sceneOptions;
            sceneOptions.lightCount = cutoffLights;
            sceneOptions.rangeFraction = 0.0f;
            const renderer::Scene scene = renderer::manyLightsScene(sceneOptions);
            renderer::RenderSettings settings = settingsFor(path, renderer::LightCulling::Naive);
            settings.lighting.intensityCutoff = 0.0f;
            const Measurement reference = measure(*device, scene, settings, warmup, frames, true, false);
            for (float cutoff : cutoffs) {
                settings.lighting.culling = renderer::LightCulling::TilesDepth;
                settings.lighting.intensityCutoff = cutoff;
                const Measurement m = measure(*device, scene, settings, warmup, frames, true, false);
                CutoffRow row{rhi::toString(backend), renderer::toString(path), cutoff};
                // Where the error is: a picture of it for the smallest cut-off (linear, white = the
                // largest error), where a lost light shows as a bright patch.
                const bool picture = cutoff == *std::min_element(cutoffs.begin(), cutoffs.end());
                const ImageError error = compareHdr(*reference.hdr, *m.hdr, picture);
                const std::vector<double>& pixelError = error.perPixel;
                row.maxError = error.maxError, row.meanError = error.meanError, row.psnr = error.psnr;
                row.maxX = error.maxX, row.maxY = error.maxY;
                row.ms = frameMs(m);
                row.referenceMs = frameMs(reference);
                if (picture && row.maxError > 0.0) {
                    renderer::ImageRGBA8 errorImage{size.width, size.height, std::vector<uint8_t>(pixelError.size() * 4)};
                    for (size_t p = 0; p < pixelError.size(); ++p) {
                        const auto v = uint8_t(std::lround(255.0 * pixelError[p] / row.maxError));
                        errorImage.pixels[p * 4 + 0] = errorImage.pixels[p * 4 + 1] = errorImage.pixels[p * 4 + 2] = v;
                        errorImage.pixels[p * 4 + 3] = 255;
                    }
                    renderer::writePNG(outDir / fmt::format("cutoff-error-{}-{}.png", row.backend, row.path), errorImage);
                }
                cutoffRows.push_back(row);
            }
            // Tile size and list cap: tiles-depth against naive with the same lights and cut-off.
            // Culling is conservative, so only a full list (a cap below the lights a tile meets,
            // which drops the rest) makes an error beyond float rounding.
            if (knobLights > 0) {
                renderer::ManyLightsOptions knobSceneOptions;
                knobSceneOptions.lightCount = knobLights;
                const renderer::Scene knobScene = renderer::manyLightsScene(knobSceneOptions);
                renderer::RenderSettings knobSettings = settingsFor(path, renderer::LightCulling::Naive);
                // The main table's naive row at this count when it has one, else measured now.
                const auto measured = std::find_if(rows.begin(), rows.end(), [&](const Row& r) {
                    return r.backend == rhi::toString(backend) && r.path == renderer::toString(path) && r.lights == knobLights && r.m.hdr;
                });
                std::optional<Measurement> measuredNow;
                const Measurement& naive = measured != rows.end()
                                               ? measured->m
                                               : measuredNow.emplace(measure(*device, knobScene, knobSettings, warmup, frames, true, false));
                auto runKnob = [&](const char* knob, uint32_t tileSize, uint32_t cap) {
                    knobSettings.lighting.culling = renderer::LightCulling::TilesDepth;
                    knobSettings.lighting.tileSize = tileSize;
                    knobSettings.lighting.maxLightsPerTile = cap;
                    KnobRow row{rhi::toString(backend), renderer::toString(path), knob, tileSize, cap,
                                measure(*device, knobScene, knobSettings, warmup, frames, true, true)};
                    row.error = compareHdr(*naive.hdr, *row.m.hdr, false);
                    row.m.hdr.reset();
                    row.referenceMs = frameMs(naive);
                    const uint32_t chosenCap = row.m.report.lightCulling ? row.m.report.lightCulling->maxLightsPerTile : cap;
                    std::fprintf(stderr, "  %s/%s %5u lights tiles %3u px, cap %4u%s: %9.3f ms, max error %.4g\n", row.backend.c_str(),
                                 row.path.c_str(), knobLights, tileSize, chosenCap, cap == renderer::kAutoMaxLightsPerTile ? " (auto)" : "",
                                 frameMs(row.m), row.error.maxError);
                    knobRows.push_back(std::move(row));
                };
                for (uint32_t tileSize : tileSizes) runKnob("tile size", tileSize, *defaults.maxLightsPerTile);
                for (uint32_t cap : tileCaps)
                    if (cap != *defaults.maxLightsPerTile || std::find(tileSizes.begin(), tileSizes.end(), *defaults.tileSize) == tileSizes.end())
                        runKnob("list cap", *defaults.tileSize, cap);
            }
        }
        const std::vector<rhi::DebugMessage> messages = device->takeDebugMessages();
        reportDebugMessages(rhi::toString(backend), messages);
    }

    if (rows.empty())
        throw UnavailableError(fmt::format("bench forward: no configuration could run ({}); choose --backends and --paths this machine "
                                           "has (janus info)",
                                           fmt::join(skipped, "; ")));

    // Auto threshold suggestion: smallest light count at which the best tiled mode beats naive,
    // per backend/path.
    std::map<std::string, uint32_t> threshold;
    for (const Row& row : rows) {
        if (row.mode == "naive" || row.lights == 0 || row.speedupVsNaive <= 1.0) continue;
        const std::string key = row.backend + "/" + row.path;
        if (!threshold.count(key) || row.lights < threshold[key]) threshold[key] = row.lights;
    }

    auto efficiencyText = [](const Row& row) {
        return row.m.efficiency ? fmt::format("{:.3f}", row.m.efficiency->ratio()) : std::string("-");
    };
    std::string md = fmt::format("# Forward+ benchmark\n\nScene: built-in many-lights, {}x{}, median of {} frames after {} warm-up.\n"
                                 "Frame ms = sum of pass GPU times plus the CPU tile builder's time (CPU wall ms where the device has no timers). "
                                 "Culling ms = light-cull pass (GPU for compute, CPU for the CPU builder). "
                                 "Efficiency = contributing light evaluations / performed.\n\n",
                                 size.width, size.height, frames, warmup);
    md += "| backend | path | lights | mode | frame GPU ms | frame wall ms | culling ms | efficiency | speed-up vs naive | overflow tiles |\n"
          "|---|---|---:|---|---:|---:|---:|---:|---:|---:|\n";
    nlohmann::json json = {{"size", {size.width, size.height}}, {"frames", frames}, {"warmup", warmup}, {"rows", nlohmann::json::array()}};
    for (const Row& row : rows) {
        const uint32_t overflow = row.m.report.lightCulling ? row.m.report.lightCulling->overflowTiles : 0;
        md += fmt::format("| {} | {} | {} | {} | {:.3f} | {:.3f} | {:.3f} | {} | {:.2f}x | {} |\n", row.backend, row.path, row.lights,
                          row.mode, row.m.frameGpuMs, row.m.frameWallMs, row.m.cullMs, efficiencyText(row), row.speedupVsNaive, overflow);
        nlohmann::json j = {{"backend", row.backend}, {"path", row.path}, {"lights", row.lights}, {"mode", row.mode},
                            {"frameGpuMs", row.m.frameGpuMs}, {"frameWallMs", row.m.frameWallMs}, {"gpuTimed", row.m.gpuTimed},
                            {"cullMs", row.m.cullMs}, {"speedupVsNaive", row.speedupVsNaive}};
        if (row.m.efficiency)
            j["efficiency"] = {{"performed", row.m.efficiency->performed}, {"contributing", row.m.efficiency->contributing},
                               {"ratio", row.m.efficiency->ratio()}};
        if (row.m.report.lightCulling)
            j["overflowTiles"] = row.m.report.lightCulling->overflowTiles;
        json["rows"].push_back(j);
    }
    md += fmt::format("\n## Intensity cut-off error ({} lights without a range, tiles-depth vs infinite-range naive)\n\n"
                      "| backend | path | cut-off (lux) | max abs error | at pixel | mean abs error | PSNR dB | frame ms | reference ms |\n"
                      "|---|---|---:|---:|---|---:|---:|---:|---:|\n",
                      cutoffLights);
    json["cutoffs"] = nlohmann::json::array();
    for (const CutoffRow& row : cutoffRows) {
        md += fmt::format("| {} | {} | {} | {:.4g} | ({}, {}) | {:.4g} | {:.1f} | {:.3f} | {:.3f} |\n", row.backend, row.path, row.cutoff,
                          row.maxError, row.maxX, row.maxY, row.meanError, row.psnr, row.ms, row.referenceMs);
        json["cutoffs"].push_back({{"backend", row.backend}, {"path", row.path}, {"cutoff", row.cutoff}, {"maxAbsError", row.maxError},
                                   {"maxAbsErrorAt", {row.maxX, row.maxY}},
                                   {"meanAbsError", row.meanError}, {"psnr", std::isinf(row.psnr) ? 999.0 : row.psnr},
                                   {"frameMs", row.ms}, {"referenceMs", row.referenceMs}});
    }
    if (!knobRows.empty()) {
        md += fmt::format("\n## Tile size and list cap ({} lights, tiles-depth against naive)\n\n"
                          "One knob changed at a time from the renderer's defaults ({} px tiles, {}). Culling is "
                          "conservative: the error is float rounding until a tile meets more lights than the cap, whose list then drops "
                          "the rest (counted, and warned on stderr).\n\n"
                          "| backend | path | knob | tile px | cap | frame ms | culling ms | efficiency | overflow tiles | dropped lights | "
                          "densest tile | max abs error | mean abs error | naive ms |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
                          knobLights, *defaults.tileSize,
                          *defaults.maxLightsPerTile == renderer::kAutoMaxLightsPerTile
                              ? fmt::format("the automatic list cap, marked \"auto\": as many lights as the scene has, within {} MiB of lists",
                                            renderer::kAutoTileListBudgetBytes >> 20)
                              : fmt::format("at most {} lights per tile", *defaults.maxLightsPerTile));
        json["tileKnobs"] = nlohmann::json::array();
        for (const KnobRow& row : knobRows) {
            const renderer::LightCullingReport* culling = row.m.report.lightCulling ? &*row.m.report.lightCulling : nullptr;
            const uint32_t cap = culling ? culling->maxLightsPerTile : row.cap;   // an automatic cap as chosen
            const bool automatic = row.cap == renderer::kAutoMaxLightsPerTile;
            md += fmt::format("| {} | {} | {} | {} | {}{} | {:.3f} | {:.3f} | {} | {} | {} | {} | {:.4g} | {:.4g} | {:.3f} |\n", row.backend,
                              row.path, row.knob, row.tileSize, cap, automatic ? " (auto)" : "", frameMs(row.m), row.m.cullMs,
                              row.m.efficiency ? fmt::format("{:.3f}", row.m.efficiency->ratio()) : std::string("-"),
                              culling ? culling->overflowTiles : 0, culling ? culling->droppedLights : 0,
                              culling ? culling->densestTileLights : 0, row.error.maxError,
                              row.error.meanError, row.referenceMs);
            nlohmann::json j = {{"backend", row.backend}, {"path", row.path}, {"knob", row.knob}, {"tileSize", row.tileSize},
                                {"maxLightsPerTile", cap}, {"maxLightsPerTileAuto", automatic}, {"frameMs", frameMs(row.m)}, {"cullMs", row.m.cullMs},
                                {"overflowTiles", culling ? culling->overflowTiles : 0}, {"droppedLights", culling ? culling->droppedLights : 0},
                                {"densestTileLights", culling ? culling->densestTileLights : 0},
                                {"maxAbsError", row.error.maxError}, {"meanAbsError", row.error.meanError}, {"naiveMs", row.referenceMs}};
            if (row.m.efficiency) j["efficiency"] = row.m.efficiency->ratio();
            json["tileKnobs"].push_back(j);
        }
    }
    md += "\n## Auto threshold suggestion (smallest light count where a tiled mode beats naive)\n\n";
    json["autoThreshold"] = nlohmann::json::object();
    for (const auto& [key, count] : threshold) {
        md += fmt::format("- {}: {}\n", key, count);
        json["autoThreshold"][key] = count;
    }
    if (threshold.empty()) md += "- none: tiled never beat naive at these counts\n";
    json["skipped"] = skipped;
    if (!skipped.empty()) {
        md += "\nSkipped:\n\n";
        for (const std::string& item : skipped) md += "- " + item + "\n";
    }

    // Plot: frame ms vs light count, one line per backend/path/mode.
    std::vector<PlotSeries> series;
    for (const Row& row : rows) {
        if (row.lights == 0) continue;   // log x
        const std::string name = fmt::format("{}/{} {}", row.backend, row.path, row.mode);
        seriesNamed(series, name).points.push_back({double(row.lights), frameMs(row.m)});
    }
    writeBenchOutputs(outDir, "forward", md, json, drawLogXPlot(series, "LIGHTS", "FRAME MS"));
    return 0;
}

}  // namespace

Command addBenchCommand(CLI::App& parent) {
    auto options = std::make_shared<BenchOptions>();
    CLI::App* app = parent.add_subcommand("bench", "Benchmarks; 'janus bench forward' measures Forward+ light culling, "
                                                   "'janus bench probes' the GGX prefilter's accuracy vs time, "
                                                   "'janus bench gi' the probe GI's accuracy vs time, "
                                                   "'janus bench shadows' the shadow map's accuracy vs time, "
                                                   "'janus bench msaa' anti-aliasing's accuracy vs time");
    CLI::App* forward = app->add_subcommand("forward", "Many-lights scene: naive / tiles-2d / tiles-depth on each path and backend; "
                                                       "writes forward.md, forward.json, forward.png and cutoff-error-<backend>-<path>.png (where the smallest "
                                                       "cut-off's error is, white = its largest) to --out");
    app->require_subcommand(1);
    forward->add_option("--lights", options->lights, "Comma-separated local-light counts")->default_str(options->lights);
    forward->add_option("--modes", options->modes, "Comma-separated culling modes")->default_str(options->modes);
    forward->add_option("--paths", options->paths, "Comma-separated feature paths")->default_str(options->paths);
    forward->add_option("--backends", options->backends, "Comma-separated backends")->default_str(options->backends);
    forward->add_option("--cutoffs", options->cutoffs, "Intensity cut-offs (lux) whose error is measured")->default_str(options->cutoffs);
    forward->add_option("--tile-sizes", options->tileSizes, "Tile sizes (px, powers of two 16..256) timed at the largest light count, with the automatic list cap")
        ->default_str(options->tileSizes);
    forward->add_option("--tile-caps", options->tileCaps, "Lights-per-tile caps (1..1024) timed at the largest light count, with the error "
                                                          "a full list makes")
        ->default_str(options->tileCaps);
    addSizeOption(*forward, options->size);
    forward->add_option("--frames", options->frames, "Measured frames per row (median)")->default_str("5");
    forward->add_option("--warmup", options->warmup, "Frames rendered before measuring")->default_str("2");
    forward->add_option("--out,-o", options->out, "Output directory; required")->type_name("DIR");
    forward->add_flag("--quick", options->quick,
                      "Tiny run for tests: 64x64, lights 0,64, one frame after one warm-up, cut-off 0.01, tiles 16 and 64 px, caps 4 "
                      "and 256; options given explicitly win");
    addGLPlatformOption(*forward, options->glPlatform);
    app->footer(kExitCodeHelp);
    forward->footer(kExitCodeHelp);
    std::function<int()> runProbes = addBenchProbesCommand(*app);
    std::function<int()> runGi = addBenchGiCommand(*app);
    std::function<int()> runShadows = addBenchShadowsCommand(*app);
    std::function<int()> runMsaa = addBenchMsaaCommand(*app);
    CLI::App* gi = app->get_subcommand("gi");
    CLI::App* shadows = app->get_subcommand("shadows");
    CLI::App* msaa = app->get_subcommand("msaa");
    return {app, [options, forward, gi, shadows, msaa, runProbes, runGi, runShadows, runMsaa] {
                if (forward->parsed()) {
                    for (const char* name : {"--lights", "--cutoffs", "--size", "--frames", "--warmup", "--tile-sizes", "--tile-caps"})
                        if (forward->count(name) > 0) options->given.insert(name);
                    return runForward(*options);
                }
                if (shadows->parsed()) return runShadows();
                if (msaa->parsed()) return runMsaa();
                return gi->parsed() ? runGi() : runProbes();
            }};
}

}  // namespace janus::cli
