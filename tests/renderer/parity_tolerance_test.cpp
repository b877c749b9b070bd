// The suite's parity rule (test_support::parityProblem) against what real drivers produced
// (tests/renderer/data/nvidia_gl_vs_vulkan.csv): NVIDIA's GL and Vulkan compilers' rounding must
// pass where two compilers are involved, and the bug that hardware found (labels sampled at mip 0
// after a discard) must fail either way, or the tolerance hides what the suite exists to catch.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>

#include "janus/renderer/parity.h"
#include "renderer_test_support.h"

namespace janus::renderer {
namespace {

using test_support::parityProblem;
using test_support::ShaderCompilers;

struct RecordedPair {
    ImageRGBA8 vulkan;
    ImageRGBA8 gl;
};

// Each case of the file as two images that agree everywhere but at its recorded pixels.
std::map<std::string, RecordedPair> recordedPairs() {
    const std::filesystem::path file = std::filesystem::path(__FILE__).parent_path() / "data" / "nvidia_gl_vs_vulkan.csv";
    std::ifstream in(file);
    if (!in) throw std::runtime_error("cannot read " + file.string());
    std::map<std::string, RecordedPair> pairs;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#' || line.starts_with("case,")) continue;
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream fields(line);
        std::string name;
        uint32_t width = 0, height = 0, x = 0, y = 0;
        std::array<int, 8> values{};
        fields >> name >> width >> height >> x >> y;
        for (int& v : values) fields >> v;
        if (!fields || x >= width || y >= height) throw std::runtime_error("malformed line in " + file.string() + ": " + line);
        RecordedPair& pair = pairs[name];
        for (ImageRGBA8* image : {&pair.vulkan, &pair.gl}) {
            if (image->pixels.empty()) {
                image->width = width;
                image->height = height;
                image->pixels.assign(size_t(width) * height * 4, 128);
            }
        }
        for (int c = 0; c < 4; ++c) {
            pair.vulkan.pixels[(size_t(y) * width + x) * 4 + c] = uint8_t(values[c]);
            pair.gl.pixels[(size_t(y) * width + x) * 4 + c] = uint8_t(values[4 + c]);
        }
    }
    return pairs;
}

TEST(ParityTolerance, NvidiasCompilerRoundingPassesOnlyAsTwoCompilers) {
    const RecordedPair helmet = recordedPairs().at("helmet");
    EXPECT_EQ(parityProblem(helmet.vulkan, helmet.gl, ShaderCompilers::Different), "");
    // Held to one compiler's rule, the same pixels fail: the allowance is what lets them pass.
    EXPECT_NE(parityProblem(helmet.vulkan, helmet.gl, ShaderCompilers::Same), "");
}

TEST(ParityTolerance, TheLabelsSampledAtMipZeroFailEitherWay) {
    const RecordedPair labels = recordedPairs().at("labels-after-discard");
    const std::string problem = parityProblem(labels.vulkan, labels.gl, ShaderCompilers::Different);
    EXPECT_NE(problem.find("62 pixels more than 1 step off (up to 121 steps), 58 more than 4 steps"), std::string::npos) << problem;
    EXPECT_NE(parityProblem(labels.vulkan, labels.gl, ShaderCompilers::Same), "");
}

TEST(ParityTolerance, CountsAndStepsAtTheirLimits) {
    ImageRGBA8 reference;
    reference.width = reference.height = 40;   // 1600 pixels: 4 compiler-noise pixels allowed besides 4 silhouettes
    reference.pixels.assign(1600 * 4, 100);
    auto offBy = [&](uint32_t pixels, uint8_t steps) {
        ImageRGBA8 image = reference;
        for (uint32_t p = 0; p < pixels; ++p) image.pixels[size_t(p) * 4 + 1] = uint8_t(100 + steps);
        return image;
    };
    EXPECT_EQ(parityProblem(reference, offBy(1600, 1), ShaderCompilers::Same), "");        // one step anywhere
    EXPECT_EQ(parityProblem(reference, offBy(4, 200), ShaderCompilers::Same), "");         // four silhouettes
    EXPECT_NE(parityProblem(reference, offBy(5, 2), ShaderCompilers::Same), "");
    EXPECT_EQ(parityProblem(reference, offBy(8, 4), ShaderCompilers::Different), "");     // 4 + 1600 / 400
    EXPECT_NE(parityProblem(reference, offBy(9, 4), ShaderCompilers::Different), "");
    EXPECT_NE(parityProblem(reference, offBy(5, 5), ShaderCompilers::Different), "");     // over 4 steps: silhouettes only
    EXPECT_EQ(parityProblem(reference, offBy(4, 5), ShaderCompilers::Different), "");
}

rhi::DeviceInfo device(rhi::Backend backend, std::string name) {
    rhi::DeviceInfo info;
    info.backend = backend;
    info.deviceName = std::move(name);
    return info;
}

TEST(ParityTolerance, WhichDevicesShareAShaderCompiler) {
    const std::string lavapipe = "llvmpipe (LLVM 15.0.6, 256 bits)";
    const std::string nvidiaVulkan = "NVIDIA H100 80GB HBM3", nvidiaGL = "NVIDIA H100 80GB HBM3/PCIe/SSE2";
    EXPECT_TRUE(shareShaderCompiler(device(rhi::Backend::Vulkan, lavapipe), device(rhi::Backend::GL, lavapipe)));
    EXPECT_TRUE(shareShaderCompiler(device(rhi::Backend::GLES, lavapipe), device(rhi::Backend::Vulkan, lavapipe)));
    EXPECT_TRUE(shareShaderCompiler(device(rhi::Backend::GL, nvidiaGL), device(rhi::Backend::GLES, nvidiaGL)));
    EXPECT_TRUE(shareShaderCompiler(device(rhi::Backend::Vulkan, nvidiaVulkan), device(rhi::Backend::Vulkan, nvidiaVulkan)));
    EXPECT_FALSE(shareShaderCompiler(device(rhi::Backend::Vulkan, nvidiaVulkan), device(rhi::Backend::GL, nvidiaGL)));
    EXPECT_FALSE(shareShaderCompiler(device(rhi::Backend::Vulkan, nvidiaVulkan), device(rhi::Backend::Vulkan, lavapipe)));
    EXPECT_FALSE(shareShaderCompiler(device(rhi::Backend::GL, nvidiaGL), device(rhi::Backend::GL, lavapipe)));
}

TEST(ParityTolerance, AWiderToleranceLeavesTheRoundingAllowanceNothingToAdd) {
    const RecordedPair helmet = recordedPairs().at("helmet");
    ParityRule rule;
    rule.tolerance = 3;   // the helmet's worst pixel
    const ParityVerdict verdict = judgeParity(helmet.vulkan, helmet.gl, rule);
    EXPECT_TRUE(verdict.agrees) << verdict.problem;
    EXPECT_EQ(verdict.roundingPixels, 0u);
    const ParityVerdict rounded = judgeParity(helmet.vulkan, helmet.gl, withCompilerRounding(ParityRule{}));
    EXPECT_TRUE(rounded.agrees) << rounded.problem;
    EXPECT_EQ(rounded.roundingPixels, 14u);   // the 14 recorded pixels two or three steps off
}

}  // namespace
}  // namespace janus::renderer
