// `janus bake`: bakes a scene's irradiance volume to a file `janus render --gi-bake` reuses (docs/GI.md).
#include <cstdio>
#include <memory>

#include <fmt/format.h>

#include "cli_common.h"

namespace janus::cli {
namespace {

struct BakeOptions {
    std::string scene;
    std::string out;
    std::string backend = "vulkan";
    std::string glPlatform = "egl";
    bool allowOutsidePaths = false;
};

int run(const BakeOptions& options) {
    if (options.out.empty()) throw UsageError("--out FILE is required: where to write the bake");
    const std::filesystem::path outPath = options.out;
    checkOutputFile(outPath, "--out");
    const rhi::Backend backend = parseBackendOption(options.backend);
    const rhi::GLPlatform platform = parseGLPlatformOption(options.glPlatform);
    std::optional<std::filesystem::path> scenePath;
    if (!options.scene.empty()) scenePath = options.scene;
    checkOutputsDistinct({{"--out", outPath}}, sceneInputFiles(scenePath));   // never overwrite the scene or what it reads
    renderer::Scene scene = loadSceneOrDefault(scenePath, options.allowOutsidePaths);
    loadEnvironmentImage(scene, false, sceneLabel(scenePath));   // exit 3 for a sky it cannot read, before the device opens
    if (!scene.irradianceVolume)
        throw InputError(fmt::format("{} has no irradiance volume to bake; give its scene file an \"irradianceVolume\" (docs/SCENES.md) "
                                     "or its glTF a node named IrradianceVolume...",
                                     sceneLabel(scenePath)));
    std::unique_ptr<rhi::IDevice> device = rhi::createDevice(rhi::DeviceDesc{}.setBackend(backend).setGLPlatform(platform));
    const renderer::IrradianceBakeSummary summary = renderer::bakeIrradianceVolume(*device, scene, outPath);
    std::printf("baked the irradiance volume of %s on %s in %.0f ms\n", sceneLabel(scenePath).c_str(), rhi::toString(backend),
                summary.milliseconds);
    std::printf("  probes:    %u (%u valid, %u moved out of geometry)\n  surfels:   %llu\n  bricks:    %llu\n  transfers: %llu\n  file:      %s\n",
                summary.probes, summary.validProbes, summary.relocatedProbes, static_cast<unsigned long long>(summary.surfels), static_cast<unsigned long long>(summary.bricks),
                static_cast<unsigned long long>(summary.transfers), outPath.c_str());
    return 0;
}

}  // namespace

Command addBakeCommand(CLI::App& parent) {
    auto options = std::make_shared<BakeOptions>();
    CLI::App* app = parent.add_subcommand("bake", "Bake a scene's irradiance volume (GI probes) to a file for janus render --gi-bake");
    addSceneArgument(*app, options->scene);
    addAllowOutsidePathsFlag(*app, options->allowOutsidePaths);
    app->add_option("--out,-o", options->out, "Bake file to write (atomically); required")->type_name("FILE");
    app->add_option("--backend,-b", options->backend, "vulkan, gl or gles (the G-buffer is rendered there)")
        ->default_str("vulkan")
        ->type_name("BACKEND");
    addGLPlatformOption(*app, options->glPlatform);
    app->footer(kExitCodeHelp);
    return {app, [options] { return run(*options); }};
}

}  // namespace janus::cli
