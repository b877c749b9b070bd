// `janus parity`: render every configuration and compare every pair pixel by pixel.
#include <cmath>
#include <cstdio>
#include <memory>

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
    std::string glPlatform = "egl";
    bool validation = false;
    bool allowOutsidePaths = false;
    LightingOptions lighting;
    EnvironmentOptions environment;
    AnimationOptions animation;
    SceneChoiceOptions sceneChoice;
};

int run(const ParityOptions& options) {
    RenderRequest base;
    base.size = parseSize(options.size);
    base.glPlatform = parseGLPlatformOption(options.glPlatform);
    base.validation = options.validation;
    base.lighting = parseLightingOptions(options.lighting);
    const uint32_t tolerance = parseTolerance(options.tolerance);
    if (options.out.empty()) throw UsageError("--out DIR is required: where to write the images and parity.json");

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
    applyAnimationOverride(scene, animation, sceneLabel(scenePath));

    std::filesystem::create_directories(outDir, ec);
    if (ec)
        throw InputError(fmt::format("cannot create --out directory '{}': {}; choose another path", options.out, ec.message()));
    checkOutputFile(outDir / "parity.json", "--out");

    std::printf("parity: %s at %ux%u, tolerance %u step(s)\n", sceneLabel(scenePath).c_str(), base.size.width,
                base.size.height, tolerance);
    if (const std::string pose = poseLine(scene); !pose.empty()) std::printf("pose: %s\n", pose.c_str());
    std::printf("\n");

    std::vector<ConfigurationResult> results;
    std::vector<std::vector<std::string>> configRows{{"configuration", "result", "image"}};
    for (const Configuration& config : kConfigurations) {
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
    for (const PairComparison& comparison : compareAllPairs(images, tolerance)) {
        const ConfigurationResult& a = results[comparison.a];
        const ConfigurationResult& b = results[comparison.b];
        const std::string pairName = fmt::format("{} vs {}", a.stem, b.stem);
        nlohmann::json pair{{"a", a.stem}, {"b", b.stem}};
        if (comparison.difference) {
            const renderer::ImageDifference& diff = *comparison.difference;
            const bool pairPassed = comparison.passed;
            const std::filesystem::path heatmap = outDir / fmt::format("diff-{}-vs-{}.png", a.stem, b.stem);
            renderer::writePNG(heatmap, renderer::differenceHeatmap(a.outcome->display, b.outcome->display, kHeatmapFullScaleSteps));
            pairRows.push_back({pairName, std::to_string(diff.maxChannelDifference), psnrText(diff.psnr),
                                fmt::format("{} / {}", diff.differingPixels, diff.totalPixels), pairPassed ? "ok" : "FAIL"});
            pair["compared"] = true;
            pair["maxChannelDifference"] = diff.maxChannelDifference;
            // JSON has no infinity: identical images say so explicitly and carry a null PSNR.
            pair["identical"] = std::isinf(diff.psnr);
            pair["psnr"] = std::isinf(diff.psnr) ? nlohmann::json(nullptr) : nlohmann::json(diff.psnr);
            pair["differingPixels"] = diff.differingPixels;
            pair["totalPixels"] = diff.totalPixels;
            pair["heatmap"] = heatmap.filename().string();
            pair["passed"] = pairPassed;
            passed = passed && pairPassed;
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
    std::fputs(formatTable(pairRows).c_str(), stdout);

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
            entry["report"] = r.outcome->report.toJson();
        }
        configsJson.push_back(std::move(entry));
    }
    nlohmann::json summary{{"scene", sceneLabel(scenePath)},
                                 {"width", base.size.width},
                                 {"height", base.size.height},
                                 {"tolerance", tolerance},
                                 {"heatmapFullScaleSteps", kHeatmapFullScaleSteps},
                                 {"passed", passed},
                                 {"configurations", configsJson},
                                 {"pairs", pairsJson}};
    if (scene.posedAnimation) {   // the pose the images show
        summary["animation"] = *scene.posedAnimation;
        summary["animationName"] = scene.animations[*scene.posedAnimation].name;
        summary["time"] = scene.posedTime;
    }
    const std::filesystem::path summaryPath = outDir / "parity.json";
    renderer::writeFileAtomically(summaryPath, summary.dump(2) + "\n");

    std::printf("\nparity %s; details in %s\n", passed ? "PASSED" : "FAILED", summaryPath.c_str());
    return passed ? 0 : static_cast<int>(ExitCode::ComparisonFailed);
}

}  // namespace

Command addParityCommand(CLI::App& parent) {
    auto options = std::make_shared<ParityOptions>();
    CLI::App* app = parent.add_subcommand(
        "parity",
        "Render all five configurations, compare every pair, write images, heat maps and parity.json; "
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
    addGLPlatformOption(*app, options->glPlatform);
    addLightingOptions(*app, options->lighting);
    addEnvironmentOptions(*app, options->environment);
    addAnimationOptions(*app, options->animation);
    addSceneChoiceOptions(*app, options->sceneChoice);
    app->add_flag("--validation", options->validation,
                  "Enable Vulkan validation layers / GL debug output; a configuration with errors fails");
    return {app, [options] { return run(*options); }};
}

}  // namespace janus::cli
