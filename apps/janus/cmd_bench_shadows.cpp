// `janus bench shadows [SCENE]`: accuracy vs time of the main directional light's shadow map
// (docs/SHADOWS.md, "Accuracy vs time"). Sweeps the map's size on each path and backend; per size
// the shadow-map pass's time, the forward pass's (which samples the map), and the error of the
// light's visibility (a `--debug shadow` frame's HDR) against the Embree reference
// (GiReference::lightVisibility): mean |error|, and the pixels on the wrong side of one half (light
// leaks, false shadows). A row without a shadow map says what shadows buy. Writes shadows.md,
// shadows.json, shadows.png, shadows-reference.png and shadows-error-<backend>-<path>.png (at the
// scene's own map size when the sweep has it, else at the sweep's largest).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
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

struct ShadowsOptions {
    std::string scene;
    std::string sizes = "256,512,1024,2048,4096";
    BenchTargets targets{"compute,fallback", "vulkan,gl,gles"};
    std::string size = "256x256";
    uint32_t runs = 5;
    bool allowOutsidePaths = false;
    bool quick = false;
    bool sizesGiven = false;
};

// Map sizes the sweep may ask for; a device's own limit (its largest 2D texture) skips a row.
constexpr uint32_t kMinMapSize = 16, kMaxMapSize = 16384;

struct Row {
    std::string backend, path;
    uint32_t mapSize = 0;      // 0: no shadow map (the light unshadowed)
    bool sceneDefault = false;  // the size the scene renders with
    double shadowMs = 0.0;     // the shadow-map pass, median over runs
    double forwardMs = 0.0;    // the forward pass (which samples the map), median over runs
    bool gpuTimed = true;
    renderer::VisibilityError error;
};

std::string percent(double value) { return fmt::format("{:.2f}", 100.0 * value); }

nlohmann::json errorJson(const renderer::VisibilityError& e) {
    return {{"meanAbsolute", e.meanAbsolute}, {"rmse", e.rmse}, {"wrongFraction", e.wrongFraction}, {"leakFraction", e.leakFraction},
            {"falseShadowFraction", e.falseShadowFraction}, {"compared", e.compared}};
}

// The reference as a picture: lit white, shadowed black, not compared (no surface, or one facing
// away from the light) dark blue.
renderer::ImageRGBA8 referencePicture(const renderer::ImageRGBAF& reference) {
    renderer::ImageRGBA8 image{reference.width, reference.height, std::vector<uint8_t>(size_t(reference.width) * reference.height * 4)};
    for (size_t i = 0; i < size_t(reference.width) * reference.height; ++i) {
        uint8_t* out = &image.pixels[i * 4];
        const float* in = &reference.pixels[i * 4];
        if (in[3] < 0.5f) out[0] = 16, out[1] = 16, out[2] = 48;
        else out[0] = out[1] = out[2] = in[0] >= 0.5f ? 255 : 0;
        out[3] = 255;
    }
    return image;
}

// Where a map is wrong: grey where it agrees (light grey lit, dark grey shadowed), red where it
// lets light through that the reference blocks, blue where it shadows what the reference lights,
// brighter the larger the difference; not compared pixels near black.
renderer::ImageRGBA8 errorPicture(const renderer::ImageRGBAF& rendered, const renderer::ImageRGBAF& reference) {
    renderer::ImageRGBA8 image{reference.width, reference.height, std::vector<uint8_t>(size_t(reference.width) * reference.height * 4)};
    for (size_t i = 0; i < size_t(reference.width) * reference.height; ++i) {
        uint8_t* out = &image.pixels[i * 4];
        const float expected = reference.pixels[i * 4], value = rendered.pixels[i * 4];
        out[3] = 255;
        if (reference.pixels[i * 4 + 3] < 0.5f) {
            out[0] = out[1] = out[2] = 12;
            continue;
        }
        const float difference = std::isfinite(value) ? value - expected : (expected < 0.5f ? 1.0f : -1.0f);
        const uint8_t grey = expected >= 0.5f ? 110 : 55;
        const float strength = std::min(1.0f, std::abs(difference));
        if (strength < 1.0f / 255.0f) {
            out[0] = out[1] = out[2] = grey;
            continue;
        }
        const uint8_t mixed = uint8_t(std::lround(grey * (1.0f - strength)));
        const uint8_t full = uint8_t(std::lround(grey + (255.0f - grey) * strength));
        out[0] = difference > 0.0f ? full : mixed;
        out[1] = mixed;
        out[2] = difference > 0.0f ? mixed : full;
    }
    return image;
}

int runShadows(const ShadowsOptions& options) {
    const auto [paths, backends] = parseBenchTargets(options.targets, options.quick, "compute");
    const std::vector<uint32_t> sizes =
        parseCountList(options.quick && !options.sizesGiven ? "64,512" : options.sizes, "--sizes", kMinMapSize, kMaxMapSize, true);
    if (options.runs < 1 || options.runs > 100) throw UsageError(fmt::format("--runs {} must be 1..100", options.runs));
    const ImageSize size = options.quick ? ImageSize{64, 64} : parseSize(options.size);
    const uint32_t runs = options.quick ? 1 : options.runs;
    const std::filesystem::path outDir = benchOutputDir(options.targets.out, "shadows");

    const std::optional<std::filesystem::path> scenePath =
        options.scene.empty() ? std::nullopt : std::optional<std::filesystem::path>(options.scene);
    const renderer::Scene scene = loadSceneOrDefault(scenePath, options.allowOutsidePaths);
    const std::optional<size_t> mainLight = renderer::mainDirectionalLight(scene);
    if (!mainLight)
        throw InputError(fmt::format("{} has no directional light that gives light: there is no shadow map to measure (add a "
                                     "KHR_lights_punctual directional light, or one in a scene file's \"lights\"; docs/SCENES.md)",
                                     sceneLabel(scenePath)));
    // The scene's own size (its "quality", else the default) is marked in the table; shadows are
    // measured even where the scene turns them off.
    const uint32_t sceneMapSize = *renderer::resolveLightingSettings({}, scene).shadowMapSize;
    const uint32_t pictureMapSize = std::find(sizes.begin(), sizes.end(), sceneMapSize) != sizes.end() ? sceneMapSize : sizes.back();
    {
        std::vector<std::string> outputs{"shadows.md", "shadows.json", "shadows.png", "shadows-reference.png"};
        for (rhi::Backend backend : backends)
            for (renderer::FeaturePath path : paths)
                outputs.push_back(fmt::format("shadows-error-{}-{}.png", rhi::toString(backend), renderer::toString(path)));
        checkFolderOutputs(outDir, "--out", outputs, sceneInputFiles(scenePath));
    }

    const auto referenceStart = std::chrono::steady_clock::now();
    const renderer::GiReference tracer(scene);
    const renderer::ImageRGBAF reference =
        tracer.lightVisibility(scene.camera, size.width, size.height, scene.lights[*mainLight].direction);
    const double referenceMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - referenceStart).count();
    const renderer::VisibilityError unshadowedError = renderer::compareVisibility(
        renderer::ImageRGBAF{size.width, size.height, std::vector<float>(size_t(size.width) * size.height * 4, 1.0f)}, reference);
    if (unshadowedError.compared == 0)
        throw InputError(fmt::format("{}: no surface in the camera's view faces the main directional light at {}x{}, so no pixel "
                                     "can show its shadow",
                                     sceneLabel(scenePath), size.width, size.height));
    // Said with the first measured row, so that a run in which nothing can run prints only its error.
    bool referenceShown = false;
    auto showReference = [&] {
        if (referenceShown) return;
        referenceShown = true;
        // Against an image lit everywhere, the leaks are the pixels the reference shadows.
        std::fprintf(stderr, "  reference: %ux%u, %llu pixels face the light, %.1f %% of them shadowed (%.0f ms)\n", size.width, size.height,
                     static_cast<unsigned long long>(unshadowedError.compared), 100.0 * unshadowedError.leakFraction, referenceMs);
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
            showReference();
            std::vector<renderer::Light> turnedLights = scene.lights;
            if (const std::optional<size_t> sun = renderer::mainDirectionalLight(scene))
                turnedLights[*sun].direction = glm::normalize(turnedLights[*sun].direction + glm::vec3(0.01f, 0.0f, 0.0f));
            // Without a map first: the light unshadowed, the error shadows remove.
            rows.push_back(Row{rhi::toString(backend), renderer::toString(path), 0, false, 0.0, 0.0, true, unshadowedError});
            for (uint32_t mapSize : sizes) {
                renderer::RenderSettings settings;
                settings.width = size.width, settings.height = size.height;
                settings.path = path;
                settings.lighting.shadows = true;
                settings.lighting.shadowMapSize = mapSize;
                settings.debugView = renderer::DebugView::Shadow;
                Row row{rhi::toString(backend), renderer::toString(path), mapSize, mapSize == sceneMapSize};
                std::optional<renderer::Renderer> renderer;
                try {
                    renderer.emplace(*device, scene, settings);
                } catch (const renderer::RendererError& e) {   // e.g. a map larger than the device's largest texture
                    skipped.push_back(fmt::format("{} {}: {}", configurationLabel(backend, path), mapSize, e.what()));
                    continue;
                }
                // Frame 0 pays for first use (pipeline compiles, the map's memory) and is not timed.
                // A static scene draws its map once (docs/SHADOWS.md): the sun turns by a hair
                // every other frame, so every frame draws it, and the last frame, whose image is
                // compared, has the scene's own sun.
                std::vector<double> shadowRuns, forwardRuns;
                for (uint32_t run = 0; run <= runs; ++run) {
                    renderer->setLights((runs - run) % 2 == 0 ? scene.lights : turnedLights);
                    const renderer::FrameReport report = renderer->renderFrame();
                    if (run == 0) continue;
                    double shadowMs = 0.0, forwardMs = 0.0;
                    for (const renderer::PassReport& pass : report.passes) {
                        const bool shadowPass = pass.name == "shadow-map", forwardPass = pass.name == "forward" && pass.view == "main";
                        if (!shadowPass && !forwardPass) continue;
                        if (!pass.gpuMs) row.gpuTimed = false;
                        (shadowPass ? shadowMs : forwardMs) += pass.gpuMs.value_or(pass.cpuMs);
                    }
                    shadowRuns.push_back(shadowMs);
                    forwardRuns.push_back(forwardMs);
                }
                row.shadowMs = median(shadowRuns);
                row.forwardMs = median(forwardRuns);
                const renderer::ImageRGBAF visibility = renderer->readHdrImage();
                row.error = renderer::compareVisibility(visibility, reference);
                if (mapSize == pictureMapSize)
                    renderer::writePNG(outDir / fmt::format("shadows-error-{}-{}.png", row.backend, row.path), errorPicture(visibility, reference));
                std::fprintf(stderr, "  %s map %5u: shadow pass %8.3f ms, forward %8.3f ms; mean error %6.2f %%, wrong %6.2f %% (leaks %.2f %%, false shadows %.2f %%)\n",
                             configurationLabel(backend, path).c_str(), mapSize, row.shadowMs, row.forwardMs, 100.0 * row.error.meanAbsolute,
                             100.0 * row.error.wrongFraction, 100.0 * row.error.leakFraction, 100.0 * row.error.falseShadowFraction);
                rows.push_back(std::move(row));
            }
        }
        reportDebugMessages(rhi::toString(backend), device->takeDebugMessages());
    }
    if (std::none_of(rows.begin(), rows.end(), [](const Row& r) { return r.mapSize > 0; }))
        throw UnavailableError(fmt::format("bench shadows: no configuration could run ({})", fmt::join(skipped, "; ")));
    renderer::writePNG(outDir / "shadows-reference.png", referencePicture(reference));

    // ---- Report ----
    const bool gpuTimed = std::all_of(rows.begin(), rows.end(), [](const Row& r) { return r.gpuTimed; });
    const char* unit = gpuTimed ? "GPU ms" : "ms";
    std::string md = fmt::format(
        "# Shadow map: accuracy vs time\n\n"
        "Scene: {}. Image: {}x{}, the `--debug shadow` frame's HDR: the main directional light's visibility through its shadow map "
        "(3x3 bilinear PCF taps, docs/SHADOWS.md). The scene's own map size ({}) is marked *.\n\n"
        "- **shadow pass**: the `shadow-map` pass, {}; **forward**: the forward pass, which samples the map ({} each; median of {} "
        "frame(s) after the first).\n"
        "- **mean error**: mean |visibility - reference| over the {} pixels whose surface faces the light ({:.1f} % of them in shadow): "
        "the share of the light's direct contribution that is wrong. **wrong**: pixels on the wrong side of one half, split into "
        "**leaks** (lit where the reference is shadowed) and **false shadows** (shadowed where it is lit).\n"
        "- Reference (`GiReference::lightVisibility`): one Embree ray from each pixel's surface towards the light, blocked by the "
        "casters the map draws ({:.0f} ms). The row without a map is the error shadows remove.\n\n",
        sceneLabel(scenePath), size.width, size.height, sceneMapSize, unit, unit, runs, unshadowedError.compared,
        100.0 * unshadowedError.leakFraction, referenceMs);
    nlohmann::json json = {{"scene", sceneLabel(scenePath)}, {"width", size.width}, {"height", size.height}, {"runs", runs},
                           {"gpuTimed", gpuTimed}, {"sceneMapSize", sceneMapSize}, {"pictureMapSize", pictureMapSize}, {"referenceMs", referenceMs},
                           {"comparedPixels", unshadowedError.compared}, {"configurations", nlohmann::json::array()}, {"skipped", skipped}};
    md += "| backend | path | map | shadow pass " + std::string(unit) + " | forward " + std::string(unit) +
          " | mean error % | RMSE % | wrong % | leaks % | false shadows % |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    std::vector<PlotSeries> series;
    for (const Row& r : rows) {
        const std::string map = r.mapSize == 0 ? std::string("none") : fmt::format("{}{}", r.mapSize, r.sceneDefault ? " *" : "");
        md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", r.backend, r.path, map,
                          r.mapSize == 0 ? std::string("-") : fmt::format("{:.3f}", r.shadowMs),
                          r.mapSize == 0 ? std::string("-") : fmt::format("{:.3f}", r.forwardMs), percent(r.error.meanAbsolute),
                          percent(r.error.rmse), percent(r.error.wrongFraction), percent(r.error.leakFraction),
                          percent(r.error.falseShadowFraction));
        nlohmann::json row = {{"backend", r.backend}, {"path", r.path}, {"mapSize", r.mapSize}, {"sceneDefault", r.sceneDefault},
                              {"error", errorJson(r.error)}};
        if (r.mapSize > 0) row["shadowMs"] = r.shadowMs, row["forwardMs"] = r.forwardMs;
        json["configurations"].push_back(row);
        // Plot: mean error against the shadow pass's time, one line per configuration.
        if (r.mapSize == 0 || !(r.shadowMs > 0.0) || !(r.error.meanAbsolute > 0.0)) continue;
        const std::string name = r.backend + "/" + r.path;
        seriesNamed(series, name).points.push_back({r.shadowMs, 100.0 * r.error.meanAbsolute});
    }

    // What the sweep says, per configuration: how the error falls with the map's size (the slope of
    // log error against log size, smallest to largest map: -1 when it is the texel size alone), and
    // what the last doubling of the size costs in time for what it gains in error.
    md += "\n## What it says\n\n";
    nlohmann::json summary = nlohmann::json::array();
    for (const Row& first : rows) {
        if (first.mapSize != 0) continue;
        std::vector<const Row*> measured;
        for (const Row& r : rows)
            if (r.backend == first.backend && r.path == first.path && r.mapSize > 0) measured.push_back(&r);
        if (measured.empty()) continue;
        const Row& smallest = *measured.front();
        const Row& largest = *measured.back();
        std::string line =
            measured.size() == 1
                ? fmt::format("- {}/{}: mean error {} % at map size {} (without a map {} %)", first.backend, first.path,
                              percent(smallest.error.meanAbsolute), smallest.mapSize, percent(first.error.meanAbsolute))
                : fmt::format("- {}/{}: mean error {} % at map size {}, {} % at {} (without a map {} %)", first.backend, first.path,
                              percent(smallest.error.meanAbsolute), smallest.mapSize, percent(largest.error.meanAbsolute),
                              largest.mapSize, percent(first.error.meanAbsolute));
        nlohmann::json entry = {{"backend", first.backend}, {"path", first.path}, {"smallestMap", smallest.mapSize}, {"largestMap", largest.mapSize},
                                {"smallestMeanError", smallest.error.meanAbsolute}, {"largestMeanError", largest.error.meanAbsolute},
                                {"unshadowedMeanError", first.error.meanAbsolute}};
        if (measured.size() >= 2 && smallest.error.meanAbsolute > 0.0 && largest.error.meanAbsolute > 0.0) {
            const double slope = std::log(largest.error.meanAbsolute / smallest.error.meanAbsolute) /
                                 std::log(double(largest.mapSize) / double(smallest.mapSize));
            const Row& previous = *measured[measured.size() - 2];
            const double timeRatio = largest.shadowMs / std::max(1e-9, previous.shadowMs);
            const double errorRatio = largest.error.meanAbsolute / std::max(1e-12, previous.error.meanAbsolute);
            line += fmt::format(": error ~ size^{:.2f}. The last step, {} -> {}, costs **{:.1f}x** the shadow pass ({:.3f} -> {:.3f} {}) for "
                                "**{:.2f}x** the error",
                                slope, previous.mapSize, largest.mapSize, timeRatio, previous.shadowMs, largest.shadowMs, unit, errorRatio);
            entry["errorSlope"] = slope;
            entry["lastStepTimeRatio"] = timeRatio;
            entry["lastStepErrorRatio"] = errorRatio;
        }
        md += line + ".\n";
        summary.push_back(entry);
    }
    json["summary"] = summary;
    // Surfaces the reference does not see as the rasteriser does: their pixels count as error at any size.
    uint32_t blended = 0, masked = 0;
    for (const renderer::Instance& instance : scene.instances) {
        const int32_t material = instance.mesh < scene.meshes.size() ? scene.meshes[instance.mesh].material : -1;
        if (material < 0 || size_t(material) >= scene.materials.size()) continue;
        blended += scene.materials[size_t(material)].alphaMode == renderer::AlphaMode::Blend;
        masked += scene.materials[size_t(material)].alphaMode == renderer::AlphaMode::Mask;
    }
    if (blended > 0 || masked > 0) {
        md += fmt::format("\nNote: {} blended and {} alpha-masked instance(s). The view shows a blended surface's own visibility where the "
                          "reference sees through it, and the reference hits masked surfaces where their cut-outs let the view "
                          "through: those pixels are error at every map size (docs/SHADOWS.md).\n",
                          blended, masked);
        json["blendedInstances"] = blended;
        json["maskedInstances"] = masked;
    }
    if (!skipped.empty()) {
        md += "\nSkipped:\n\n";
        for (const std::string& s : skipped) md += "- " + s + "\n";
    }
    md += fmt::format("\nPlot (shadows.png): mean visibility error (%) vs the shadow pass's {}, log-log, one line per configuration, "
                      "one point per map size. Pictures: shadows-reference.png (white lit, black shadowed, blue not compared) and "
                      "shadows-error-<backend>-<path>.png at map size {} (grey agrees, red leaks light, blue shadows too much).\n",
                      unit, pictureMapSize);
    writeBenchOutputs(outDir, "shadows", md, json, drawLogXPlot(series, fmt::format("SHADOW PASS {}", gpuTimed ? "GPU MS" : "MS"), "MEAN ERROR (PERCENT)"));
    return 0;
}

}  // namespace

std::function<int()> addBenchShadowsCommand(CLI::App& bench) {
    auto options = std::make_shared<ShadowsOptions>();
    CLI::App* shadows = bench.add_subcommand(
        "shadows", "Shadow map: error of the main directional light's visibility against an Embree reference vs the shadow "
                   "pass's time, per map size; writes shadows.md, shadows.json, shadows.png and pictures to --out");
    addSceneArgument(*shadows, options->scene);
    shadows->add_option("--sizes", options->sizes, "Comma-separated shadow map sizes (powers of two, 16..16384)")->default_str(options->sizes);
    shadows->add_option("--size", options->size, "Image size WxH")->default_str(options->size);
    shadows->add_option("--runs", options->runs, "Frames timed per map size (median)")->default_str("5");
    shadows->add_flag("--quick", options->quick,
                      "Tiny run for tests: 64x64, maps 64 and 512, 1 run, the compute path; --sizes and --paths given win");
    addAllowOutsidePathsFlag(*shadows, options->allowOutsidePaths);
    addBenchTargetOptions(*shadows, options->targets);
    shadows->footer(kExitCodeHelp);
    return [options, shadows] {
        noteBenchTargetsGiven(*shadows, options->targets);
        options->sizesGiven = shadows->count("--sizes") > 0;
        return runShadows(*options);
    };
}

}  // namespace janus::cli
