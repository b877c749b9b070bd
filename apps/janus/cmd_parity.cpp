// `janus parity`: render every configuration and compare every pair pixel by pixel.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "configurations.h"

namespace janus::cli {
namespace {

struct ParityOptions {
    std::string scene;
    std::string size = "256x256";
    std::string out;
    std::string tolerance = "1";
    std::string edgePixels = std::to_string(kDefaultEdgePixels);
    std::string compilerRounding = "auto";
    std::string configs;                  // --configs
    bool configsGiven = false;            // else all five
    std::string against;                  // another machine's `janus parity --out` directory
    std::string againstTolerance = "1";
    bool againstToleranceGiven = false;
    std::string glPlatform = "egl";
    bool validation = false;
    bool allowOutsidePaths = false;
    LightingOptions lighting;
    MultisamplingOptions msaa;
    EnvironmentOptions environment;
    AnimationOptions animation;
    SceneChoiceOptions sceneChoice;
};

// Another machine's renders of the same configurations, compared with this run's image by image
// (`--against DIR`): cross-driver checks, where filtering and derivatives legitimately differ, so
// they carry their own tolerance.
struct AgainstDirectory {
    std::filesystem::path dir;
    uint32_t tolerance = 1;
    nlohmann::json summary;   // its parity.json, read once by checkAgainstSummary
};

std::optional<AgainstDirectory> parseAgainst(const ParityOptions& options) {
    if (options.against.empty()) {
        if (options.againstToleranceGiven)
            throw UsageError("--against-tolerance applies to --against DIR, which is not given; add --against or leave it out");
        return std::nullopt;
    }
    AgainstDirectory against{options.against, parseTolerance(options.againstTolerance, "--against-tolerance")};
    std::error_code ec;
    if (!std::filesystem::is_directory(against.dir, ec))
        throw InputError(fmt::format("--against '{}' is not a directory; give the --out directory of a janus parity run", options.against));
    if (!std::filesystem::exists(against.dir / "parity.json", ec))
        throw InputError(fmt::format("--against '{}' has no parity.json; give the --out directory of a janus parity run", options.against));
    return against;
}

// The other run's parity.json must describe renders this one can be compared with.
void checkAgainstSummary(AgainstDirectory& against, const std::string& scene, const ImageSize& size) {
    const std::filesystem::path path = against.dir / "parity.json";
    uint32_t width = 0, height = 0;
    std::string otherScene;
    try {
        std::ifstream file(path);
        against.summary = nlohmann::json::parse(file);
        const nlohmann::json& other = against.summary;
        width = other.at("width").get<uint32_t>();
        height = other.at("height").get<uint32_t>();
        otherScene = other.value("scene", std::string());
        // Every image the other run says it wrote must be there, or its configuration would
        // silently count as "not in --against".
        if (other.contains("configurations") && other["configurations"].is_array())
            for (const nlohmann::json& config : other["configurations"]) {
                if (!config.is_object() || !config.value("ran", false) || !config.contains("image") || !config["image"].is_string()) continue;
                const std::filesystem::path image = against.dir / config["image"].get<std::string>();
                std::error_code ec;
                if (!std::filesystem::is_regular_file(image, ec))
                    throw InputError(fmt::format("--against: {} lists {} as rendered, but '{}' is missing; copy that run's whole --out "
                                                 "directory",
                                                 path.string(), config["image"].get<std::string>(), image.string()));
            }
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(fmt::format("--against: cannot read {} as a janus parity summary: {}", path.string(), e.what()));
    }
    if (width != size.width || height != size.height)
        throw InputError(fmt::format("--against: {} was rendered at {}x{}, this run at {}x{}; use the same --size", path.string(), width,
                                     height, size.width, size.height));
    if (otherScene != scene)
        std::fprintf(stderr, "janus: warning: --against: %s rendered '%s', this run renders '%s'; comparing anyway\n", path.c_str(),
                     otherScene.c_str(), scene.c_str());
}

// One comparison's table row and JSON fields (`pair` or an --against entry): the heat map is written
// to `heatmap`. JSON has no infinity: identical images say so and carry a null PSNR.
void recordDifference(const std::string& name, const renderer::ImageRGBA8& a, const renderer::ImageRGBA8& b,
                      const renderer::ImageDifference& diff, uint32_t tolerance, bool passed, uint64_t roundingPixels,
                      const std::filesystem::path& heatmap, std::vector<std::vector<std::string>>& rows, nlohmann::json& entry) {
    renderer::writePNG(heatmap, renderer::differenceHeatmap(a, b, kHeatmapFullScaleSteps));
    rows.push_back({name, std::to_string(diff.maxChannelDifference), psnrText(diff.psnr),
                    fmt::format("{} / {}", diff.differingPixels, diff.totalPixels), pairResultText(diff, tolerance, passed, roundingPixels)});
    entry["compared"] = true;
    entry["maxChannelDifference"] = diff.maxChannelDifference;
    entry["identical"] = std::isinf(diff.psnr);
    entry["psnr"] = std::isinf(diff.psnr) ? nlohmann::json(nullptr) : nlohmann::json(diff.psnr);
    entry["differingPixels"] = diff.differingPixels;
    entry["totalPixels"] = diff.totalPixels;
    entry["heatmap"] = heatmap.filename().string();
    entry["passed"] = passed;
}

// Each configuration that ran against the same configuration's image in --against's directory:
// prints the table, returns parity.json's `against` and clears `passed` on a failure.
nlohmann::json compareAgainst(const AgainstDirectory& against, const std::vector<ConfigurationResult>& results,
                              const nlohmann::json& imageSettings, const std::filesystem::path& outDir, bool& passed) {
    // Settings that change every image (samples per pixel; checkAgainstSummary checked the size and
    // the scene): said, since the comparison below will then fail for a reason other than the driver.
    const nlohmann::json& other = against.summary;
    for (const auto& [key, ours] : imageSettings.items())
        if (other.is_object() && other.contains(key) && other[key] != ours)
            std::fprintf(stderr, "janus: warning: --against: %s rendered with %s %s, this run with %s; its images differ wherever "
                                 "that matters\n",
                         against.dir.c_str(), key.c_str(), other[key].dump().c_str(), ours.dump().c_str());
    std::vector<std::vector<std::string>> rows{
        {"configuration", "max diff", "PSNR dB", fmt::format("pixels > {} step(s)", against.tolerance), "result"}};
    nlohmann::json entries = nlohmann::json::array();
    bool anyCompared = false;
    for (const ConfigurationResult& r : results) {
        if (r.image.empty()) continue;   // did not run here: already a failure
        const std::filesystem::path theirs = against.dir / (r.stem + ".png");
        nlohmann::json entry{{"configuration", r.stem}, {"image", theirs.string()}};
        std::error_code missing;
        if (!std::filesystem::exists(theirs, missing)) {
            // The other machine may lack a backend: said, not a failure.
            rows.push_back({r.stem, "-", "-", "-", "not in --against"});
            entry["compared"] = false;
            entries.push_back(std::move(entry));
            continue;
        }
        const renderer::ImageRGBA8& ours = r.outcome->display;
        const renderer::ImageRGBA8 other = renderer::readPNG(theirs);
        if (other.width != ours.width || other.height != ours.height)
            throw InputError(fmt::format("--against: {} is {}x{}, this run's {} is {}x{}", theirs.string(), other.width, other.height,
                                         r.stem, ours.width, ours.height));
        const renderer::ImageDifference diff = renderer::compareImages(ours, other, against.tolerance);
        const bool ok = diff.differingPixels == 0;
        recordDifference(r.stem, ours, other, diff, against.tolerance, ok, 0, outDir / fmt::format("against-{}.png", r.stem), rows, entry);
        passed = passed && ok;
        anyCompared = true;
        entries.push_back(std::move(entry));
    }
    if (!anyCompared) passed = false;   // nothing in common: the comparison asked for did not happen
    std::printf("\nagainst %s (tolerance %u step(s)):\n", against.dir.c_str(), against.tolerance);
    std::fputs(formatTable(rows).c_str(), stdout);
    if (!anyCompared) std::printf("no configuration of this run has an image in --against: nothing was compared\n");
    return {{"dir", against.dir.string()}, {"tolerance", against.tolerance}, {"configurations", entries}};
}

// Every file a parity run writes in --out: parity.json, an image per configuration, a comparison
// per configuration with --against and a difference image per pair.
std::vector<std::string> parityOutputNames() {
    std::vector<std::string> names{"parity.json"};
    for (size_t i = 0; i < kConfigurations.size(); ++i) {
        const std::string stem = configurationFileStem(kConfigurations[i].backend, kConfigurations[i].path);
        names.push_back(stem + ".png");
        names.push_back(fmt::format("against-{}.png", stem));
        for (size_t k = i + 1; k < kConfigurations.size(); ++k)
            names.push_back(fmt::format("diff-{}-vs-{}.png", stem, configurationFileStem(kConfigurations[k].backend, kConfigurations[k].path)));
    }
    return names;
}

int run(const ParityOptions& options) {
    RenderRequest base;
    base.size = parseSize(options.size);
    base.glPlatform = parseGLPlatformOption(options.glPlatform);
    base.validation = options.validation;
    base.lighting = parseLightingOptions(options.lighting);
    applyMultisamplingOptions(options.msaa, base);
    const uint32_t tolerance = parseTolerance(options.tolerance);
    const uint64_t edgePixels = parseEdgePixels(options.edgePixels);
    const bool compilerRounding = parseCompilerRounding(options.compilerRounding);
    if (options.out.empty()) throw UsageError("--out DIR is required: where to write the images and parity.json");
    std::optional<AgainstDirectory> against = parseAgainst(options);
    const std::vector<Configuration> configurations =
        options.configsGiven ? parseConfigurations(options.configs)
                             : std::vector<Configuration>(kConfigurations.begin(), kConfigurations.end());

    const std::filesystem::path outDir = options.out;
    std::error_code ec;
    if (std::filesystem::exists(outDir, ec) && !std::filesystem::is_directory(outDir, ec))
        throw InputError(fmt::format("--out '{}' is a file; give a directory for the images", options.out));

    const EnvironmentOverride environment = parseEnvironmentOptions(options.environment);
    const AnimationOverride animation = parseAnimationOptions(options.animation);

    // The scene is loaded before the directory is created, so a bad scene leaves nothing behind.
    std::optional<std::filesystem::path> scenePath;
    if (!options.scene.empty()) scenePath = options.scene;
    renderer::Scene scene = loadSceneOrDefault(scenePath, parseSceneLoadOptions(options.sceneChoice, options.allowOutsidePaths));
    applyEnvironmentOverride(scene, environment);
    loadEnvironmentImage(scene, environment.map.has_value(), sceneLabel(scenePath));   // exit 3 for a sky it cannot read
    checkLightingOptions(base.lighting, scene, sceneLabel(scenePath));
    applyAnimationOverride(scene, animation, sceneLabel(scenePath));

    if (against) {
        checkAgainstSummary(*against, sceneLabel(scenePath), base.size);
        if (std::filesystem::equivalent(against->dir, outDir, ec))
            throw UsageError("--against and --out are the same directory; write this run's images elsewhere");
    }
    std::filesystem::create_directories(outDir, ec);
    if (ec)
        throw InputError(fmt::format("cannot create --out directory '{}': {}; choose another path", options.out, ec.message()));
    checkOutputFile(outDir / "parity.json", "--out");
    const std::vector<std::string> outputs = parityOutputNames();
    std::vector<NamedPath> inputs = sceneInputFiles(scenePath);
    if (environment.map) inputs.emplace_back("the --env file", *environment.map);
    if (against) {
        inputs.emplace_back("--against's summary", against->dir / "parity.json");
        for (const Configuration& config : kConfigurations)
            inputs.emplace_back("an --against image", against->dir / (configurationFileStem(config.backend, config.path) + ".png"));
    }
    checkFolderOutputs(outDir, "--out", outputs, inputs);
    // A previous run's images in the same --out must not pass for this run's: every file a parity
    // run writes besides parity.json (which is replaced) is removed first.
    for (const std::string& name : outputs)
        if (name != "parity.json") std::filesystem::remove(outDir / name, ec);

    std::printf("parity: %s at %ux%u, tolerance %u step(s), up to %llu edge pixel(s) beyond it, compiler rounding %s\n",
                sceneLabel(scenePath).c_str(), base.size.width, base.size.height, tolerance, static_cast<unsigned long long>(edgePixels),
                options.compilerRounding.c_str());
    if (const std::string pose = poseLine(scene); !pose.empty()) std::printf("pose: %s\n", pose.c_str());
    std::printf("\n");

    std::vector<ConfigurationResult> results;
    std::vector<std::vector<std::string>> configRows{{"configuration", "result", "image"}};
    for (const Configuration& config : configurations) {
        ConfigurationResult result = runConfiguration(scene, config, base);
        if (result.ran()) {
            result.image = outDir / (result.stem + ".png");
            renderer::writePNG(result.image, result.outcome->display);
            configRows.push_back({configurationLabel(config.backend, config.path), "rendered", result.image.string()});
        } else {
            configRows.push_back({configurationLabel(config.backend, config.path), "DID NOT RUN: " + result.failure, "-"});
        }
        results.push_back(std::move(result));
    }
    std::fputs(formatTable(configRows).c_str(), stdout);

    bool passed = true;
    nlohmann::json pairsJson = nlohmann::json::array();
    std::vector<std::vector<std::string>> pairRows{
        {"pair", "max diff", "PSNR dB", fmt::format("pixels > {} step(s)", tolerance), "result"}};
    std::vector<const renderer::ImageRGBA8*> images;
    for (const ConfigurationResult& r : results) images.push_back(r.image.empty() ? nullptr : &r.outcome->display);
    std::vector<const rhi::DeviceInfo*> devices;
    for (const ConfigurationResult& r : results) devices.push_back(compilerRounding && r.outcome ? &r.outcome->device : nullptr);
    for (const PairComparison& comparison : compareAllPairs(images, renderer::ParityRule{tolerance, edgePixels}, devices)) {
        const ConfigurationResult& a = results[comparison.a];
        const ConfigurationResult& b = results[comparison.b];
        const std::string pairName = fmt::format("{} vs {}", a.stem, b.stem);
        nlohmann::json pair{{"a", a.stem}, {"b", b.stem}};
        if (comparison.difference) {
            recordDifference(pairName, a.outcome->display, b.outcome->display, *comparison.difference, tolerance, comparison.passed,
                             comparison.roundingPixels,
                             outDir / fmt::format("diff-{}-vs-{}.png", a.stem, b.stem), pairRows, pair);
            pair["twoCompilers"] = comparison.twoCompilers;
            pair["roundingPixels"] = comparison.roundingPixels;
            passed = passed && comparison.passed;
        } else {
            const std::string missing = a.image.empty() ? a.stem : b.stem;
            pairRows.push_back({pairName, "-", "-", "-", fmt::format("FAIL (not compared: {} did not run)", missing)});
            pair["compared"] = false;
            pair["passed"] = false;
            passed = false;
        }
        pairsJson.push_back(std::move(pair));
    }
    std::printf("\n");
    if (pairRows.size() > 1)
        std::fputs(formatTable(pairRows).c_str(), stdout);
    else
        std::printf("one configuration: no pairs to compare\n");

    // --msaa, else what the scene's quality asked for (every configuration renders with the same).
    uint32_t msaaSamples = base.msaaSamples;
    bool alphaToCoverage = false;   // used: samples, and not turned off
    std::set<uint32_t> probeSamples;   // the reflection probes' captures' (--probe-msaa, else each probe's own)
    for (const ConfigurationResult& r : results) {
        if (msaaSamples == 0 && r.outcome) msaaSamples = r.outcome->report.msaaSamples;
        if (r.outcome) alphaToCoverage = r.outcome->report.alphaToCoverage;
        if (r.outcome)
            for (const renderer::ProbeUpdateReport& update : r.outcome->report.probeUpdates) probeSamples.insert(update.msaaSamples);
    }
    // What changes every image without changing the scene: --against warns where the other run differs.
    const nlohmann::json imageSettings{{"msaaSamples", std::max(msaaSamples, 1u)},
                                       {"alphaToCoverage", alphaToCoverage},
                                       {"probeCaptureSamples", probeSamples}};

    nlohmann::json againstJson;
    if (against) againstJson = compareAgainst(*against, results, imageSettings, outDir, passed);

    nlohmann::json configsJson = nlohmann::json::array();
    for (const ConfigurationResult& r : results) {
        nlohmann::json entry{{"backend", rhi::toString(r.config.backend)},
                             {"path", renderer::toString(r.config.path)},
                             {"ran", !r.image.empty()}};
        if (r.image.empty()) entry["error"] = r.failure;
        if (!r.image.empty()) entry["image"] = r.image.filename().string();
        if (r.outcome) {
            entry["device"] = r.outcome->device.deviceName;
            entry["apiVersion"] = r.outcome->device.apiVersion;
            // What a driver was told that changes images (NVIDIA GL's filtering): an --against
            // comparison across machines needs it.
            if (!r.outcome->device.driverSettings.empty()) entry["driverSettings"] = r.outcome->device.driverSettings;
            entry["report"] = r.outcome->report.toJson();
        }
        configsJson.push_back(std::move(entry));
    }
    nlohmann::json selected = nlohmann::json::array();
    for (const Configuration& config : configurations) selected.push_back(configurationFileStem(config.backend, config.path));
    nlohmann::json summary{{"scene", sceneLabel(scenePath)},
                                 {"selectedConfigurations", selected},
                                 {"width", base.size.width},
                                 {"height", base.size.height},
                                 {"msaaSamples", imageSettings["msaaSamples"]},
                                 {"alphaToCoverage", imageSettings["alphaToCoverage"]},
                                 {"probeCaptureSamples", imageSettings["probeCaptureSamples"]},
                                 {"tolerance", tolerance},
                                 {"edgePixels", edgePixels},
                                 {"compilerRounding", options.compilerRounding},
                                 {"heatmapFullScaleSteps", kHeatmapFullScaleSteps},
                                 {"passed", passed},
                                 {"configurations", configsJson},
                                 {"pairs", pairsJson}};
    if (against) summary["against"] = againstJson;
    if (scene.posedAnimation) {   // the pose the images show
        summary["animation"] = *scene.posedAnimation;
        summary["animationName"] = scene.animations[*scene.posedAnimation].name;
        summary["time"] = scene.posedTime;
    }
    const std::filesystem::path summaryPath = outDir / "parity.json";
    renderer::writeFileAtomically(summaryPath, jsonFileText(summary));

    std::printf("\nparity %s; details in %s\n", passed ? "PASSED" : "FAILED", summaryPath.c_str());
    return passed ? 0 : static_cast<int>(ExitCode::ComparisonFailed);
}

}  // namespace

Command addParityCommand(CLI::App& parent) {
    auto options = std::make_shared<ParityOptions>();
    CLI::App* app = parent.add_subcommand(
        "parity",
        "Render all five configurations (or --configs), compare every pair, write images, heat maps and parity.json; "
        "exit 1 if any pair differs beyond --tolerance");
    app->footer(std::string("Configurations: vulkan/compute, vulkan/fallback, gl/compute, gl/fallback, gles/fallback.\n\n") +
                kExitCodeHelp);
    addSceneArgument(*app, options->scene);
    addAllowOutsidePathsFlag(*app, options->allowOutsidePaths);
    addSizeOption(*app, options->size);
    app->add_option("--out,-o", options->out,
                    "Directory for <backend>-<path>.png, diff-<a>-vs-<b>.png and parity.json (created if missing); required")
        ->type_name("DIR");
    app->add_option("--tolerance,-t", options->tolerance,
                    "Largest allowed channel difference, in steps of 1/255, for a pair to agree")
        ->default_str("1")
        ->type_name("STEPS");
    addEdgePixelsOption(*app, options->edgePixels);
    addCompilerRoundingOption(*app, options->compilerRounding);
    app->add_option("--configs", options->configs,
                    "Render and compare only these configurations: a comma-separated list of vulkan/compute, "
                    "vulkan/fallback, gl/compute, gl/fallback, gles/fallback (or vulkan-compute, ...); all five by default. "
                    "Each runs in this process: --configs gl/compute,gles/fallback starts no Vulkan driver")
        ->type_name("LIST");
    app->add_option("--against", options->against,
                    "The --out directory of a parity run on another machine (same scene and --size): compare each "
                    "configuration's image with its image there")
        ->type_name("DIR");
    app->add_option("--against-tolerance", options->againstTolerance,
                    "Largest allowed channel difference, in steps of 1/255, against --against's images (drivers differ "
                    "in filtering and derivatives: see docs/CLI.md)")
        ->default_str("1")
        ->type_name("STEPS");
    addGLPlatformOption(*app, options->glPlatform);
    addLightingOptions(*app, options->lighting);
    addMultisamplingOptions(*app, options->msaa);
    addEnvironmentOptions(*app, options->environment);
    addAnimationOptions(*app, options->animation);
    addSceneChoiceOptions(*app, options->sceneChoice);
    app->add_flag("--validation", options->validation,
                  "Enable Vulkan validation layers / GL debug output; a configuration with errors fails");
    return {app, [options, app] {
                options->againstToleranceGiven = app->count("--against-tolerance") > 0;
                options->configsGiven = app->count("--configs") > 0;
                return run(*options);
            }};
}

}  // namespace janus::cli
