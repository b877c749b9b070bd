// The five configurations janus keeps in agreement, running one, and comparing their images:
// shared by `janus parity` (one scene) and `janus check` (every glTF under some folders).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cli_common.h"
#include "janus/renderer/parity.h"

namespace janus::cli {

struct Configuration {
    rhi::Backend backend;
    renderer::FeaturePath path;
};

// Every configuration the project promises to keep in agreement. gles has no compute path.
inline constexpr std::array kConfigurations = {
    Configuration{rhi::Backend::Vulkan, renderer::FeaturePath::Compute},
    Configuration{rhi::Backend::Vulkan, renderer::FeaturePath::Fallback},
    Configuration{rhi::Backend::GL, renderer::FeaturePath::Compute},
    Configuration{rhi::Backend::GL, renderer::FeaturePath::Fallback},
    Configuration{rhi::Backend::GLES, renderer::FeaturePath::Fallback},
};

// Pixel differences beyond this many steps show as full red in the heat maps: small enough that
// a one-step disagreement is clearly visible, large enough to tell 2 from 8.
inline constexpr uint32_t kHeatmapFullScaleSteps = 8;

struct ConfigurationResult {
    Configuration config;
    std::string stem;                  // "vulkan-compute"
    std::optional<RenderOutcome> outcome;
    std::string failure;               // why it did not run
    std::filesystem::path image;

    bool ran() const { return outcome && failure.empty(); }
};

// Runs one configuration. Failures that belong to this configuration alone (backend missing,
// capability missing, driver trouble, validation errors) are recorded in `failure` so the others
// still run and get compared. A renderer::SceneError is rethrown: it is about the scene, which all
// configurations share.
ConfigurationResult runConfiguration(const renderer::Scene& scene, const Configuration& config, const RenderRequest& base);

// Whether a configuration can run on this machine at all, found once by opening each backend's
// device (as `janus info` does): the backend starts, has the compute capability the compute path
// needs, and allows `size`.
struct ConfigurationAvailability {
    Configuration config;
    bool available = false;
    std::string reason;        // why not
    std::string device;        // device name when available
};
std::vector<ConfigurationAvailability> probeConfigurations(rhi::GLPlatform platform, ImageSize size);

// --configs: a comma-separated list of configurations, each as "gl/compute" or "gl-compute";
// returns them in kConfigurations order, each once. Throws UsageError naming the item that is not
// a configuration and listing those that are.
std::vector<Configuration> parseConfigurations(std::string_view list);

// --tolerance: whole 1/255 steps in 0..255; throws UsageError.
uint32_t parseTolerance(std::string_view text, std::string_view option = "--tolerance");   // UsageError naming `option`

// "inf" for identical images, else two decimals.
std::string psnrText(double psnr);

// Pixels a pair may have beyond the tolerance and still agree (--edge-pixels): a pixel centre on
// an edge between two triangles, or within rounding of one, may go to either triangle on GL and
// Vulkan (the two compile the vertex shader separately, so positions can differ in the last bit,
// and they apply the tie-break rule with y up and y down). The default is the shared parity
// rule's (janus/renderer/parity.h), which the renderer suite applies; seen: one interior pixel,
// 2 steps, of DamagedHelmet at 512x512 on llvmpipe. A real bug changes far more pixels.
inline constexpr uint64_t kDefaultEdgePixels = renderer::ParityRule{}.edgePixels;

// --edge-pixels: a pixel count in 0..2^32; throws UsageError.
uint64_t parseEdgePixels(std::string_view text);
// Adds --edge-pixels N (parity and check), stored as text for parseEdgePixels; `edgePixels` holds
// the default (std::to_string(kDefaultEdgePixels)) until the option is given.
void addEdgePixelsOption(CLI::App& app, std::string& edgePixels);

// --compiler-rounding auto|off (parity and check): whether pairs whose devices do not share a
// shader compiler (renderer::shareShaderCompiler: vulkan against gl on a hardware driver) get the
// rounding allowance of janus/renderer/parity.h on top of --tolerance and --edge-pixels.
// Throws UsageError; true for auto.
bool parseCompilerRounding(std::string_view text);
void addCompilerRoundingOption(CLI::App& app, std::string& compilerRounding);

// One pair of configurations compared (i < j, indices into the images given).
struct PairComparison {
    size_t a = 0, b = 0;
    std::optional<renderer::ImageDifference> difference;   // nothing: one of the two did not render
    bool passed = false;          // compared, and agreeing by the rule (renderer::judgeParity)
    bool twoCompilers = false;    // the rounding allowance applied to this pair
    uint64_t roundingPixels = 0;  // pixels beyond the tolerance it let through
};

// Every pair (i < j, in order) of `images` by `rule`; a null image did not render, and its pairs
// are not compared. `devices` (one per image, or empty) says which pairs cross shader compilers:
// those get renderer::withCompilerRounding(rule); with no devices, none does.
std::vector<PairComparison> compareAllPairs(const std::vector<const renderer::ImageRGBA8*>& images, const renderer::ParityRule& rule,
                                            const std::vector<const rhi::DeviceInfo*>& devices = {});

// The result column of a compared pair: "ok", "ok (N edge pixel(s))", "ok (N pixel(s) of
// compiler rounding)" or "FAIL".
std::string pairResultText(const renderer::ImageDifference& difference, uint32_t tolerance, bool passed, uint64_t roundingPixels = 0);

}  // namespace janus::cli
