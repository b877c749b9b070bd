#include "cli_common.h"

#include <algorithm>
#include <cctype>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <new>
#include <system_error>
#include <sstream>

#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

#include "gltf_features.h"

namespace janus::cli {
namespace {

// Options whose empty value would otherwise read as "not given" (they hold a string that is
// parsed later): --env-intensity '' is a mistake to name, not the default.
const CLI::Validator kNotEmpty([](std::string& value) { return value.empty() ? std::string("is empty; give a value or leave the option out") : std::string(); },
                               "", "not empty");

int exitStatus(ExitCode code) { return static_cast<int>(code); }

// Library messages may span lines (driver logs); the contract is one line per error.
std::string singleLine(std::string_view text) {
    std::string line;
    line.reserve(text.size());
    for (char c : text) {
        if (c == '\n') {
            if (!line.empty() && line.back() != ' ') line += "; ";
        } else if (c != '\r') {
            line += c;
        }
    }
    while (!line.empty() && (line.back() == ' ' || line.back() == ';')) line.pop_back();
    return line;
}

std::optional<uint32_t> parseSide(std::string_view text, bool& tooLarge) {
    uint64_t value = 0;
    const char* begin = text.data();
    const char* end = text.data() + text.size();
    const auto [ptr, error] = std::from_chars(begin, end, value);
    if (error == std::errc::result_out_of_range) {
        tooLarge = true;
        return std::nullopt;
    }
    if (error != std::errc() || ptr != end || text.empty()) return std::nullopt;
    if (value > kMaxRenderSide) {
        tooLarge = true;
        return std::nullopt;
    }
    return uint32_t(value);
}

}  // namespace

void printError(std::string_view message) {
    std::fflush(stdout);   // keep stdout's progress lines before the error when both go to a terminal
    std::fprintf(stderr, "janus: error: %s\n", singleLine(message).c_str());
}

int runCommand(const std::function<int()>& body) {
    try {
        return body();
    } catch (const UsageError& e) {
        printError(e.what());
        return exitStatus(ExitCode::UsageError);
    } catch (const InputError& e) {
        printError(e.what());
        return exitStatus(ExitCode::InputError);
    } catch (const UnavailableError& e) {
        printError(e.what());
        return exitStatus(ExitCode::BackendUnavailable);
    } catch (const renderer::SceneError& e) {
        printError(fmt::format("scene: {}", e.what()));
        return exitStatus(ExitCode::InputError);
    } catch (const renderer::ImageIOError& e) {
        printError(e.what());
        return exitStatus(ExitCode::InputError);
    } catch (const renderer::GiBakeFileError& e) {
        printError(e.what());
        return exitStatus(ExitCode::InputError);
    } catch (const renderer::RendererError& e) {
        // The renderer throws this for settings the device cannot honour.
        printError(e.what());
        return exitStatus(ExitCode::BackendUnavailable);
    } catch (const rhi::Error& e) {
        switch (e.code()) {
            case rhi::ErrorCode::BackendUnavailable:
                printError(fmt::format("{} (run 'janus info' to see which backends work on this machine)", e.what()));
                return exitStatus(ExitCode::BackendUnavailable);
            case rhi::ErrorCode::UnsupportedCapability:
                printError(e.what());
                return exitStatus(ExitCode::BackendUnavailable);
            case rhi::ErrorCode::OutOfMemory:
                printError(fmt::format("the device ran out of memory: {} (try a smaller --size)", e.what()));
                return exitStatus(ExitCode::BackendUnavailable);
            default:
                printError(fmt::format("internal error: {} (please report this)", e.what()));
                return exitStatus(ExitCode::InternalError);
        }
    } catch (const std::bad_alloc&) {
        printError("internal error: out of host memory (try a smaller --size)");
        return exitStatus(ExitCode::InternalError);
    } catch (const std::exception& e) {
        printError(fmt::format("internal error: {} (please report this)", e.what()));
        return exitStatus(ExitCode::InternalError);
    } catch (...) {
        printError("internal error: unknown exception (please report this)");
        return exitStatus(ExitCode::InternalError);
    }
}

ImageSize parseSize(std::string_view text) {
    const size_t separator = text.find_first_of("xX");
    bool tooLarge = false;
    std::optional<uint32_t> width, height;
    if (separator != std::string_view::npos) {
        width = parseSide(text.substr(0, separator), tooLarge);
        height = parseSide(text.substr(separator + 1), tooLarge);
    }
    if (tooLarge)
        throw UsageError(fmt::format("--size '{}' is too large: each side must be at most {}; use a smaller size such as 256x256",
                                     text, kMaxRenderSide));
    if (!width || !height)
        throw UsageError(fmt::format("--size '{}' is not WIDTHxHEIGHT; give two whole numbers such as 256x256", text));
    if (*width == 0 || *height == 0)
        throw UsageError(fmt::format("--size '{}' is empty: width and height must be at least 1 (for example 256x256)", text));
    return {*width, *height};
}

rhi::Backend parseBackendOption(std::string_view text) {
    if (auto backend = rhi::parseBackend(text)) return *backend;
    throw UsageError(fmt::format("unknown backend '{}'; choose one of vulkan, gl, gles", text));
}

renderer::FeaturePath parsePathOption(std::string_view text) {
    if (auto path = renderer::parseFeaturePath(text)) return *path;
    throw UsageError(fmt::format("unknown --path '{}'; choose compute or fallback", text));
}

rhi::GLPlatform parseGLPlatformOption(std::string_view text) {
    if (auto platform = rhi::parseGLPlatform(text)) return *platform;
    throw UsageError(fmt::format("unknown --gl-platform '{}'; choose egl or osmesa", text));
}

void checkOutputFile(const std::filesystem::path& file, std::string_view optionName) {
    namespace fs = std::filesystem;
    if (file.empty()) throw UsageError(fmt::format("{} needs a file name", optionName));
    std::error_code ec;
    if (fs::is_directory(file, ec))
        throw InputError(fmt::format("{} '{}' is a directory; give a file name inside it", optionName, file.string()));
    const fs::path directory = file.has_parent_path() ? file.parent_path() : fs::path(".");
    if (!fs::exists(directory, ec))
        throw InputError(fmt::format("cannot write {} '{}': directory '{}' does not exist; create it or choose another path",
                                     optionName, file.string(), directory.string()));
    if (!fs::is_directory(directory, ec))
        throw InputError(fmt::format("cannot write {} '{}': '{}' is not a directory; choose another path",
                                     optionName, file.string(), directory.string()));
    if (::access(directory.c_str(), W_OK) != 0)
        throw InputError(fmt::format("cannot write {} '{}': directory '{}' is not writable; choose another path",
                                     optionName, file.string(), directory.string()));
}

std::string notRegularFileKind(const std::filesystem::path& file) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status status = fs::status(file, ec);
    switch (status.type()) {
        case fs::file_type::regular:
        case fs::file_type::not_found:
        case fs::file_type::none:
            return "";
        case fs::file_type::directory: return "a directory";
        case fs::file_type::fifo: return "a FIFO";
        case fs::file_type::character: return "a character device";
        case fs::file_type::block: return "a block device";
        case fs::file_type::socket: return "a socket";
        default: return "not a regular file";
    }
}

namespace {

// Where `path` really is: links, `..` and `.` resolved as far as the file system allows.
std::filesystem::path resolvedPath(const std::filesystem::path& path) {
    std::error_code ec;
    std::filesystem::path resolved = std::filesystem::weakly_canonical(path, ec);
    if (ec) resolved = std::filesystem::absolute(path, ec).lexically_normal();
    return resolved;
}

bool sameFile(const std::filesystem::path& a, const std::filesystem::path& b) {
    std::error_code ec;
    if (std::filesystem::equivalent(a, b, ec) && !ec) return true;   // also hard links
    return resolvedPath(a) == resolvedPath(b);
}

}  // namespace

void checkOutputsDistinct(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs) {
    for (size_t i = 0; i < outputs.size(); ++i) {
        if (outputs[i].second.empty()) continue;
        for (size_t k = i + 1; k < outputs.size(); ++k)
            if (!outputs[k].second.empty() && sameFile(outputs[i].second, outputs[k].second))
                throw UsageError(fmt::format("{} '{}' and {} '{}' are the same file; give each output a file of its own",
                                             outputs[i].first, outputs[i].second.string(), outputs[k].first, outputs[k].second.string()));
        for (const auto& [what, input] : inputs)
            if (!input.empty() && sameFile(outputs[i].second, input))
                throw UsageError(fmt::format("{} '{}' is {} '{}': writing it would overwrite an input; choose another path",
                                             outputs[i].first, outputs[i].second.string(), what, input.string()));
    }
}

void checkFolderOutputs(const std::filesystem::path& dir, std::string_view option, const std::vector<std::string>& names,
                        const std::vector<NamedPath>& inputs) {
    std::map<std::pair<dev_t, ino_t>, const NamedPath*> inputFiles;
    for (const NamedPath& input : inputs) {
        struct stat info {};
        if (!input.second.empty() && ::stat(input.second.c_str(), &info) == 0) inputFiles.emplace(std::pair(info.st_dev, info.st_ino), &input);
    }
    if (inputFiles.empty()) return;
    for (const std::string& name : names) {
        const std::filesystem::path output = dir / name;
        struct stat info {};
        if (::stat(output.c_str(), &info) != 0) continue;
        if (const auto found = inputFiles.find(std::pair(info.st_dev, info.st_ino)); found != inputFiles.end())
            throw UsageError(fmt::format("{} '{}' would overwrite '{}', which is {} '{}'; choose another {} folder", option, dir.string(),
                                         output.string(), found->second->first, found->second->second.string(), option));
    }
}

std::vector<NamedPath> sceneInputFiles(const std::optional<std::filesystem::path>& scenePath) {
    std::vector<NamedPath> files;
    std::error_code ec;
    if (!scenePath || !std::filesystem::exists(*scenePath, ec) || !notRegularFileKind(*scenePath).empty()) return files;
    files.emplace_back("the scene file", *scenePath);
    auto addGltf = [&files](const std::filesystem::path& gltf) {
        for (const std::filesystem::path& file : gltfReferencedFiles(gltf)) files.emplace_back("a file the glTF reads", file);
    };
    const std::string extension = lowerCaseExtension(*scenePath);
    if (extension == ".gltf" || extension == ".glb") {
        addGltf(*scenePath);
    } else if (extension == ".json") {
        std::ifstream in(*scenePath, std::ios::binary);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const nlohmann::json root = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
        if (!root.is_object()) return files;
        if (const auto gltf = root.find("gltf"); gltf != root.end() && gltf->is_string()) {
            const std::filesystem::path gltfPath = scenePath->parent_path() / gltf->get<std::string>();
            files.emplace_back("the scene's glTF", gltfPath);
            if (notRegularFileKind(gltfPath).empty()) addGltf(gltfPath);
        }
        if (const auto environment = root.find("environment"); environment != root.end() && environment->is_object())
            if (const auto map = environment->find("map"); map != environment->end() && map->is_string())
                files.emplace_back("the scene's environment map", scenePath->parent_path() / map->get<std::string>());
    }
    return files;
}

void addSceneArgument(CLI::App& app, std::string& scene) {
    app.add_option("scene", scene, ".gltf, .glb or .json scene file (extension in any case), or a built-in scene: many-lights[:N] (the "
                                   "many-lights hall with N local lights, 0..16384, default 128), probes (the reflection-probe scene) or "
                                   "gi-rooms (two rooms with probe GI); "
                                   "a file (not a folder) of that name wins (default: the built-in room)")
        ->type_name("SCENE");
}

void addAllowOutsidePathsFlag(CLI::App& app, bool& allow) {
    app.add_flag("--allow-outside-paths", allow,
                 "Let the glTF read buffers and images outside its folder (../ or absolute URIs); refused by default");
}

void addSizeOption(CLI::App& app, std::string& size) {
    app.add_option("--size,-s", size, fmt::format("Image size WIDTHxHEIGHT, each side 1..{}", kMaxRenderSide))
        ->default_str("256x256")
        ->type_name("WxH");
}

void addGLPlatformOption(CLI::App& app, std::string& glPlatform) {
    app.add_option("--gl-platform", glPlatform, "How the gl/gles backends get a context: egl (the display from "
                   "JANUS_EGL_PLATFORM / JANUS_EGL_DEVICE, else the first that works) or osmesa (if installed)")
        ->default_str("egl")
        ->type_name("PLATFORM");
}

void addBenchTargetOptions(CLI::App& app, BenchTargets& targets) {
    app.add_option("--paths", targets.paths, "Comma-separated feature paths")->default_str(targets.paths);
    app.add_option("--backends", targets.backends, "Comma-separated backends")->default_str(targets.backends);
    app.add_option("--out,-o", targets.out, "Output directory; required")->type_name("DIR");
    addGLPlatformOption(app, targets.glPlatform);
}

void noteBenchTargetsGiven(const CLI::App& app, BenchTargets& targets) {
    targets.pathsGiven = app.count("--paths") > 0;
    targets.backendsGiven = app.count("--backends") > 0;
}

BenchConfigurations parseBenchTargets(const BenchTargets& targets, bool quick, const std::string& quickPaths,
                                      const std::string& quickBackends) {
    BenchConfigurations configurations;
    for (const std::string& item : splitList(quick && !targets.pathsGiven && !quickPaths.empty() ? quickPaths : targets.paths))
        configurations.paths.push_back(parsePathOption(item));
    for (const std::string& item : splitList(quick && !targets.backendsGiven && !quickBackends.empty() ? quickBackends : targets.backends))
        configurations.backends.push_back(parseBackendOption(item));
    if (configurations.paths.empty() || configurations.backends.empty())
        throw UsageError("--paths and --backends need at least one entry each");
    return configurations;
}

std::optional<uint32_t> parseManyLightsSceneName(std::string_view text) {
    if (text.substr(0, kManyLightsSceneName.size()) != kManyLightsSceneName) return std::nullopt;
    std::string_view rest = text.substr(kManyLightsSceneName.size());
    if (rest.empty()) return renderer::ManyLightsOptions{}.lightCount;
    if (rest[0] != ':') return std::nullopt;
    rest.remove_prefix(1);
    uint32_t count = 0;
    const auto [end, error] = std::from_chars(rest.data(), rest.data() + rest.size(), count);
    if (error != std::errc() || end != rest.data() + rest.size() || rest.empty() || count > 16384)
        throw UsageError(fmt::format("scene '{}': the built-in many-lights scene takes a light count 0..16384, "
                                     "as in many-lights:512", text));
    return count;
}

namespace {
// A built-in scene's name, unless a regular file (or a link to one) of that name is there: a
// folder named "probes" (say, for output) does not hide the built-in scene.
bool namesBuiltInScene(const std::filesystem::path& scenePath) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(scenePath, ec)) return false;
    return parseManyLightsSceneName(scenePath.string()) || scenePath.string() == kProbesSceneName || scenePath.string() == kGiRoomsSceneName;
}
}  // namespace

renderer::Scene loadSceneOrDefault(const std::optional<std::filesystem::path>& scenePath, const renderer::SceneLoadOptions& options) {
    std::error_code ec;
    const bool builtIn = !scenePath || namesBuiltInScene(*scenePath);
    if (builtIn && (options.scene || options.camera))
        throw UsageError(fmt::format("{} picks a glTF file's scene or camera; the {} has one of each, give a .gltf, .glb or .json scene",
                                     options.scene ? "--scene" : "--camera", sceneLabel(scenePath)));
    if (!scenePath) return renderer::defaultScene();
    if (builtIn) {
        if (const std::optional<uint32_t> lights = parseManyLightsSceneName(scenePath->string())) {
            renderer::ManyLightsOptions options;
            options.lightCount = *lights;
            return renderer::manyLightsScene(options);
        }
        if (scenePath->string() == kGiRoomsSceneName) return renderer::giRoomsScene();
        return renderer::probesScene();
    }
    if (!std::filesystem::exists(*scenePath, ec))
        throw InputError(fmt::format("scene file '{}' does not exist; give a .gltf, .glb or .json scene, "
                                     "or leave it out to use the built-in scene", scenePath->string()));
    if (std::filesystem::is_directory(*scenePath, ec))
        throw InputError(fmt::format("scene '{}' is a directory; give the .gltf, .glb or .json file inside it",
                                     scenePath->string()));
    if (const std::string kind = notRegularFileKind(*scenePath); !kind.empty())
        throw InputError(fmt::format("scene '{}' is {}, not a regular file; give a .gltf, .glb or .json file", scenePath->string(), kind));
    return renderer::loadScene(*scenePath, options);
}

void addSceneChoiceOptions(CLI::App& app, SceneChoiceOptions& options) {
    app.add_option("--scene", options.scene, "Which glTF scene to render: its index in the file's \"scenes\" (default: the file's "
                                             "\"scene\", else 0)")
        ->type_name("N")
        ->check(kNotEmpty);
    app.add_option("--camera", options.camera, "Which glTF camera to look through: its index in the file's \"cameras\" (default: the "
                                               "first camera, perspective or orthographic, else one that frames the scene)")
        ->type_name("N")
        ->check(kNotEmpty);
}

renderer::SceneLoadOptions parseSceneLoadOptions(const SceneChoiceOptions& choice, bool allowOutsidePaths) {
    auto index = [](const std::string& text, const char* option) -> std::optional<uint32_t> {
        if (text.empty()) return std::nullopt;
        uint32_t value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (error != std::errc() || end != text.data() + text.size())
            throw UsageError(fmt::format("{} '{}' is not an index (a whole number >= 0)", option, text));
        return value;
    };
    renderer::SceneLoadOptions options;
    options.allowPathsOutsideSceneFolder = allowOutsidePaths;
    options.scene = index(choice.scene, "--scene");
    options.camera = index(choice.camera, "--camera");
    return options;
}

std::string sceneLabel(const std::optional<std::filesystem::path>& scenePath) {
    if (!scenePath) return "built-in default scene";
    if (namesBuiltInScene(*scenePath))
        return fmt::format("built-in {} scene", scenePath->string());
    return scenePath->string();
}

void addLightingOptions(CLI::App& app, LightingOptions& options) {
    app.add_option("--culling", options.culling, "Local-light culling: auto, naive, tiles-2d or tiles-depth (default: scene, then auto)")
        ->type_name("MODE");
    app.add_option("--tile-size", options.tileSize, "Screen tile side in pixels: 16, 32, 64, 128 or 256 (default 16)")->type_name("N");
    app.add_option("--max-lights-per-tile", options.maxLightsPerTile,
                   fmt::format("Cap of each tile's light list, 1..{0}, or auto: the light count (no tile drops a light), within {0} and "
                               "{1} MiB of lists (default: scene, then auto)",
                               renderer::kMaxLightsPerTileLimit, renderer::kAutoTileListBudgetBytes >> 20))
        ->type_name("N");
    app.add_option("--intensity-cutoff", options.intensityCutoff,
                   "Illuminance (lux) below which a light without a range is culled; 0 = never (naive only; default 0.01)")
        ->type_name("LUX");
    app.add_flag("--no-shadows", options.noShadows, "No shadow map for the main directional light");
}

namespace {

uint32_t parseWholeFlag(std::string_view flag, std::string_view text, uint32_t lo, uint32_t hi, std::string_view allowed) {
    uint32_t value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size() || text.empty() || value < lo || value > hi)
        throw UsageError(fmt::format("{} '{}' is not allowed; use {}", flag, text, allowed));
    return value;
}

}  // namespace

void addMultisamplingOptions(CLI::App& app, MultisamplingOptions& options) {
    app.add_option("--msaa", options.msaa,
                   "Samples per pixel: 1 (off), 2, 4, 8 or 16, where the backend allows it for RGBA16F and D32F targets (`janus info`, "
                   "column samples; 4 everywhere). Edges are anti-aliased; tiled culling then has no depth bounds (docs/LIGHTING.md)")
        ->type_name("N");
    app.add_option("--alpha-to-coverage", options.alphaToCoverage,
                   "With --msaa above 1: 'on' (the default) gives alpha-masked materials coverage by alpha around their cut-off, so "
                   "cut-out edges are anti-aliased; 'off' keeps the per-pixel cut-off (docs/LIGHTING.md, \"Anti-aliasing\")")
        ->type_name("on|off");
    app.add_option("--probe-msaa", options.probeMsaa,
                   "Samples per pixel of every reflection probe's capture, as --msaa (default: each probe's own \"msaa\" in the scene "
                   "file, else 1); sharper edges in mirror-like reflections (docs/PROBES.md, \"Multisampled captures\")")
        ->type_name("N");
}

namespace {

uint32_t parseSampleCount(std::string_view flag, const std::string& text) {
    if (text.empty()) return 0;
    const uint32_t samples = parseWholeFlag(flag, text, 1, 16, "1, 2, 4, 8 or 16");
    if (!std::has_single_bit(samples)) throw UsageError(fmt::format("{} '{}' is not allowed; use 1, 2, 4, 8 or 16", flag, text));
    return samples;
}

}  // namespace

void applyMultisamplingOptions(const MultisamplingOptions& options, RenderRequest& request) {
    request.msaaSamples = parseSampleCount("--msaa", options.msaa);
    request.probeMsaaSamples = parseSampleCount("--probe-msaa", options.probeMsaa);
    if (options.alphaToCoverage.empty())
        request.alphaToCoverage.reset();
    else if (options.alphaToCoverage == "on" || options.alphaToCoverage == "off")
        request.alphaToCoverage = options.alphaToCoverage == "on";
    else
        throw UsageError(fmt::format("--alpha-to-coverage '{}' is not allowed; use on or off", options.alphaToCoverage));
}

renderer::LightingSettings parseLightingOptions(const LightingOptions& options) {
    renderer::LightingSettings lighting;
    if (!options.culling.empty()) {
        lighting.culling = renderer::parseLightCulling(options.culling);
        if (!lighting.culling)
            throw UsageError(fmt::format("--culling '{}' is not a culling mode; use auto, naive, tiles-2d or tiles-depth", options.culling));
    }
    if (!options.tileSize.empty()) {
        const uint32_t size = parseWholeFlag("--tile-size", options.tileSize, 16, 256, "16, 32, 64, 128 or 256");
        if (size != 16 && size != 32 && size != 64 && size != 128 && size != 256)
            throw UsageError(fmt::format("--tile-size '{}' is not allowed; use 16, 32, 64, 128 or 256", options.tileSize));
        lighting.tileSize = size;
    }
    if (options.maxLightsPerTile == "auto")
        lighting.maxLightsPerTile = renderer::kAutoMaxLightsPerTile;
    else if (!options.maxLightsPerTile.empty())
        lighting.maxLightsPerTile =
            parseWholeFlag("--max-lights-per-tile", options.maxLightsPerTile, 1, 1024, "a whole number 1..1024 or auto");
    if (!options.intensityCutoff.empty()) {
        float cutoff = 0.0f;
        const std::string& text = options.intensityCutoff;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), cutoff);
        if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(cutoff) || cutoff < 0.0f)
            throw UsageError(fmt::format("--intensity-cutoff '{}' is not allowed; use a finite number >= 0 (lux; 0 = infinite range)", text));
        lighting.intensityCutoff = cutoff;
    }
    if (options.noShadows) lighting.shadows = false;
    return lighting;
}

renderer::DebugView parseDebugOption(std::string_view text) {
    const std::optional<renderer::DebugView> view = renderer::parseDebugView(text);
    if (!view) throw UsageError(fmt::format("--debug '{}' is not a debug view; use none, tiles, gi, gi-light or shadow", text));
    return *view;
}

void addEnvironmentOptions(CLI::App& app, EnvironmentOptions& options) {
    app.add_option("--env", options.map,
                   "Equirectangular sky (.hdr or .exr) that lights the scene and is its background; replaces the scene's")
        ->type_name("FILE.hdr|FILE.exr")
        ->check(kNotEmpty);
    app.add_option("--env-intensity", options.intensity, "Multiplies the sky's radiance, a finite number >= 0 (default: scene, then 1)")
        ->type_name("X")
        ->check(kNotEmpty);
}

EnvironmentOverride parseEnvironmentOptions(const EnvironmentOptions& options) {
    EnvironmentOverride environment;
    if (!options.intensity.empty()) {
        float intensity = 0.0f;
        const std::string& text = options.intensity;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), intensity);
        if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(intensity) || intensity < 0.0f)
            throw UsageError(fmt::format("--env-intensity '{}' is not allowed; use a finite number >= 0", text));
        environment.intensity = intensity;
    }
    if (!options.map.empty()) {
        const std::filesystem::path map = options.map;
        const std::string extension = lowerCaseExtension(map);
        if (extension != ".hdr" && extension != ".exr")
            throw UsageError(fmt::format("--env '{}' must name an equirectangular .hdr or .exr image", options.map));
        std::error_code ec;
        if (!std::filesystem::exists(map, ec))
            throw InputError(fmt::format("--env '{}' does not exist; give an existing .hdr or .exr sky", options.map));
        if (std::filesystem::is_directory(map, ec))
            throw InputError(fmt::format("--env '{}' is a directory; give the .hdr or .exr file inside it", options.map));
        if (const std::string kind = notRegularFileKind(map); !kind.empty())
            throw InputError(fmt::format("--env '{}' is {}, not a regular file; give an .hdr or .exr image file", options.map, kind));
        environment.map = std::filesystem::absolute(map).lexically_normal();
    }
    return environment;
}

void applyEnvironmentOverride(renderer::Scene& scene, const EnvironmentOverride& environment) {
    if (environment.map) scene.environment.map = *environment.map;
    if (environment.intensity) scene.environment.intensity = *environment.intensity;
}

void loadEnvironmentImage(renderer::Scene& scene, bool fromEnvOption, std::string_view sceneLabel) {
    renderer::Environment& environment = scene.environment;
    if (environment.map.empty()) return;
    const std::string source = fromEnvOption ? std::string("given by --env") : fmt::format("the \"environment.map\" of {}", sceneLabel);
    try {
        const std::string extension = lowerCaseExtension(environment.map);
        if (extension != ".hdr" && extension != ".exr")
            throw renderer::ImageIOError(fmt::format("'{}' is not an .hdr or .exr image", environment.map.string()));
        environment.image = std::make_shared<const renderer::ImageRGBAF>(
            extension == ".exr" ? renderer::readEXR(environment.map) : renderer::readRadianceHDR(environment.map));
    } catch (const renderer::ImageIOError& e) {
        throw InputError(fmt::format("environment map '{}' ({}) cannot be read: {}; give an equirectangular .hdr (Radiance RGBE) or "
                                     ".exr image",
                                     environment.map.string(), source, e.what()));
    }
    environment.map.clear();   // the image is used from now on
}

void checkLightingOptions(const renderer::LightingSettings& lighting, const renderer::Scene& scene, std::string_view sceneLabel) {
    // Where each setting comes from: the option, else the scene's "quality" key (the loader checked its value).
    std::optional<renderer::LightCulling> culling = lighting.culling;
    std::string cullingFrom = "--culling";
    if (!culling && scene.quality.is_object() && scene.quality.contains("lightCulling") && scene.quality["lightCulling"].is_string()) {
        culling = renderer::parseLightCulling(scene.quality["lightCulling"].get<std::string>());
        cullingFrom = fmt::format("{}'s \"quality\".\"lightCulling\"", sceneLabel);
    }
    std::optional<float> cutoff = lighting.intensityCutoff;
    std::string cutoffFrom = "--intensity-cutoff";
    if (!cutoff && scene.quality.is_object() && scene.quality.contains("intensityCutoff") && scene.quality["intensityCutoff"].is_number()) {
        cutoff = scene.quality["intensityCutoff"].get<float>();
        cutoffFrom = fmt::format("{}'s \"quality\".\"intensityCutoff\"", sceneLabel);
    }
    if (!lighting.culling && !lighting.intensityCutoff) return;   // the scene's own settings, checked when it loaded
    if (cutoff && *cutoff == 0.0f && culling &&
        (*culling == renderer::LightCulling::Tiles2D || *culling == renderer::LightCulling::TilesDepth))
        throw UsageError(fmt::format("{} 0 gives lights without a range an infinite range, which only naive culling renders, but {} is "
                                     "{}; use --culling naive, or a cut-off above 0 (--intensity-cutoff 0.01)",
                                     cutoffFrom, cullingFrom, renderer::toString(*culling)));
}

void addAnimationOptions(CLI::App& app, AnimationOptions& options) {
    app.add_option("--time", options.time,
                   "Pose the scene at this time in seconds (>= 0; past the last keyframe the animation holds its end; default: "
                   "the scene file's \"time\", else 0)")
        ->type_name("SECONDS")
        ->check(kNotEmpty);
    app.add_option("--animation", options.animation,
                   "Which glTF animation --time samples: its name or index (default: the scene file's \"animation\", else 0)")
        ->type_name("NAME|INDEX")
        ->check(kNotEmpty);
}

AnimationOverride parseAnimationOptions(const AnimationOptions& options) {
    AnimationOverride animation;
    if (!options.time.empty()) {
        const std::string& text = options.time;
        float time = 0.0f;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), time);
        if (error == std::errc::result_out_of_range && end == text.data() + text.size())
            throw UsageError(fmt::format("--time '{}' is too large (or too small) for a float; give a finite number of seconds >= 0, "
                                         "such as 0.5",
                                         text));
        if (error != std::errc() || end != text.data() + text.size())
            throw UsageError(fmt::format("--time '{}' is not a number; give the time in seconds, such as 0.5", text));
        if (!std::isfinite(time) || time < 0.0f)
            throw UsageError(fmt::format("--time '{}' is not allowed; give a finite number of seconds >= 0", text));
        animation.time = time;
    }
    if (!options.animation.empty()) animation.animation = options.animation;
    return animation;
}

void applyAnimationOverride(renderer::Scene& scene, const AnimationOverride& animation, std::string_view sceneLabel) {
    if (!animation.time && !animation.animation) return;
    std::optional<size_t> index = scene.posedAnimation;
    if (animation.animation) {
        if (scene.animations.empty())
            throw UsageError(fmt::format("--animation '{}': {} has no animations", *animation.animation, sceneLabel));
        try {
            index = renderer::findAnimation(scene, *animation.animation);
        } catch (const renderer::SceneError& e) {
            throw UsageError(fmt::format("--animation '{}': {} ({})", *animation.animation, e.what(), sceneLabel));
        }
    }
    renderer::poseScene(scene, animation.time.value_or(scene.posedTime), index);
}

std::string poseLine(const renderer::Scene& scene) {
    if (scene.animations.empty() || !scene.posedAnimation) return "";
    const size_t index = *scene.posedAnimation;
    const renderer::Animation& animation = scene.animations[index];
    return fmt::format("animation {}{} at {} s (of {} s; {} animation{} in the scene)", index,
                       animation.name.empty() ? "" : fmt::format(" '{}'", animation.name), scene.posedTime, animation.duration,
                       scene.animations.size(), scene.animations.size() == 1 ? "" : "s");
}

std::string lightCullingLine(const renderer::FrameReport& report) {
    if (!report.lightCulling) return "";
    const renderer::LightCullingReport& c = *report.lightCulling;
    std::string line = fmt::format("light culling: {}", renderer::toString(c.mode));
    if (!c.builder.empty()) line += fmt::format(" ({} builder)", c.builder);
    line += fmt::format(", {} local + {} directional lights", c.localLights, c.directionalLights);
    if (c.tilesX * c.tilesY > 0) {
        line += fmt::format(", {}x{} tiles of {} px, cap {}{}, {:.1f} lights/tile", c.tilesX, c.tilesY, c.tileSize, c.maxLightsPerTile,
                            c.maxLightsPerTileAuto ? " (auto)" : "", double(c.listedLights) / double(c.tilesX * c.tilesY));
        line += c.overflowTiles ? fmt::format(", OVERFLOW: {} tiles, {} lights dropped (the densest tile met {})", c.overflowTiles,
                                              c.droppedLights, c.densestTileLights)
                                : std::string(", no overflow");
    }
    return line;
}

std::string configurationLabel(rhi::Backend backend, renderer::FeaturePath path) {
    return fmt::format("{}/{}", rhi::toString(backend), renderer::toString(path));
}

std::string configurationFileStem(rhi::Backend backend, renderer::FeaturePath path) {
    return fmt::format("{}-{}", rhi::toString(backend), renderer::toString(path));
}

RenderOutcome renderConfiguration(const renderer::Scene& scene, const RenderRequest& request) {
    rhi::DeviceDesc desc;
    desc.setBackend(request.backend).setGLPlatform(request.glPlatform).setEnableValidation(request.validation);
    std::unique_ptr<rhi::IDevice> device = rhi::createDevice(desc);

    const rhi::Capabilities& caps = device->capabilities();
    if (request.path == renderer::FeaturePath::Compute && !caps.has(rhi::Capability::Compute))
        throw UnavailableError(fmt::format("the {} backend lacks the '{}' capability that --path compute needs; "
                                           "use --path fallback",
                                           rhi::toString(request.backend), rhi::toString(rhi::Capability::Compute)));
    const uint32_t maxSide = caps.limits.maxTextureSize2D;
    if (maxSide != 0 && (request.size.width > maxSide || request.size.height > maxSide))
        throw UnavailableError(fmt::format("--size {}x{} exceeds the {} backend's largest texture side ({}); use a smaller --size",
                                           request.size.width, request.size.height, rhi::toString(request.backend), maxSide));

    renderer::RenderSettings settings;
    settings.width = request.size.width;
    settings.height = request.size.height;
    settings.path = request.path;
    settings.lighting = request.lighting;
    settings.debugView = request.debugView;
    settings.giBakeFile = request.giBakeFile;
    // A count the device does not allow (given here or by the scene's quality.msaa) is the
    // renderer's RendererError: exit 4, naming the counts it allows.
    settings.msaaSamples = request.msaaSamples;
    settings.alphaToCoverage = request.alphaToCoverage;
    settings.probeMsaaSamples = request.probeMsaaSamples;

    RenderOutcome outcome;
    outcome.device = device->info();
    {
        // The renderer owns device resources, so it must go before the device does.
        renderer::Renderer frameRenderer(*device, scene, settings);
        outcome.report = frameRenderer.renderFrame();
        // Reflection probes may spread their first update over several frames: render until each
        // is shown; the report keeps the last frame's passes and every frame's probe updates.
        std::vector<renderer::ProbeUpdateReport> probeUpdates = outcome.report.probeUpdates;
        outcome.frames = 1;
        while (((frameRenderer.probesPending() || frameRenderer.irradiancePending()) && outcome.frames < kMaxWarmUpFrames) ||
               outcome.frames < request.frames) {
            outcome.report = frameRenderer.renderFrame();
            probeUpdates.insert(probeUpdates.end(), outcome.report.probeUpdates.begin(), outcome.report.probeUpdates.end());
            ++outcome.frames;
        }
        outcome.report.probeUpdates = std::move(probeUpdates);
        outcome.display = frameRenderer.readDisplayImage();
        if (request.wantHdr) outcome.hdr = frameRenderer.readHdrImage();
    }
    outcome.debugMessages = device->takeDebugMessages();
    return outcome;
}

bool reportDebugMessages(std::string_view label, const std::vector<rhi::DebugMessage>& messages) {
    bool anyError = false;
    for (const rhi::DebugMessage& message : messages) {
        const bool isError = message.severity == rhi::MessageSeverity::Error;
        anyError = anyError || isError;
        std::fprintf(stderr, "janus: %.*s: validation %s: %s\n", int(label.size()), label.data(), isError ? "error" : "warning",
                     message.text.c_str());
    }
    return anyError;
}

std::string formatTable(const std::vector<std::vector<std::string>>& rows, size_t indent) {
    std::vector<size_t> widths;
    for (const auto& row : rows) {
        if (widths.size() < row.size()) widths.resize(row.size(), 0);
        for (size_t c = 0; c < row.size(); ++c) widths[c] = std::max(widths[c], row[c].size());
    }
    std::string out;
    for (const auto& row : rows) {
        std::string line(indent, ' ');
        for (size_t c = 0; c < row.size(); ++c) {
            line += row[c];
            if (c + 1 < row.size()) line += std::string(widths[c] - row[c].size() + 2, ' ');
        }
        while (!line.empty() && line.back() == ' ') line.pop_back();
        out += line;
        out += '\n';
    }
    return out;
}

std::string validUtf8(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    size_t i = 0;
    while (i < text.size()) {
        const auto byte = static_cast<unsigned char>(text[i]);
        // The length of the sequence this byte starts and the range its second byte must be in
        // (RFC 3629: no overlong forms, no surrogates, nothing above U+10FFFF).
        size_t length = 0;
        unsigned char lo = 0x80, hi = 0xBF;
        if (byte < 0x80) length = 1;
        else if (byte >= 0xC2 && byte <= 0xDF) length = 2;
        else if (byte == 0xE0) length = 3, lo = 0xA0;
        else if (byte >= 0xE1 && byte <= 0xEC) length = 3;
        else if (byte == 0xED) length = 3, hi = 0x9F;
        else if (byte >= 0xEE && byte <= 0xEF) length = 3;
        else if (byte == 0xF0) length = 4, lo = 0x90;
        else if (byte >= 0xF1 && byte <= 0xF3) length = 4;
        else if (byte == 0xF4) length = 4, hi = 0x8F;
        bool valid = length != 0 && i + length <= text.size();
        for (size_t k = 1; valid && k < length; ++k) {
            const auto next = static_cast<unsigned char>(text[i + k]);
            valid = k == 1 ? next >= lo && next <= hi : next >= 0x80 && next <= 0xBF;
        }
        if (valid) {
            out.append(text.substr(i, length));
            i += length;
        } else {
            out += fmt::format("\\x{:02X}", byte);
            ++i;
        }
    }
    return out;
}

namespace {

nlohmann::json withValidUtf8(const nlohmann::json& json) {
    if (json.is_string()) return validUtf8(json.get_ref<const std::string&>());
    if (json.is_array()) {
        nlohmann::json out = nlohmann::json::array();
        for (const nlohmann::json& item : json) out.push_back(withValidUtf8(item));
        return out;
    }
    if (json.is_object()) {
        nlohmann::json out = nlohmann::json::object();
        for (const auto& [key, value] : json.items()) out[validUtf8(key)] = withValidUtf8(value);
        return out;
    }
    return json;
}

}  // namespace

std::string jsonFileText(const nlohmann::json& json) { return withValidUtf8(json).dump(2) + "\n"; }

std::vector<std::string> splitList(const std::string& text) {
    std::vector<std::string> items;
    std::stringstream stream(text);
    for (std::string item; std::getline(stream, item, ',');)
        if (!item.empty()) items.push_back(item);
    return items;
}

std::vector<uint32_t> parseCountList(const std::string& text, const char* option, uint32_t lo, uint32_t hi, bool powerOfTwo) {
    std::vector<uint32_t> values;
    std::stringstream stream(text);
    for (std::string item; std::getline(stream, item, ',');) {
        uint32_t n = 0;
        const auto [end, error] = std::from_chars(item.data(), item.data() + item.size(), n);
        if (item.empty() || error != std::errc() || end != item.data() + item.size() || n < lo || n > hi ||
            (powerOfTwo && (n & (n - 1)) != 0))
            throw UsageError(fmt::format("{} '{}' must be a comma-separated list of {}integers {}..{}", option, text,
                                         powerOfTwo ? "power-of-two " : "", lo, hi));
        if (std::find(values.begin(), values.end(), n) == values.end()) values.push_back(n);
    }
    if (values.empty()) throw UsageError(fmt::format("{} '{}' is empty", option, text));
    std::sort(values.begin(), values.end());
    return values;
}

double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const size_t mid = values.size() / 2;
    return values.size() % 2 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
}

std::filesystem::path benchOutputDir(const std::string& out, const std::string& stem) {
    if (out.empty()) throw UsageError(fmt::format("--out DIR is required: where to write {0}.md, {0}.json and {0}.png", stem));
    const std::filesystem::path dir = out;
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (!std::filesystem::is_directory(dir, ec)) throw InputError(fmt::format("--out '{}' could not be created as a directory", out));
    return dir;
}

void writeBenchOutputs(const std::filesystem::path& dir, const std::string& stem, const std::string& markdown,
                       const nlohmann::json& json, const renderer::ImageRGBA8& plot) {
    renderer::writeFileAtomically(dir / (stem + ".md"), markdown);
    renderer::writeFileAtomically(dir / (stem + ".json"), jsonFileText(json));
    renderer::writePNG(dir / (stem + ".png"), plot);
    std::fputs(markdown.c_str(), stdout);
    std::printf("\nwrote %s, %s.json, %s.png\n", (dir / (stem + ".md")).c_str(), stem.c_str(), stem.c_str());
}

void printPassSummary(const renderer::FrameReport& report) {
    std::vector<std::vector<std::string>> rows{{"view", "pass", "GPU ms", "CPU ms", "draws", "dispatches"}};
    double totalCpu = 0.0, totalGpu = 0.0;
    bool allTimed = true;
    uint32_t totalDraws = 0, totalDispatches = 0;
    for (const renderer::PassReport& pass : report.passes) {
        rows.push_back({pass.view.empty() ? "-" : pass.view, pass.name, pass.gpuMs ? fmt::format("{:.3f}", *pass.gpuMs) : "-", fmt::format("{:.3f}", pass.cpuMs),
                        std::to_string(pass.draws), std::to_string(pass.dispatches)});
        totalCpu += pass.cpuMs;
        if (pass.gpuMs) totalGpu += *pass.gpuMs; else allTimed = false;
        totalDraws += pass.draws;
        totalDispatches += pass.dispatches;
    }
    rows.push_back({"total", "", allTimed && !report.passes.empty() ? fmt::format("{:.3f}", totalGpu) : "-",
                    fmt::format("{:.3f}", totalCpu), std::to_string(totalDraws), std::to_string(totalDispatches)});
    std::fputs(formatTable(rows).c_str(), stdout);
}

void printPerformanceMessages(const std::vector<std::string>& messages) {
    if (messages.empty()) return;
    std::printf("\nperformance messages from the driver (%zu; slow paths, not errors):\n", messages.size());
    for (const std::string& message : messages) std::printf("  %s\n", message.c_str());
}

void printProbeUpdates(const std::vector<renderer::ProbeUpdateReport>& updates) {
    if (updates.empty()) return;
    std::vector<std::vector<std::string>> rows{
        {"probe", "samples", "update", "step", "shown", "GPU ms", "draws", "dispatches", "update draws", "prefilter draws",
         "prefilter dispatches"}};
    for (const renderer::ProbeUpdateReport& u : updates)
        rows.push_back({u.probe, std::to_string(u.msaaSamples), std::to_string(u.update), fmt::format("{}/{}", u.step, u.steps),
                        u.shown ? "yes" : "no",
                        u.gpuMs ? fmt::format("{:.3f}", *u.gpuMs) : "-", std::to_string(u.draws), std::to_string(u.dispatches),
                        std::to_string(u.updateDraws), std::to_string(u.prefilterDraws), std::to_string(u.prefilterDispatches)});
    std::printf("\nreflection probe updates (one row per probe per frame):\n");
    std::fputs(formatTable(rows).c_str(), stdout);
}

}  // namespace janus::cli
