// Shared by the renderer's GPU tests: the five configurations, one validated device per backend
// per test process (starting a device costs far more than a frame), and a one-frame render that
// fails the current test on any validation / GL debug message.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "janus/renderer/image.h"
#include "janus/renderer/renderer.h"
#include "janus/renderer/scene.h"
#include "janus/rhi/rhi.h"

namespace janus::renderer::test_support {

struct Config {
    rhi::Backend backend;
    FeaturePath path;
    std::string name() const;   // "vulkan_compute", "gles_fallback", ...
};
void PrintTo(const Config& config, std::ostream* os);

// vulkan/compute (the reference) first, then vulkan/fallback, gl/compute, gl/fallback, gles/fallback.
const std::vector<Config>& allConfigs();

rhi::IDevice& deviceFor(rhi::Backend backend);
std::string joinMessages(const std::vector<rhi::DebugMessage>& messages);

// Where failing comparisons leave their images for a look.
std::filesystem::path outputDir();

struct FrameOutput {
    FrameReport report;
    ImageRGBA8 display;
    ImageRGBAF hdr;
    std::optional<TileLists> tiles;   // when asked for and the frame built tiles
    std::vector<float> depth;         // when asked for
};

struct ReadBack {
    bool tiles = false;
    bool depth = false;
};

// Renders one frame of `scene` on `config` with `settings` (its path is replaced by the
// config's). Adds a test failure naming the config for any debug message the device produced.
FrameOutput renderOneFrame(const Config& config, const Scene& scene, RenderSettings settings, ReadBack readBack = {});

constexpr uint32_t kSize = 128;   // small: llvmpipe/lavapipe render on two CPU cores

Light pointLight(glm::vec3 position, glm::vec3 color, float intensity, std::optional<float> range);
Light spotLight(glm::vec3 position, glm::vec3 direction, glm::vec3 color, float intensity, std::optional<float> range,
                float innerConeAngle, float outerConeAngle);

// size x size with the given culling mode, everything else unset (scene quality, then defaults).
RenderSettings settingsFor(LightCulling culling, uint32_t size = kSize);

// For labels. Not toString(LightCulling): these tests stay independent of the code they check.
const char* cullingName(LightCulling mode);

bool hasPassStartingWith(const FrameReport& report, std::string_view prefix);
uint32_t countPasses(const FrameReport& report, std::string_view prefix);   // passes whose name starts with it
std::string passNames(const FrameReport& report);   // for failure messages

// The world matrix that puts detail::makeQuad's 2 x 2 quad (in XY, facing +Z) at `center`, facing
// `normal`, `size` metres wide; mirrored: x flipped (a negative determinant, the same front side).
glm::mat4 quadFacing(const glm::vec3& center, const glm::vec3& normal, float size = 2.0f, bool mirrored = false);
// A closed 2 m room around the origin: six quads facing inwards, wall f (+X, -X, +Y, -Y, +Z, -Z)
// emitting emission[f] and reflecting `albedo`; named "wall 0".."wall 5".
void addGlowingRoom(Scene& scene, const std::array<glm::vec3, 6>& emission, float albedo = 0.0f, bool doubleSided = true);

// Every HDR value finite and non-negative (radiance); reports the first bad one.
void expectFiniteHdr(const ImageRGBAF& hdr, const std::string& label);

// The layout of docs/LIGHTING.md ("Tile lists"): grid size from the image size, counts within
// the cap, indices below the local light count and ascending, and agreement with the report.
void expectWellFormedTileLists(const TileLists& tiles, const LightCullingReport& report, uint32_t width, uint32_t height,
                               const std::string& label);

// Display images within 1 step and HDR within 1e-3 relative (see the definition for why);
// failing images are written to outputDir() with `label` in their names.
void expectSameImage(const FrameOutput& expected, const FrameOutput& actual, const std::string& label);

// Whether two configurations' shaders go through one compiler (renderer::shareShaderCompiler of
// their devices): then their images are held to the last bit of shading math.
enum class ShaderCompilers { Same, Different };
ShaderCompilers shaderCompilersOf(rhi::Backend a, rhi::Backend b);

// The suite's parity rule (see the definition for why it allows what it allows): empty when
// `result` agrees with `reference`, else a sentence saying how far it is off.
std::string parityProblem(const ImageRGBA8& reference, const ImageRGBA8& result, ShaderCompilers compilers);

// Cross-configuration parity against vulkan/compute by parityProblem(), the compilers those of
// vulkan and `config`'s backend. On failure writes <stem>-<config>.png, <stem>-vulkan_compute.png
// and <stem>-<config>-diff.png to outputDir().
void expectMatchesVulkanCompute(const ImageRGBA8& reference, const ImageRGBA8& result, const std::string& stem,
                                const Config& config);

// What the parameterised renderer suites share: the config's device, settings of a size on the
// config's path, and no debug messages since the last take.
class ConfigTest : public testing::TestWithParam<Config> {
protected:
    rhi::IDevice& device() const { return deviceFor(GetParam().backend); }
    RenderSettings settingsOfSize(uint32_t width, uint32_t height) const {
        RenderSettings s;
        s.width = width;
        s.height = height;
        s.path = GetParam().path;
        return s;
    }
    void expectNoMessages() const {
        const std::vector<rhi::DebugMessage> messages = device().takeDebugMessages();
        EXPECT_TRUE(messages.empty()) << GetParam().name() << ":" << joinMessages(messages);
    }
};

}  // namespace janus::renderer::test_support
