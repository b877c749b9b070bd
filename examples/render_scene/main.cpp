// render_scene: renders one scene on two configurations (backend and feature path, chosen at run
// time) and checks that they agree pixel by pixel, as a port to a GL-only device would.
//
//   render_scene [SCENE.gltf|.glb|.json] [--a vulkan/compute] [--b gles/fallback] [--size 128]
//                [--out DIR]
//
// Without a scene it renders the built-in default scene. Writes DIR/a.png, DIR/b.png and
// DIR/difference.png (default DIR: the current folder) and prints each frame's passes and their
// cost. Exit codes: 0 the images agree; 1 they do not; 2 usage; 3 the scene cannot be loaded or an
// image written; 4 a backend is missing here; 5 another error.
#include <janus/renderer/parity.h>
#include <janus/renderer/renderer.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace {

using namespace janus;

struct Configuration {
    rhi::Backend backend = rhi::Backend::Vulkan;
    renderer::FeaturePath path = renderer::FeaturePath::Compute;
    std::string name() const { return std::string(rhi::toString(backend)) + "/" + renderer::toString(path); }
};

std::optional<Configuration> parseConfiguration(std::string_view text) {
    const size_t slash = text.find('/');
    if (slash == std::string_view::npos) return std::nullopt;
    const std::optional<rhi::Backend> backend = rhi::parseBackend(text.substr(0, slash));
    const std::optional<renderer::FeaturePath> path = renderer::parseFeaturePath(text.substr(slash + 1));
    if (!backend || !path) return std::nullopt;
    return Configuration{*backend, *path};
}

struct Options {
    std::optional<std::filesystem::path> scene;
    Configuration a{rhi::Backend::Vulkan, renderer::FeaturePath::Compute};
    Configuration b{rhi::Backend::GLES, renderer::FeaturePath::Fallback};   // ES 3.0: no compute
    uint32_t size = 128;
    std::filesystem::path out = ".";
};

int usage(const std::string& problem) {
    std::fprintf(stderr, "render_scene: %s\nusage: render_scene [SCENE] [--a BACKEND/PATH] [--b BACKEND/PATH] [--size N] "
                         "[--out DIR]\n  BACKEND: vulkan, gl, gles; PATH: compute, fallback\n", problem.c_str());
    return 2;
}

// The options, or nullopt with `problem` saying what is wrong with the command line.
std::optional<Options> parse(int argc, char** argv, std::string& problem) {
    Options options;
    for (int i = 1; i < argc; ++i) {
        const std::string_view argument = argv[i];
        const char* value = i + 1 < argc ? argv[i + 1] : nullptr;
        if ((argument == "--a" || argument == "--b") && value) {
            const std::optional<Configuration> configuration = parseConfiguration(value);
            if (!configuration) problem = std::string("'") + value + "' is not BACKEND/PATH";
            else (argument == "--a" ? options.a : options.b) = *configuration;
            ++i;
        } else if (argument == "--size" && value) {
            char* end = nullptr;
            const unsigned long size = std::strtoul(value, &end, 10);
            if (*end != '\0' || size < 8 || size > 4096) problem = std::string("--size takes 8 to 4096 pixels, got '") + value + "'";
            options.size = uint32_t(size);
            ++i;
        } else if (argument == "--out" && value) {
            options.out = value;
            ++i;
        } else if (!argument.starts_with("--") && !options.scene) {
            options.scene = std::filesystem::path(argument);
        } else {
            problem = std::string("unexpected argument '") + std::string(argument) + "'";
        }
        if (!problem.empty()) return std::nullopt;
    }
    return options;
}

struct Rendered {
    renderer::ImageRGBA8 image;   // tonemapped, sRGB: what PNGs and parity use
    rhi::DeviceInfo device;       // which driver made it (parity asks whether two share a compiler)
};

// One frame of `scene` on `configuration`, with the frame's passes printed.
Rendered render(const renderer::Scene& scene, const Configuration& configuration, uint32_t size) {
    const std::unique_ptr<rhi::IDevice> device = rhi::createDevice(rhi::DeviceDesc().setBackend(configuration.backend));
    // Capabilities are queried, not assumed: the compute path needs compute (ES 3.0 has none).
    if (configuration.path == renderer::FeaturePath::Compute) device->require(rhi::Capability::Compute, configuration.name());
    renderer::RenderSettings settings;
    settings.width = settings.height = size;
    settings.path = configuration.path;
    // Uploads the scene; throws RendererError for settings the device cannot honour, naming why.
    renderer::Renderer renderer(*device, scene, settings);
    renderer::FrameReport report = renderer.renderFrame();
    // Reflection probes are updated over several frames (time slicing): render until they are done.
    while (renderer.probesPending() || renderer.irradiancePending()) report = renderer.renderFrame();
    std::printf("%s on %s: %zu passes\n", configuration.name().c_str(), device->info().deviceName.c_str(), report.passes.size());
    for (const renderer::PassReport& pass : report.passes) {
        std::printf("  %-28s %4u draws %3u dispatches  cpu %.3f ms", pass.name.c_str(), pass.draws, pass.dispatches, pass.cpuMs);
        if (pass.gpuMs) std::printf("  gpu %.3f ms", *pass.gpuMs);   // nullopt where the device has no timers
        std::printf("\n");
    }
    return {renderer.readDisplayImage(), device->info()};
}

}  // namespace

int main(int argc, char** argv) {
    std::string problem;
    const std::optional<Options> options = parse(argc, argv, problem);
    if (!options) return usage(problem);
    renderer::Scene scene;
    try {
        scene = options->scene ? renderer::loadScene(*options->scene) : renderer::defaultScene();
    } catch (const std::exception& error) {   // SceneError (and image errors): names the file and the problem
        std::fprintf(stderr, "render_scene: %s\n", error.what());
        return 3;
    }
    try {
        const Rendered renderedA = render(scene, options->a, options->size);
        const Rendered renderedB = render(scene, options->b, options->size);
        const renderer::ImageRGBA8& a = renderedA.image;
        const renderer::ImageRGBA8& b = renderedB.image;
        std::filesystem::create_directories(options->out);
        renderer::writePNG(options->out / "a.png", a);   // written atomically
        renderer::writePNG(options->out / "b.png", b);
        renderer::writePNG(options->out / "difference.png", renderer::differenceHeatmap(a, b));
        // The parity rule of Janus's own suite: within 1 step of 1/255, but for a few edge pixels; and
        // where two shader compilers made the images (NVIDIA's GL and Vulkan), a few rounding pixels.
        renderer::ParityRule rule;
        if (!renderer::shareShaderCompiler(renderedA.device, renderedB.device)) rule = renderer::withCompilerRounding(rule);
        const renderer::ParityVerdict verdict = renderer::judgeParity(a, b, rule);
        std::printf("%s vs %s: %s\n", options->a.name().c_str(), options->b.name().c_str(),
                    verdict.agrees ? "agree" : verdict.problem.c_str());
        return verdict.agrees ? 0 : 1;
    } catch (const rhi::Error& error) {
        std::fprintf(stderr, "render_scene: %s\n", error.what());   // what() starts with the code
        const bool unavailable = error.code() == rhi::ErrorCode::BackendUnavailable || error.code() == rhi::ErrorCode::UnsupportedCapability;
        return unavailable ? 4 : 5;
    } catch (const renderer::ImageIOError& error) {
        std::fprintf(stderr, "render_scene: %s\n", error.what());
        return 3;
    } catch (const std::exception& error) {   // RendererError: what the device cannot do, and why
        std::fprintf(stderr, "render_scene: %s\n", error.what());
        return 5;
    }
}
