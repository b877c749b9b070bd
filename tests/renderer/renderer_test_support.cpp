#include "renderer/renderer_test_support.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include "janus/renderer/parity.h"
#include "scene/scene_internal.h"

namespace janus::renderer::test_support {

std::string Config::name() const { return fmt::format("{}_{}", rhi::toString(backend), toString(path)); }

void PrintTo(const Config& config, std::ostream* os) { *os << config.name(); }

const std::vector<Config>& allConfigs() {
    static const std::vector<Config> configs = {
        {rhi::Backend::Vulkan, FeaturePath::Compute}, {rhi::Backend::Vulkan, FeaturePath::Fallback},
        {rhi::Backend::GL, FeaturePath::Compute},     {rhi::Backend::GL, FeaturePath::Fallback},
        {rhi::Backend::GLES, FeaturePath::Fallback},
    };
    return configs;
}

namespace {
std::map<rhi::Backend, std::unique_ptr<rhi::IDevice>>& sharedDevices() {
    static std::map<rhi::Backend, std::unique_ptr<rhi::IDevice>> devices;
    return devices;
}

// The shared devices go when the tests have run, not among the static destructors: by then a
// driver may have shut its EGL down (NVIDIA's does at exit, issue 10), leaving the device unable
// to release its objects.
class ReleaseSharedDevices : public testing::Environment {
public:
    void TearDown() override { sharedDevices().clear(); }
};
[[maybe_unused]] testing::Environment* const kReleaseSharedDevices =
    testing::AddGlobalTestEnvironment(new ReleaseSharedDevices);
}  // namespace

rhi::IDevice& deviceFor(rhi::Backend backend) {
    std::unique_ptr<rhi::IDevice>& device = sharedDevices()[backend];
    if (!device) device = rhi::createDevice(rhi::DeviceDesc{}.setBackend(backend).setEnableValidation(true).setEnableSynchronizationValidation(true));
    return *device;
}

std::string joinMessages(const std::vector<rhi::DebugMessage>& messages) {
    std::string text;
    for (const rhi::DebugMessage& m : messages) text += "\n  " + m.text;
    return text;
}

std::filesystem::path outputDir() {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "janus-renderer-tests";
    std::filesystem::create_directories(dir);
    return dir;
}

FrameOutput renderOneFrame(const Config& config, const Scene& scene, RenderSettings settings, ReadBack readBack) {
    rhi::IDevice& device = deviceFor(config.backend);
    device.takeDebugMessages();
    settings.path = config.path;
    FrameOutput output;
    {
        Renderer renderer(device, scene, settings);
        output.report = renderer.renderFrame();
        output.display = renderer.readDisplayImage();
        output.hdr = renderer.readHdrImage();
        if (readBack.tiles && output.report.lightCulling && output.report.lightCulling->mode != LightCulling::Naive)
            output.tiles = renderer.readTileLists();
        if (readBack.depth) output.depth = renderer.readDepth();
    }
    const std::vector<rhi::DebugMessage> messages = device.takeDebugMessages();
    EXPECT_TRUE(messages.empty()) << config.name() << " produced validation / debug messages:" << joinMessages(messages);
    return output;
}

Light pointLight(glm::vec3 position, glm::vec3 color, float intensity, std::optional<float> range) {
    Light light;
    light.type = LightType::Point;
    light.position = position;
    light.color = color;
    light.intensity = intensity;
    light.range = range;
    return light;
}

Light spotLight(glm::vec3 position, glm::vec3 direction, glm::vec3 color, float intensity, std::optional<float> range,
                float innerConeAngle, float outerConeAngle) {
    Light light = pointLight(position, color, intensity, range);
    light.type = LightType::Spot;
    light.direction = glm::normalize(direction);
    light.innerConeAngle = innerConeAngle;
    light.outerConeAngle = outerConeAngle;
    return light;
}

RenderSettings settingsFor(LightCulling culling, uint32_t size) {
    RenderSettings settings;
    settings.width = size;
    settings.height = size;
    settings.lighting.culling = culling;
    return settings;
}

const char* cullingName(LightCulling mode) { return toString(mode); }

bool hasPassStartingWith(const FrameReport& report, std::string_view prefix) {
    return std::any_of(report.passes.begin(), report.passes.end(), [&](const PassReport& pass) { return pass.name.starts_with(prefix); });
}

uint32_t countPasses(const FrameReport& report, std::string_view prefix) {
    return uint32_t(std::count_if(report.passes.begin(), report.passes.end(), [&](const PassReport& pass) { return pass.name.starts_with(prefix); }));
}

glm::mat4 quadFacing(const glm::vec3& center, const glm::vec3& normal, float size, bool mirrored) {
    const glm::vec3 n = glm::normalize(normal);
    const glm::vec3 up = std::abs(n.y) > 0.5f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
    const glm::vec3 right = glm::normalize(glm::cross(up, n));
    glm::mat4 world(1.0f);
    world[0] = glm::vec4(right * (size * 0.5f) * (mirrored ? -1.0f : 1.0f), 0.0f);
    world[1] = glm::vec4(glm::cross(n, right) * (size * 0.5f), 0.0f);
    world[2] = glm::vec4(n, 0.0f);
    world[3] = glm::vec4(center, 1.0f);
    return world;
}

void addGlowingRoom(Scene& scene, const std::array<glm::vec3, 6>& emission, float albedo, bool doubleSided) {
    const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int face = 0; face < 6; ++face) {
        const int32_t material = detail::addMaterial(scene, fmt::format("wall {}", face), glm::vec3(albedo), 0.0f, 1.0f, emission[face]);
        scene.materials[size_t(material)].doubleSided = doubleSided;
        const uint32_t mesh = detail::addMesh(scene, detail::makeQuad(material));
        scene.instances.push_back(Instance{mesh, quadFacing(axes[face], -axes[face]), 1u, fmt::format("wall {}", face)});
    }
}

std::string passNames(const FrameReport& report) {
    std::string names;
    for (const PassReport& pass : report.passes) names += (names.empty() ? "" : ", ") + pass.name;
    return names;
}

// Every value finite and non-negative (radiance); stops at the first bad one.
void expectFiniteHdr(const ImageRGBAF& hdr, const std::string& label) {
    for (size_t i = 0; i < hdr.pixels.size(); ++i) {
        const float v = hdr.pixels[i];
        if (!std::isfinite(v) || v < 0.0f) {
            ADD_FAILURE() << label << ": HDR value " << v << " at pixel " << i / 4 << " channel " << i % 4;
            return;
        }
    }
}

// The layout docs/LIGHTING.md gives, and what the frame report says about the same lists.
void expectWellFormedTileLists(const TileLists& tiles, const LightCullingReport& report, uint32_t width, uint32_t height,
                               const std::string& label) {
    ASSERT_GT(tiles.tileSize, 0u) << label;
    EXPECT_EQ(tiles.tileSize, report.tileSize) << label;
    EXPECT_EQ(tiles.tilesX, (width + tiles.tileSize - 1) / tiles.tileSize) << label;
    EXPECT_EQ(tiles.tilesY, (height + tiles.tileSize - 1) / tiles.tileSize) << label;
    EXPECT_EQ(tiles.tilesX, report.tilesX) << label;
    EXPECT_EQ(tiles.tilesY, report.tilesY) << label;
    EXPECT_EQ(tiles.maxLightsPerTile, report.maxLightsPerTile) << label;
    const size_t tileCount = size_t(tiles.tilesX) * tiles.tilesY;
    ASSERT_EQ(tiles.counts.size(), tileCount) << label;
    ASSERT_EQ(tiles.indices.size(), tileCount * tiles.maxLightsPerTile) << label;
    uint64_t listed = 0;
    for (size_t t = 0; t < tileCount; ++t) {
        const uint32_t count = tiles.counts[t];
        ASSERT_LE(count, tiles.maxLightsPerTile) << label << " tile " << t;
        listed += count;
        for (uint32_t k = 0; k < count; ++k) {
            const uint32_t index = tiles.indices[t * tiles.maxLightsPerTile + k];
            ASSERT_LT(index, report.localLights) << label << " tile " << t << " entry " << k;
            if (k > 0) {
                // Ascending: the tiled sum then runs in the naive loop's order.
                ASSERT_LT(tiles.indices[t * tiles.maxLightsPerTile + k - 1], index) << label << " tile " << t << " entry " << k;
            }
        }
    }
    EXPECT_EQ(listed, report.listedLights) << label;
}

// Used where two frame plans must light the scene identically, e.g. tiled vs naive: tiles only
// skip lights whose contribution is exactly zero and the sum runs in the same ascending order, so
// a difference of 0 is expected everywhere; the tolerances
// allow for the shader compiler contracting the two loops' arithmetic differently (FMA), which
// moves a value by at most a rounding step: 1 step of 8-bit display, and 1e-3 relative in HDR,
// which is just over one RGBA16F ulp (2^-10 relative), plus 1e-7 absolute for fp16 subnormals.
void expectSameImage(const FrameOutput& expected, const FrameOutput& actual, const std::string& label) {
    const ImageDifference diff = compareImages(expected.display, actual.display, 1);
    if (diff.maxChannelDifference > 1) {
        const std::filesystem::path dir = outputDir();
        writePNG(dir / (label + "-expected.png"), expected.display);
        writePNG(dir / (label + "-actual.png"), actual.display);
        writePNG(dir / (label + "-diff.png"), differenceHeatmap(expected.display, actual.display));
        ADD_FAILURE() << label << ": display differs from the expected image by up to " << diff.maxChannelDifference << " steps in "
                      << diff.differingPixels << " pixels; images in " << dir;
    }
    ASSERT_EQ(expected.hdr.pixels.size(), actual.hdr.pixels.size()) << label;
    uint64_t badValues = 0;
    std::string first;
    for (size_t i = 0; i < expected.hdr.pixels.size(); ++i) {
        const float a = expected.hdr.pixels[i], b = actual.hdr.pixels[i];
        if (!(std::abs(a - b) <= 1e-3f * std::max(std::abs(a), std::abs(b)) + 1e-7f)) {
            if (badValues++ == 0) first = fmt::format("pixel ({}, {}) channel {}: expected {} actual {}", i / 4 % expected.hdr.width, i / 4 / expected.hdr.width, i % 4, a, b);
        }
    }
    EXPECT_EQ(badValues, 0u) << label << ": HDR values differ from the expected image beyond 1e-3 relative; first at " << first;
}

ShaderCompilers shaderCompilersOf(rhi::Backend a, rhi::Backend b) {
    return shareShaderCompiler(deviceFor(a).info(), deviceFor(b).info()) ? ShaderCompilers::Same : ShaderCompilers::Different;
}

// The rule janus parity applies too (janus/renderer/parity.h says why it allows what it allows):
// at most 1 step, but for 4 edge pixels, and between two compilers 1 pixel in 400 up to 4 steps.
// One compiler: seen 1 edge pixel of 16384 on MetalRoughSpheres at 128x128 on Mesa; two
// compilers: tests/renderer/data/nvidia_gl_vs_vulkan.csv, which parity_tolerance_test.cpp checks.
std::string parityProblem(const ImageRGBA8& reference, const ImageRGBA8& result, ShaderCompilers compilers) {
    const ParityRule rule = compilers == ShaderCompilers::Same ? ParityRule{} : withCompilerRounding(ParityRule{});
    return judgeParity(reference, result, rule).problem;
}

void expectMatchesVulkanCompute(const ImageRGBA8& reference, const ImageRGBA8& result, const std::string& stem, const Config& config) {
    const std::string problem = parityProblem(reference, result, shaderCompilersOf(rhi::Backend::Vulkan, config.backend));
    if (problem.empty()) return;
    const std::filesystem::path dir = outputDir();
    writePNG(dir / fmt::format("{}-{}.png", stem, config.name()), result);
    writePNG(dir / fmt::format("{}-vulkan_compute.png", stem), reference);
    writePNG(dir / fmt::format("{}-{}-diff.png", stem, config.name()), differenceHeatmap(reference, result));
    ADD_FAILURE() << config.name() << " differs from vulkan/compute: " << problem << "; images in " << dir;
}

}  // namespace janus::renderer::test_support
