// `janus render`: one scene, one configuration, PNG (+ optional HDR and JSON report).
#include <cctype>
#include <cstdio>
#include <memory>

#include <fmt/format.h>

#include "cli_common.h"

namespace janus::cli {
namespace {

constexpr uint32_t kMaxRenderFrames = 1000;

struct RenderOptions {
    std::string scene;
    std::string backend = "vulkan";
    std::string path = "compute";
    std::string size = "256x256";
    std::string out;
    std::string hdr;
    std::string report;
    std::string glPlatform = "egl";
    bool validation = false;
    bool allowOutsidePaths = false;
    std::string debug;
    std::string giBake;
    LightingOptions lighting;
    MultisamplingOptions msaa;
    uint32_t frames = 1;
    EnvironmentOptions environment;
    AnimationOptions animation;
    SceneChoiceOptions sceneChoice;
};

bool hasExtension(const std::filesystem::path& file, std::string_view extension) { return lowerCaseExtension(file) == extension; }

int run(const RenderOptions& options) {
    // Everything that can be checked without a GPU is checked first, so a typo never costs a render.
    RenderRequest request;
    request.backend = parseBackendOption(options.backend);
    request.path = parsePathOption(options.path);
    request.glPlatform = parseGLPlatformOption(options.glPlatform);
    request.size = parseSize(options.size);
    request.validation = options.validation;
    request.lighting = parseLightingOptions(options.lighting);
    applyMultisamplingOptions(options.msaa, request);
    if (options.frames < 1 || options.frames > kMaxRenderFrames)
        throw UsageError(fmt::format("--frames {} is not allowed; render 1..{} frames", options.frames, kMaxRenderFrames));
    request.frames = options.frames;
    if (!options.debug.empty()) request.debugView = parseDebugOption(options.debug);
    if (!options.giBake.empty()) {
        request.giBakeFile = options.giBake;
        std::error_code ec;
        if (!std::filesystem::is_regular_file(request.giBakeFile, ec))
            throw UsageError(fmt::format("--gi-bake '{}' is not a file; make one with janus bake SCENE --out FILE", options.giBake));
    }

    if (options.out.empty()) throw UsageError("--out FILE.png is required: where to write the rendered image");
    const std::filesystem::path outPath = options.out;
    if (!hasExtension(outPath, ".png"))
        throw UsageError(fmt::format("--out '{}' must name a .png file", options.out));
    checkOutputFile(outPath, "--out");
    std::optional<std::filesystem::path> hdrPath;
    if (!options.hdr.empty()) {
        hdrPath = options.hdr;
        if (!hasExtension(*hdrPath, ".exr") && !hasExtension(*hdrPath, ".pfm"))
            throw UsageError(fmt::format("--hdr '{}' must name a .exr or .pfm file", options.hdr));
        checkOutputFile(*hdrPath, "--hdr");
        request.wantHdr = true;
    }
    std::optional<std::filesystem::path> reportPath;
    if (!options.report.empty()) {
        reportPath = options.report;
        checkOutputFile(*reportPath, "--report");
    }
    const EnvironmentOverride environment = parseEnvironmentOptions(options.environment);
    const AnimationOverride animation = parseAnimationOptions(options.animation);
    std::optional<std::filesystem::path> scenePath;
    if (!options.scene.empty()) scenePath = options.scene;
    // No output may replace another or an input (the scene, what it reads, the sky, the bake).
    std::vector<NamedPath> inputs = sceneInputFiles(scenePath);
    if (environment.map) inputs.emplace_back("the --env file", *environment.map);
    if (!request.giBakeFile.empty()) inputs.emplace_back("the --gi-bake file", request.giBakeFile);
    checkOutputsDistinct({{"--out", outPath}, {"--hdr", hdrPath.value_or("")}, {"--report", reportPath.value_or("")}}, inputs);

    renderer::Scene scene = loadSceneOrDefault(scenePath, parseSceneLoadOptions(options.sceneChoice, options.allowOutsidePaths));
    applyEnvironmentOverride(scene, environment);
    loadEnvironmentImage(scene, environment.map.has_value(), sceneLabel(scenePath));   // exit 3 for a sky it cannot read
    checkLightingOptions(request.lighting, scene, sceneLabel(scenePath));
    applyAnimationOverride(scene, animation, sceneLabel(scenePath));
    if (!scene.irradianceVolume && !request.giBakeFile.empty())
        throw InputError(fmt::format("--gi-bake '{}': {} has no irradiance volume for a bake to fill; give the scene the bake was made "
                                     "for, or leave --gi-bake out",
                                     request.giBakeFile.string(), sceneLabel(scenePath)));
    if (scene.irradianceVolume && request.giBakeFile.empty())
        std::fprintf(stderr, "janus: note: baking the scene's irradiance volume now (the gi-bake pass); janus bake SCENE --out FILE "
                             "saves a bake that --gi-bake FILE reuses\n");
    const RenderOutcome outcome = renderConfiguration(scene, request);

    const bool validationFailed =
        reportDebugMessages(configurationLabel(request.backend, request.path), outcome.debugMessages);

    renderer::writePNG(outPath, outcome.display);
    if (hdrPath) {
        if (hasExtension(*hdrPath, ".exr"))
            renderer::writeEXR(*hdrPath, *outcome.hdr);
        else
            renderer::writePFM(*hdrPath, *outcome.hdr);
    }
    if (reportPath) {
        nlohmann::json report = outcome.report.toJson();
        report["sceneWarnings"] = scene.warnings;   // what the loader ignored (also printed on stderr when it loaded)
        report["frames"] = outcome.frames;          // the report is the last of these frames'
        renderer::writeFileAtomically(*reportPath, jsonFileText(report));
    }

    std::printf("rendered %s with %s at %ux%u on %s\n", sceneLabel(scenePath).c_str(),
                configurationLabel(request.backend, request.path).c_str(), request.size.width, request.size.height,
                outcome.device.deviceName.c_str());
    std::printf("  image:  %s\n", outPath.c_str());
    if (hdrPath) std::printf("  hdr:    %s\n", hdrPath->c_str());
    if (reportPath) std::printf("  report: %s\n", reportPath->c_str());
    if (const std::string pose = poseLine(scene); !pose.empty()) std::printf("  pose:   %s\n", pose.c_str());
    if (const std::string culling = lightCullingLine(outcome.report); !culling.empty()) std::printf("  %s\n", culling.c_str());
    if (outcome.frames > options.frames)
        std::printf("  frames: %u (until every reflection probe was shown; passes below are the last frame's)\n", outcome.frames);
    else if (outcome.frames > 1)
        std::printf("  frames: %u (--frames; passes below are the last frame's)\n", outcome.frames);
    std::printf("\n");
    printPassSummary(outcome.report);
    // The first frame pays for first use (pipelines, target memory): an msaa-resolve took 40 ms
    // there on llvmpipe and 0.7 ms after it (docs/LIGHTING.md, "Anti-aliasing").
    if (outcome.frames == 1)
        std::printf("  (the first frame: its times include first use; --frames 3 shows a later frame's)\n");
    printProbeUpdates(outcome.report.probeUpdates);
    printPerformanceMessages(outcome.report.performanceMessages);

    if (validationFailed)
        throw std::runtime_error("the validation layer / GL debug output reported errors (listed above); "
                                 "the image was written but may be wrong");
    return 0;
}

}  // namespace

Command addRenderCommand(CLI::App& parent) {
    auto options = std::make_shared<RenderOptions>();
    CLI::App* app = parent.add_subcommand("render", "Render a scene with one backend and feature path to a PNG "
                                                    "(+ optional HDR image and JSON frame report)");
    addSceneArgument(*app, options->scene);
    addAllowOutsidePathsFlag(*app, options->allowOutsidePaths);
    app->add_option("--backend,-b", options->backend, "vulkan, gl or gles")->default_str("vulkan")->type_name("BACKEND");
    app->add_option("--path,-p", options->path, "compute or fallback (compute needs the 'compute' capability)")
        ->default_str("compute")
        ->type_name("PATH");
    addSizeOption(*app, options->size);
    app->add_option("--out,-o", options->out, "PNG file to write (display image, sRGB); required")->type_name("FILE.png");
    app->add_option("--hdr", options->hdr, "Also write the linear HDR image (.exr or .pfm)")->type_name("FILE.exr|FILE.pfm");
    app->add_option("--report", options->report, "Also write the frame report as JSON")->type_name("FILE.json");
    addGLPlatformOption(*app, options->glPlatform);
    addLightingOptions(*app, options->lighting);
    addMultisamplingOptions(*app, options->msaa);
    app->add_option("--frames", options->frames,
                    "Frames to render (1..1000); the image, report and pass times are the last frame's, so 3 shows times "
                    "without the first frame's first-use costs")
        ->default_str("1")
        ->type_name("N");
    addEnvironmentOptions(*app, options->environment);
    addAnimationOptions(*app, options->animation);
    addSceneChoiceOptions(*app, options->sceneChoice);
    app->add_option("--debug", options->debug, "Debug view: none, tiles (heat map of lights per tile, blue to red; "
                                               "tiles at the cap white-hatched), gi (the irradiance volume's light alone and its probes) or "
                                               "gi-light (the volume's light without the probes), shadow (the main directional light's visibility "
                                               "from its shadow map, 0 black to 1 white)")
        ->type_name("VIEW");
    app->add_option("--gi-bake", options->giBake, "The scene's irradiance volume from this file (janus bake); default: bake at start-up")
        ->type_name("FILE");
    app->add_flag("--validation", options->validation,
                  "Enable Vulkan validation layers / GL debug output; errors make the command fail (exit 5)");
    app->footer(kExitCodeHelp);
    return {app, [options] { return run(*options); }};
}

}  // namespace janus::cli
