// glTF coverage on the GPU (issue 13): every Khronos sample model in ../shared/scenes/khronos
// renders on every configuration in agreement with vulkan/compute, and the self-checking models
// are checked by the test, not by eye: VertexColorTest's "Test" row matches its "Sample pass"
// row, EmissiveStrengthTest's cubes glow in the ratio of their strengths, UnlitTest's objects
// show exactly their base colour.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <tuple>

#include <fmt/format.h>

#include "janus/renderer/image.h"
#include "janus/renderer/renderer.h"
#include "janus/renderer/scene.h"
#include "janus/renderer/scene_view.h"
#include "gltf_test_file.h"
#include "renderer_test_support.h"

namespace janus::renderer {
namespace {

namespace fs = std::filesystem;
using test_support::Config;
using test_support::FrameOutput;

fs::path khronosDir() { return fs::path(JANUS_SHARED_SCENES_DIR) / "khronos"; }

using test_support::khronosModel;

// Every model of ../shared/scenes/khronos (its README lists what each exercises).
const std::array<const char*, 20> kModels = {
    "AnimatedMorphCube",    "BoxInterleaved",       "BoxVertexColors",        "CesiumMan",
    "EmissiveStrengthTest", "Fox",                  "MeshPrimitiveModes",     "MultiUVTest",
    "OrientationTest",      "RiggedSimple",         "SimpleMorph",            "SimpleSkin",
    "SimpleSparseAccessor", "TextureCoordinateTest", "TextureEncodingTest",   "TextureLinearInterpolationTest",
    "TextureSettingsTest",  "TextureTransformTest", "UnlitTest",              "VertexColorTest"};

TEST(KhronosModels, TheListNamesEveryModelInTheFolder) {
    std::set<std::string> onDisk;
    for (const fs::directory_entry& entry : fs::directory_iterator(khronosDir()))
        if (entry.is_directory()) onDisk.insert(entry.path().filename().string());
    const std::set<std::string> listed(kModels.begin(), kModels.end());
    EXPECT_EQ(onDisk, listed) << "a model was added to or removed from " << khronosDir() << ": update kModels";
}

constexpr uint32_t kParitySize = 96;

FrameOutput renderModel(const Config& config, const Scene& scene, uint32_t size) {
    RenderSettings settings;
    settings.width = settings.height = size;
    return test_support::renderOneFrame(config, scene, settings);
}

// `scene` rendered on `config` matches its vulkan/compute render (made once per `stem`) within the
// suite's parity tolerance (test_support::expectMatchesVulkanCompute), with a finite HDR image.
void expectParity(const Scene& scene, const std::string& stem, const Config& config) {
    static std::map<std::string, FrameOutput> references;
    auto reference = references.find(stem);
    if (reference == references.end())
        reference = references.emplace(stem, renderModel(test_support::allConfigs()[0], scene, kParitySize)).first;
    const FrameOutput result = renderModel(config, scene, kParitySize);
    test_support::expectFiniteHdr(result.hdr, stem + " " + config.name());
    test_support::expectMatchesVulkanCompute(reference->second.display, result.display, stem, config);
}

using ModelParam = std::tuple<const char*, Config>;

class KhronosParityTest : public testing::TestWithParam<ModelParam> {};

// Loads (no model is refused any more) and matches vulkan/compute within the suite's parity
// tolerance (test_support::expectMatchesVulkanCompute), with a finite HDR image.
TEST_P(KhronosParityTest, RendersLikeVulkanCompute) {
    const std::string model = std::get<0>(GetParam());
    const Config& config = std::get<1>(GetParam());
    expectParity(loadScene(khronosModel(model)), "khronos-" + model, config);
}

INSTANTIATE_TEST_SUITE_P(Configs, KhronosParityTest,
                         testing::Combine(testing::ValuesIn(kModels), testing::ValuesIn(test_support::allConfigs())),
                         [](const testing::TestParamInfo<ModelParam>& info) {
                             return fmt::format("{}_{}", std::get<0>(info.param), std::get<1>(info.param).name());
                         });

// The animated models also agree at a time other than t = 0 (poses the GPU deforms differently).
const std::array<const char*, 6> kAnimatedModels = {"AnimatedMorphCube", "CesiumMan", "Fox", "RiggedSimple", "SimpleMorph", "SimpleSkin"};

class KhronosAnimatedParityTest : public testing::TestWithParam<ModelParam> {};

TEST_P(KhronosAnimatedParityTest, RendersLikeVulkanComputeAtAnotherTime) {
    const std::string model = std::get<0>(GetParam());
    const Config& config = std::get<1>(GetParam());
    Scene scene = loadScene(khronosModel(model));
    ASSERT_FALSE(scene.animations.empty()) << model;
    poseScene(scene, 0.8f, 0);
    expectParity(scene, "khronos-t0.8-" + model, config);
}

INSTANTIATE_TEST_SUITE_P(Configs, KhronosAnimatedParityTest,
                         testing::Combine(testing::ValuesIn(kAnimatedModels), testing::ValuesIn(test_support::allConfigs())),
                         [](const testing::TestParamInfo<ModelParam>& info) {
                             return fmt::format("{}_{}", std::get<0>(info.param), std::get<1>(info.param).name());
                         });

// --- the self-checking models -------------------------------------------------------------------

constexpr uint32_t kCheckSize = 256;

class KhronosSelfCheckTest : public test_support::ConfigTest {
protected:
    FrameOutput render(const Scene& scene) { return renderModel(GetParam(), scene, kCheckSize); }
};

// The pixel a world point projects to with the scene's camera (row 0 on top).
glm::ivec2 pixelOf(const Scene& scene, glm::vec3 world) {
    const glm::vec4 clip = makeCameraView(scene.camera, kCheckSize, kCheckSize).viewProjection() * glm::vec4(world, 1.0f);
    return glm::ivec2((glm::vec2(clip) / clip.w * 0.5f + 0.5f) * float(kCheckSize));
}

glm::vec4 hdrAt(const ImageRGBAF& hdr, glm::ivec2 p) {
    const size_t at = (size_t(p.y) * hdr.width + size_t(p.x)) * 4;
    return {hdr.pixels[at], hdr.pixels[at + 1], hdr.pixels[at + 2], hdr.pixels[at + 3]};
}

const Instance& instanceNamed(const Scene& scene, const std::string& node) {
    for (const Instance& instance : scene.instances)
        if (instance.nodeName == node) return instance;
    throw std::runtime_error("no node '" + node + "'");
}

// Counts of clearly red, green and blue pixels (one channel over half the brightest, the
// others not) in a box given in fractions of the image.
std::array<uint32_t, 3> primaryCounts(const ImageRGBA8& image, float x0, float y0, float x1, float y1) {
    std::array<uint32_t, 3> counts{};
    for (uint32_t y = uint32_t(y0 * float(image.height)); y < uint32_t(y1 * float(image.height)); ++y)
        for (uint32_t x = uint32_t(x0 * float(image.width)); x < uint32_t(x1 * float(image.width)); ++x) {
            const uint8_t* p = &image.pixels[(size_t(y) * image.width + x) * 4];
            const int top = std::max({int(p[0]), int(p[1]), int(p[2])});
            if (top < 80) continue;
            const bool bright[3] = {p[0] * 2 > top, p[1] * 2 > top, p[2] * 2 > top};
            for (int c = 0; c < 3; ++c)
                if (bright[c] && !bright[(c + 1) % 3] && !bright[(c + 2) % 3]) ++counts[size_t(c)];
        }
    return counts;
}

// The model's top row ("Test") colours its check marks with COLOR_0 (a white texture times red,
// green and blue vertex colours); the bottom row ("Sample pass") draws the same marks from a
// texture. Each of the three cells must show the same mark in the same colour in both rows.
// Where the cells are (fractions of the image) follows from the auto-framed camera, which sees
// the model head-on.
TEST_P(KhronosSelfCheckTest, VertexColorTestRowsMatch) {
    const FrameOutput output = render(loadScene(khronosModel("VertexColorTest")));
    const std::string label = GetParam().name();
    constexpr float kColumns[3] = {0.325f, 0.485f, 0.652f};   // red, green, blue cells' centres
    constexpr float kTestRow = 0.40f, kSampleRow = 0.665f, kHalf = 0.045f;
    for (size_t c = 0; c < 3; ++c) {
        const auto test = primaryCounts(output.display, kColumns[c] - kHalf, kTestRow - kHalf, kColumns[c] + kHalf, kTestRow + kHalf);
        const auto sample = primaryCounts(output.display, kColumns[c] - kHalf, kSampleRow - kHalf, kColumns[c] + kHalf, kSampleRow + kHalf);
        const std::string where = fmt::format("{} cell {}: test row r/g/b {}/{}/{}, sample row {}/{}/{}", label, c, test[0], test[1], test[2],
                                              sample[0], sample[1], sample[2]);
        EXPECT_GT(sample[c], 40u) << where << " (the sample row's mark is not where the test expects it)";
        // The same mark: within a fifth in pixel count, and no mark of another colour.
        EXPECT_GT(test[c] * 5, sample[c] * 4) << where;
        EXPECT_LT(test[c] * 4, sample[c] * 5) << where;
        for (size_t other = 0; other < 3; ++other)
            if (other != c) {
                EXPECT_LT(test[other], 5u) << where;
            }
    }
    if (testing::Test::HasFailure()) writePNG(test_support::outputDir() / fmt::format("vertex-color-test-{}.png", label), output.display);
}

// Five cubes, emissiveFactor (0.1, 0.5, 0.9) with KHR_materials_emissive_strength 1 (none), 2,
// 4, 8, 16. Black and fully metallic, they reflect the key light at grazing angles (about 0.01):
// without lights and ambient light, what the camera sees of them is their emission alone, so the
// HDR radiance at each cube's centre is (0.1, 0.5, 0.9) times its strength, up to the target's
// half-float conversion (one step, relative 2^-10: the drivers round toward zero).
TEST_P(KhronosSelfCheckTest, EmissiveStrengthTestCubesGlowByTheirStrength) {
    Scene scene = loadScene(khronosModel("EmissiveStrengthTest"));
    scene.lights.clear();
    scene.environment.ambientColor = glm::vec3(0.0f);
    const FrameOutput output = render(scene);
    for (const auto& [node, strength] : {std::pair{"Cube1", 1.0f}, {"Cube2", 2.0f}, {"Cube4", 4.0f}, {"Cube8", 8.0f}, {"Cube16", 16.0f}}) {
        const glm::ivec2 pixel = pixelOf(scene, glm::vec3(instanceNamed(scene, node).world[3]));
        const glm::vec4 radiance = hdrAt(output.hdr, pixel);
        const glm::vec3 expected = glm::vec3(0.1f, 0.5f, 0.9f) * strength;
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(radiance[c], expected[c], expected[c] / 1024.0f + 1e-6f)
                << GetParam().name() << " " << node << " channel " << c << " at pixel " << pixel.x << "," << pixel.y;
    }
}

// KHR_materials_unlit: the radiance is the base colour, whatever the lights, exactly up to the
// HDR target's half-float conversion (the drivers round toward zero: up to one half-float step,
// relative 2^-10).
TEST_P(KhronosSelfCheckTest, UnlitTestShowsItsBaseColour) {
    const Scene scene = loadScene(khronosModel("UnlitTest"));
    const FrameOutput output = render(scene);
    for (const auto& [node, material] : {std::pair{"Orange Object", 0}, {"Blue Object", 1}}) {
        ASSERT_TRUE(scene.materials.at(size_t(material)).unlit);
        const glm::vec4 base = scene.materials[size_t(material)].baseColorFactor;
        const glm::ivec2 pixel = pixelOf(scene, glm::vec3(instanceNamed(scene, node).world[3]));
        const glm::vec4 radiance = hdrAt(output.hdr, pixel);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(radiance[c], base[c], base[c] / 1024.0f + 1e-6f) << GetParam().name() << " " << node << " channel " << c;
    }
}

INSTANTIATE_TEST_SUITE_P(Configs, KhronosSelfCheckTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
