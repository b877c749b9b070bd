#include "configurations.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <memory>
#include <new>

#include <fmt/format.h>

namespace janus::cli {

ConfigurationResult runConfiguration(const renderer::Scene& scene, const Configuration& config, const RenderRequest& base) {
    ConfigurationResult result{config, configurationFileStem(config.backend, config.path)};
    RenderRequest request = base;
    request.backend = config.backend;
    request.path = config.path;
    try {
        result.outcome = renderConfiguration(scene, request);
        if (reportDebugMessages(configurationLabel(config.backend, config.path), result.outcome->debugMessages))
            result.failure = "validation reported errors (see stderr)";
    } catch (const renderer::SceneError&) {
        throw;   // the scene is shared by all configurations: an input error, not a parity result
    } catch (const std::bad_alloc&) {
        result.failure = "out of host memory";
    } catch (const std::exception& e) {
        result.failure = e.what();
    }
    return result;
}

std::vector<Configuration> parseConfigurations(std::string_view list) {
    auto known = [] {
        std::string names;
        for (const Configuration& config : kConfigurations)
            names += (names.empty() ? "" : ", ") + configurationLabel(config.backend, config.path);
        return names;
    };
    // splitList drops empty items; here one is a mistake: fewer items than commas plus one.
    const std::vector<std::string> items = splitList(std::string(list));
    if (items.size() != size_t(std::count(list.begin(), list.end(), ',')) + 1)
        throw UsageError(fmt::format("--configs '{}' has an empty item; give a comma-separated list of {}", list, known()));
    std::array<bool, kConfigurations.size()> chosen{};
    for (const std::string& item : items) {
        bool found = false;
        for (size_t i = 0; i < kConfigurations.size(); ++i) {
            const Configuration& config = kConfigurations[i];
            if (item == configurationLabel(config.backend, config.path) || item == configurationFileStem(config.backend, config.path)) {
                chosen[i] = true;
                found = true;
            }
        }
        if (!found) throw UsageError(fmt::format("--configs: '{}' is not a configuration; the configurations are {}", item, known()));
    }
    std::vector<Configuration> result;
    for (size_t i = 0; i < kConfigurations.size(); ++i)
        if (chosen[i]) result.push_back(kConfigurations[i]);
    return result;
}

std::vector<ConfigurationAvailability> probeConfigurations(rhi::GLPlatform platform, ImageSize size) {
    std::vector<ConfigurationAvailability> result;
    for (const Configuration& config : kConfigurations) {
        ConfigurationAvailability availability{config};
        try {
            rhi::DeviceDesc desc;
            desc.setBackend(config.backend).setGLPlatform(platform);
            const std::unique_ptr<rhi::IDevice> device = rhi::createDevice(desc);
            const rhi::Capabilities& caps = device->capabilities();
            const uint32_t maxSide = caps.limits.maxTextureSize2D;
            if (config.path == renderer::FeaturePath::Compute && !caps.has(rhi::Capability::Compute))
                availability.reason = fmt::format("the {} backend lacks the '{}' capability", rhi::toString(config.backend),
                                                  rhi::toString(rhi::Capability::Compute));
            else if (maxSide != 0 && (size.width > maxSide || size.height > maxSide))
                availability.reason = fmt::format("{}x{} exceeds the {} backend's largest texture side ({})", size.width, size.height,
                                                  rhi::toString(config.backend), maxSide);
            else
                availability.available = true;
            availability.device = device->info().deviceName;
        } catch (const std::exception& e) {
            availability.reason = e.what();
        }
        result.push_back(std::move(availability));
    }
    return result;
}

uint32_t parseTolerance(std::string_view text, std::string_view option) {
    uint32_t steps = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), steps);
    if (error != std::errc() || end != text.data() + text.size() || text.empty() || steps > 255)
        throw UsageError(fmt::format("{} '{}' is not a whole number of 1/255 steps in 0..255 (default 1)", option, text));
    return steps;
}

std::string psnrText(double psnr) { return std::isinf(psnr) ? "inf" : fmt::format("{:.2f}", psnr); }

std::vector<PairComparison> compareAllPairs(const std::vector<const renderer::ImageRGBA8*>& images, const renderer::ParityRule& rule,
                                            const std::vector<const rhi::DeviceInfo*>& devices) {
    std::vector<PairComparison> pairs;
    for (size_t i = 0; i < images.size(); ++i) {
        for (size_t j = i + 1; j < images.size(); ++j) {
            PairComparison pair{i, j};
            if (images[i] && images[j]) {
                pair.twoCompilers = i < devices.size() && j < devices.size() && devices[i] && devices[j] &&
                                    !renderer::shareShaderCompiler(*devices[i], *devices[j]);
                const renderer::ParityVerdict verdict =
                    renderer::judgeParity(*images[i], *images[j], pair.twoCompilers ? renderer::withCompilerRounding(rule) : rule);
                pair.difference = verdict.difference;
                pair.passed = verdict.agrees;
                pair.roundingPixels = verdict.roundingPixels;
            }
            pairs.push_back(pair);
        }
    }
    return pairs;
}

bool parseCompilerRounding(std::string_view text) {
    if (text == "auto") return true;
    if (text == "off") return false;
    throw UsageError(fmt::format("--compiler-rounding '{}' is not auto or off", text));
}

void addCompilerRoundingOption(CLI::App& app, std::string& compilerRounding) {
    app.add_option("--compiler-rounding", compilerRounding,
                   fmt::format("auto: pairs whose devices compile shaders with different compilers (vulkan and gl on a hardware "
                               "driver; not Mesa's llvmpipe, which compiles both) may also have 1 pixel in {} up to {} steps off, "
                               "their arithmetic's rounding; off: --tolerance and --edge-pixels only",
                               renderer::kCompilerRoundingOnePixelIn, renderer::kCompilerRoundingSteps))
        ->default_str("auto")
        ->type_name("auto|off");
}

uint64_t parseEdgePixels(std::string_view text) {
    uint64_t value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc{} || end != text.data() + text.size() || value > (uint64_t(1) << 32))
        throw UsageError(fmt::format("--edge-pixels '{}' is not a whole number of pixels in 0..2^32 (default {}; 0 allows none)",
                                     text, kDefaultEdgePixels));
    return value;
}

void addEdgePixelsOption(CLI::App& app, std::string& edgePixels) {
    app.add_option("--edge-pixels", edgePixels,
                   "Pixels two configurations may have beyond --tolerance and still agree: a pixel centre on (or within "
                   "rounding of) an edge between two triangles may go to either triangle on GL and Vulkan (0: none)")
        ->default_str(std::to_string(kDefaultEdgePixels))
        ->type_name("N");
}

std::string pairResultText(const renderer::ImageDifference& difference, uint32_t tolerance, bool passed, uint64_t roundingPixels) {
    if (!passed) return "FAIL";
    if (difference.maxChannelDifference <= tolerance) return "ok";
    if (roundingPixels > 0)
        return fmt::format("ok ({} pixel{} of compiler rounding)", roundingPixels, roundingPixels == 1 ? "" : "s");
    return fmt::format("ok ({} edge pixel{})", difference.differingPixels, difference.differingPixels == 1 ? "" : "s");
}

}  // namespace janus::cli
