#include "janus/renderer/parity.h"

#include <fmt/format.h>

#include <algorithm>

namespace janus::renderer {
namespace {
std::string steps(uint32_t count) { return fmt::format("{} step{}", count, count == 1 ? "" : "s"); }
}  // namespace

ParityRule withCompilerRounding(ParityRule rule) {
    rule.roundingSteps = kCompilerRoundingSteps;
    rule.roundingOnePixelIn = kCompilerRoundingOnePixelIn;
    return rule;
}

ParityVerdict judgeParity(const ImageRGBA8& a, const ImageRGBA8& b, const ParityRule& rule) {
    ParityVerdict verdict;
    verdict.difference = compareImages(a, b, rule.tolerance);
    const ImageDifference& beyond = verdict.difference;
    if (beyond.maxChannelDifference <= rule.tolerance || beyond.differingPixels <= rule.edgePixels) {
        verdict.agrees = true;
        return verdict;
    }
    const std::string found = fmt::format("{} pixels more than {} off (up to {})", beyond.differingPixels, steps(rule.tolerance),
                                          steps(beyond.maxChannelDifference));
    if (rule.roundingOnePixelIn == 0 || rule.roundingSteps <= rule.tolerance) {
        verdict.problem = fmt::format("{}; the rule allows {} (edge pixels)", found, rule.edgePixels);
        return verdict;
    }
    const uint64_t beyondRounding = compareImages(a, b, rule.roundingSteps).differingPixels;
    const uint64_t roundingAllowance = beyond.totalPixels / rule.roundingOnePixelIn;
    if (beyondRounding <= rule.edgePixels && beyond.differingPixels <= rule.edgePixels + roundingAllowance) {
        verdict.agrees = true;
        verdict.roundingPixels = beyond.differingPixels - std::min(beyond.differingPixels, beyondRounding);
        return verdict;
    }
    verdict.problem = fmt::format(
        "{}, {} more than {}; two shader compilers' rounding allows {} more than {} and {} (edge pixels) more than {}", found,
        beyondRounding, steps(rule.roundingSteps), rule.edgePixels + roundingAllowance, steps(rule.tolerance), rule.edgePixels,
        steps(rule.roundingSteps));
    return verdict;
}

bool shareShaderCompiler(const rhi::DeviceInfo& a, const rhi::DeviceInfo& b) {
    auto glsl = [](rhi::Backend backend) { return backend == rhi::Backend::GL || backend == rhi::Backend::GLES; };
    const bool oneFrontEnd = a.backend == b.backend || (glsl(a.backend) && glsl(b.backend));
    if (oneFrontEnd && a.deviceName == b.deviceName) return true;
    auto llvmpipe = [](const rhi::DeviceInfo& info) { return info.deviceName.find("llvmpipe") != std::string::npos; };
    return llvmpipe(a) && llvmpipe(b);
}

}  // namespace janus::renderer
