// Pieces every `janus` subcommand shares: exit codes, the errors commands raise, option parsing,
// and rendering one configuration. Adding a subcommand = one cmd_<name>.cpp with an
// add<Name>Command() declared here and registered in main.cpp.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "janus/renderer/image.h"
#include "janus/renderer/renderer.h"
#include "janus/renderer/scene.h"
#include "janus/rhi/rhi.h"

namespace janus::cli {

// The process exit status; documented in --help and docs/CLI.md, so never renumber.
enum class ExitCode : int {
    Ok = 0,
    ComparisonFailed = 1,      // parity: a pair exceeded the tolerance or a configuration did not run; check: a file failed or diverged
    UsageError = 2,            // unknown command/option/backend, malformed or absurd value
    InputError = 3,            // missing/malformed scene, unreadable input, unwritable output
    BackendUnavailable = 4,    // backend cannot start or lacks a capability the request needs
    InternalError = 5,         // a bug in janus (or the driver): please report it
};

inline constexpr const char* kExitCodeHelp =
    "Exit codes:\n"
    "  0  success\n"
    "  1  parity or check failed (a pair differs beyond --tolerance, or a configuration could not run)\n"
    "  2  usage error (unknown command, option or backend; bad --size; bad value)\n"
    "  3  input/output error (missing or malformed scene, unwritable output path)\n"
    "  4  backend or capability unavailable on this machine\n"
    "  5  internal error (a bug; please report it)\n";

// Errors the commands raise themselves. Library errors (rhi::Error, SceneError, RendererError,
// ImageIOError) are mapped to exit codes in runCommand().
class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};
class UnavailableError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Runs a command body, turning every exception into one `janus: error: ...` line on stderr and
// the matching exit code.
int runCommand(const std::function<int()>& body);

// Prints `janus: error: <message>` to stderr.
void printError(std::string_view message);

// ---- option values ------------------------------------------------------------------------

struct ImageSize {
    uint32_t width = 256;
    uint32_t height = 256;
};
// Largest side accepted before a device is even opened; devices may allow less (checked later).
inline constexpr uint32_t kMaxRenderSide = 16384;

ImageSize parseSize(std::string_view text);                        // "WxH"; throws UsageError
rhi::Backend parseBackendOption(std::string_view text);            // throws UsageError
renderer::FeaturePath parsePathOption(std::string_view text);      // throws UsageError
rhi::GLPlatform parseGLPlatformOption(std::string_view text);      // throws UsageError
std::vector<std::string> splitList(const std::string& text);        // "a,b,,c" -> {a, b, c}
// "64,16,64" -> {16, 64}: distinct, sorted, each in lo..hi (and a power of two when asked); a
// UsageError naming `option` otherwise, or when the list is empty.
std::vector<uint32_t> parseCountList(const std::string& text, const char* option, uint32_t lo, uint32_t hi, bool powerOfTwo);

// Fails early (InputError) when `file` could not be created: its directory is missing or is
// not a directory, or `file` itself is a directory. Saves a render that could not be saved.
void checkOutputFile(const std::filesystem::path& file, std::string_view optionName);

using renderer::lowerCaseExtension;   // janus dispatches on extensions in any case

// "" when `file` (after following symbolic links) is a regular file or does not exist; else what
// it is instead ("a directory", "a FIFO", "a character device", ...). Inputs must be regular
// files: a FIFO blocks the reader, a device such as /dev/zero never ends.
std::string notRegularFileKind(const std::filesystem::path& file);

// Outputs must not overwrite inputs or each other: UsageError (exit 2) when two outputs name the
// same file, or an output names an input (compared after resolving links, `..` and `.`, so
// `a.png`, `./a.png` and a link to it are one file). Each entry is (what, path), e.g.
// ("--report", "a.json") or ("the scene file", "scene.gltf"); empty paths are skipped.
using NamedPath = std::pair<std::string, std::filesystem::path>;
void checkOutputsDistinct(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs);
// The files a scene reads, for checkOutputsDistinct: the scene file; for a .json scene file its
// "gltf" and "environment.map"; for a glTF its buffers and images (not data: URIs). Nothing for
// a built-in scene. Read from the JSON alone, never failing (the loader reports bad files).
std::vector<NamedPath> sceneInputFiles(const std::optional<std::filesystem::path>& scenePath);
// The same rule for commands that write a folder of files (parity, check, bench): UsageError
// (exit 2) when a file `names` gives inside `dir`, which the command would write or replace,
// is one of `inputs` (the same file: compared by device and inode, so links count). Names are
// relative to `dir`; only files that exist can be inputs, so this costs one stat per name.
void checkFolderOutputs(const std::filesystem::path& dir, std::string_view option, const std::vector<std::string>& names,
                        const std::vector<NamedPath>& inputs);

// The scene file given on the command line, the built-in many-lights scene ("many-lights" or
// "many-lights:N", N local lights, default 128; a regular file of that name wins, a folder does
// not), or the default scene.
inline constexpr std::string_view kManyLightsSceneName = "many-lights";
inline constexpr std::string_view kProbesSceneName = "probes";   // renderer::probesScene()
inline constexpr std::string_view kGiRoomsSceneName = "gi-rooms";   // renderer::giRoomsScene()
std::optional<uint32_t> parseManyLightsSceneName(std::string_view text);   // nullopt: not that name; throws UsageError for a bad N
// `options`: --allow-outside-paths, --scene, --camera (renderer::SceneLoadOptions); --scene and
// --camera with a built-in scene are a UsageError.
renderer::Scene loadSceneOrDefault(const std::optional<std::filesystem::path>& scenePath, const renderer::SceneLoadOptions& options = {});
inline renderer::Scene loadSceneOrDefault(const std::optional<std::filesystem::path>& scenePath, bool allowOutsidePaths) {
    renderer::SceneLoadOptions options;
    options.allowPathsOutsideSceneFolder = allowOutsidePaths;
    return loadSceneOrDefault(scenePath, options);
}
std::string sceneLabel(const std::optional<std::filesystem::path>& scenePath);

// Options several commands share, declared once so their names, defaults and help agree.
void addSceneArgument(CLI::App& app, std::string& scene);
// --allow-outside-paths: a glTF may read buffers and images outside its folder.
void addAllowOutsidePathsFlag(CLI::App& app, bool& allow);
void addSizeOption(CLI::App& app, std::string& size);
// --scene N and --camera N: which glTF scene and camera to render (renderer::SceneLoadOptions).
// Empty strings = not given (the file's default scene, its first camera).
struct SceneChoiceOptions {
    std::string scene;
    std::string camera;
};
void addSceneChoiceOptions(CLI::App& app, SceneChoiceOptions& options);
// UsageError naming the option for a value that is not a non-negative integer.
renderer::SceneLoadOptions parseSceneLoadOptions(const SceneChoiceOptions& choice, bool allowOutsidePaths);
void addGLPlatformOption(CLI::App& app, std::string& glPlatform);

// What the accuracy-vs-time benches (`janus bench probes`, `gi`, `shadows`) sweep and where they
// write: --paths and --backends (comma-separated; the defaults are the subcommand's), --out/-o DIR
// and --gl-platform.
struct BenchTargets {
    std::string paths, backends, out, glPlatform = "egl";
    bool pathsGiven = false, backendsGiven = false;   // on the command line (noteBenchTargetsGiven)
};
void addBenchTargetOptions(CLI::App& app, BenchTargets& targets);
void noteBenchTargetsGiven(const CLI::App& app, BenchTargets& targets);   // in the subcommand's callback
struct BenchConfigurations {
    std::vector<renderer::FeaturePath> paths;
    std::vector<rhi::Backend> backends;
};
// The lists parsed; with `quick`, a non-empty `quickPaths` / `quickBackends` replaces a list not
// given on the command line. UsageError naming an unknown entry, or when a list is empty.
BenchConfigurations parseBenchTargets(const BenchTargets& targets, bool quick, const std::string& quickPaths = {},
                                      const std::string& quickBackends = {});

// Forward+ lighting flags (--culling, --tile-size, --max-lights-per-tile, --intensity-cutoff,
// --no-shadows), shared by render, parity and bench. Empty strings = not given (scene/default).
struct LightingOptions {
    std::string culling;
    std::string tileSize;
    std::string maxLightsPerTile;
    std::string intensityCutoff;
    bool noShadows = false;
};
void addLightingOptions(CLI::App& app, LightingOptions& options);
renderer::LightingSettings parseLightingOptions(const LightingOptions& options);   // throws UsageError naming the flag
renderer::DebugView parseDebugOption(std::string_view text);                        // throws UsageError
// Multisampling flags, shared by render and parity: --msaa N, samples per pixel of the main view
// (1 = off, 2, 4, 8 or 16; empty: the scene's quality "msaa", else 1); --alpha-to-coverage on|off,
// alpha-masked materials' coverage with samples (empty: the scene's quality "alphaToCoverage",
// else on); --probe-msaa N, samples per pixel of every reflection probe's capture (empty: each
// probe's own "msaa").
struct MultisamplingOptions {
    std::string msaa, alphaToCoverage, probeMsaa;
};
void addMultisamplingOptions(CLI::App& app, MultisamplingOptions& options);

// --env FILE.hdr|FILE.exr and --env-intensity X, shared by render and parity: they set or override
// the scene's environment map and intensity. Empty strings = not given (the scene's own).
struct EnvironmentOptions {
    std::string map;
    std::string intensity;
};
void addEnvironmentOptions(CLI::App& app, EnvironmentOptions& options);
struct EnvironmentOverride {
    std::optional<std::filesystem::path> map;   // absolute
    std::shared_ptr<const renderer::ImageRGBAF> image;   // the map, once read (check reads it once for every file)
    std::optional<float> intensity;
};
// Checks the options before any scene is loaded: UsageError for a bad intensity or an extension
// other than .hdr/.exr, InputError (exit 3) naming the file when the map is missing.
EnvironmentOverride parseEnvironmentOptions(const EnvironmentOptions& options);
void applyEnvironmentOverride(renderer::Scene& scene, const EnvironmentOverride& environment);

// Reads the scene's environment map (Environment::map: --env's, or a scene file's
// "environment.map") into Environment::image now, before any device opens, so a file that is not
// a readable .hdr / .exr is an InputError (exit 3) naming it and where it came from, and parity and
// check read it once for every configuration. `fromEnvOption`: the map is --env's.
void loadEnvironmentImage(renderer::Scene& scene, bool fromEnvOption, std::string_view sceneLabel);

// The lighting options (render, parity) against each other and the scene file's "quality" keys,
// before any device opens: UsageError naming the options (and keys) that conflict, e.g.
// --intensity-cutoff 0 with --culling tiles-depth.
void checkLightingOptions(const renderer::LightingSettings& lighting, const renderer::Scene& scene, std::string_view sceneLabel);

// --time SECONDS and --animation NAME|INDEX, shared by render and parity: the pose the scene is
// rendered at (docs/SCENES.md, "Animations"). Empty strings = not given (the scene's own pose:
// a scene file's "time"/"animation", else t = 0 of animation 0).
struct AnimationOptions {
    std::string time;
    std::string animation;
};
void addAnimationOptions(CLI::App& app, AnimationOptions& options);
struct AnimationOverride {
    std::optional<float> time;          // seconds, finite and >= 0
    std::optional<std::string> animation;
};
// Checks --time before any scene is loaded: UsageError for a value that is not a finite number >= 0.
AnimationOverride parseAnimationOptions(const AnimationOptions& options);
// Poses `scene` as the options ask (each option replaces the scene's own). UsageError naming the
// option for an unknown animation name, an index out of range or --animation on a scene without
// animations (`sceneLabel` names the scene).
void applyAnimationOverride(renderer::Scene& scene, const AnimationOverride& animation, std::string_view sceneLabel);
// "animation 1 'Walk' at 0.5 s (of 0.7 s)", or "" for a scene without animations.
std::string poseLine(const renderer::Scene& scene);

// ---- rendering one configuration ----------------------------------------------------------

struct RenderRequest {
    rhi::Backend backend = rhi::Backend::Vulkan;
    renderer::FeaturePath path = renderer::FeaturePath::Compute;
    rhi::GLPlatform glPlatform = rhi::GLPlatform::EGL;
    ImageSize size;
    bool validation = false;
    bool wantHdr = false;
    renderer::LightingSettings lighting;
    renderer::DebugView debugView = renderer::DebugView::None;
    std::filesystem::path giBakeFile;   // empty: the irradiance volume (if any) is baked at start-up
    uint32_t msaaSamples = 0;   // 0: the scene's quality "msaa", else 1
    std::optional<bool> alphaToCoverage;   // nullopt: the scene's quality "alphaToCoverage", else on
    uint32_t probeMsaaSamples = 0;   // 0: each reflection probe's own
    // Frames rendered at least (`janus render --frames`): the report is the last one's, so more
    // than one gives times without the first frame's first-use costs.
    uint32_t frames = 1;
};
// Sets msaaSamples, alphaToCoverage and probeMsaaSamples from the flags; throws UsageError naming the flag.
void applyMultisamplingOptions(const MultisamplingOptions& options, RenderRequest& request);

struct RenderOutcome {
    rhi::DeviceInfo device;
    renderer::FrameReport report;
    renderer::ImageRGBA8 display;
    std::optional<renderer::ImageRGBAF> hdr;
    std::vector<rhi::DebugMessage> debugMessages;   // with validation: warnings and errors
    uint32_t frames = 1;   // frames rendered: more than one while reflection probes were first updating
};
inline constexpr uint32_t kMaxWarmUpFrames = 64;

// Opens the device, checks it can honour the request (UnavailableError naming the capability or
// limit otherwise), renders one frame (more while reflection probes are not yet shown, at most
// kMaxWarmUpFrames) and reads the images back.
RenderOutcome renderConfiguration(const renderer::Scene& scene, const RenderRequest& request);

// Prints each validation / debug message to stderr, prefixed with `label`; true when any is an error.
bool reportDebugMessages(std::string_view label, const std::vector<rhi::DebugMessage>& messages);

// "vulkan/compute"-style label, and "vulkan-compute" for file names.
std::string configurationLabel(rhi::Backend backend, renderer::FeaturePath path);
std::string configurationFileStem(rhi::Backend backend, renderer::FeaturePath path);

// Prints the per-pass table (name, GPU ms, CPU ms, draws, dispatches).
void printPassSummary(const renderer::FrameReport& report);
// The probe updates of the frames rendered, one row per probe per frame (nothing without any).
void printProbeUpdates(const std::vector<renderer::ProbeUpdateReport>& updates);
// The driver's performance messages of a frame (FrameReport::performanceMessages), if any: shown,
// not errors.
void printPerformanceMessages(const std::vector<std::string>& messages);
// One line on how the frame culled its local lights (mode, builder, lights, tiles, overflow);
// "" when the scene had no local lights.
std::string lightCullingLine(const renderer::FrameReport& report);

// A left-aligned text table: every column as wide as its widest cell.
// A benchmark's results in `dir`: STEM.md, STEM.json and STEM.png, each written atomically; the
// Markdown is also printed, followed by where the files went.
// The benchmark's --out directory, created if needed: a UsageError without one (naming STEM.md,
// STEM.json and STEM.png), an InputError when it cannot be created.
std::filesystem::path benchOutputDir(const std::string& out, const std::string& stem);
// The median of a benchmark's runs (the mean of the middle two for an even count); 0 for none.
double median(std::vector<double> values);
void writeBenchOutputs(const std::filesystem::path& dir, const std::string& stem, const std::string& markdown,
                       const nlohmann::json& json, const renderer::ImageRGBA8& plot);

std::string formatTable(const std::vector<std::vector<std::string>>& rows, size_t indent = 2);

// JSON may only hold valid UTF-8, but file names need not be (a name is bytes on Linux): `text`
// with each byte that is not part of a valid UTF-8 sequence written as the four characters \xNN
// (upper-case hex), the rest unchanged.
std::string validUtf8(std::string_view text);
// `json` as the files janus writes hold it: indented by 2, a newline at the end, every string
// (and object key) passed through validUtf8, so a path of any bytes never makes the dump throw.
std::string jsonFileText(const nlohmann::json& json);

// ---- subcommands --------------------------------------------------------------------------

// A registered subcommand: its CLI11 app (options bound) and what to run when it was chosen.
struct Command {
    CLI::App* app = nullptr;
    std::function<int()> run;
};

Command addInfoCommand(CLI::App& parent);
Command addRenderCommand(CLI::App& parent);
Command addParityCommand(CLI::App& parent);
Command addCheckCommand(CLI::App& parent);   // cmd_check.cpp
Command addBenchCommand(CLI::App& parent);
Command addBakeCommand(CLI::App& parent);
// `janus bench probes`, registered under `bench` by addBenchCommand; returns what runs it.
std::function<int()> addBenchProbesCommand(CLI::App& bench);
std::function<int()> addBenchGiCommand(CLI::App& bench);   // cmd_bench_gi.cpp
std::function<int()> addBenchShadowsCommand(CLI::App& bench);   // cmd_bench_shadows.cpp
std::function<int()> addBenchMsaaCommand(CLI::App& bench);      // cmd_bench_msaa.cpp

}  // namespace janus::cli
