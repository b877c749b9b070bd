// texCoord and KHR_texture_transform on the GPU, on every configuration: each material texture is
// sampled at its UV set through its transform in the forward pass, the depth prepass (alpha MASK)
// and the transparent pass' shared shaders. Built-in quads with 4x4 nearest-filtered textures show
// known texels at known pixels, computed here on the CPU; the Khronos TextureTransformTest model is
// checked through the patches it draws to say what is right.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "janus/renderer/image.h"
#include "janus/renderer/renderer.h"
#include "janus/renderer/scene_view.h"
#include "renderer/renderer_test_support.h"
#include "scene/scene_internal.h"

namespace janus::renderer {
namespace {

namespace fs = std::filesystem;
using test_support::Config;
using test_support::FrameOutput;

constexpr uint32_t kWidth = 256, kHeight = 128;
constexpr uint32_t kTexels = 4;

// 4x4 RGBA8, not sRGB (radiance is texel / 255), nearest, no mips, repeating: texel (x, y) has a
// red step per column and a green step per row, so every texel differs.
TextureImage checker(const std::string& name, bool alternatingAlpha) {
    TextureImage image;
    image.name = name;
    image.width = image.height = kTexels;
    image.sampling.nearestMagnification = image.sampling.nearestMinification = true;
    image.sampling.mipmapped = false;
    for (uint32_t y = 0; y < kTexels; ++y)
        for (uint32_t x = 0; x < kTexels; ++x) {
            const uint8_t alpha = alternatingAlpha && (x + y) % 2 == 1 ? 0 : 255;
            // Blue alternates 0 / 255 like the alpha so metallic (B) steps between its extremes.
            image.rgba.insert(image.rgba.end(), {uint8_t(20 + 70 * x), uint8_t(20 + 70 * y), uint8_t((x + y) % 2 ? 0 : 255), alpha});
        }
    return image;
}

glm::vec4 texel(const TextureImage& image, glm::vec2 uv) {
    const auto wrap = [](float coordinate) {
        const int64_t i = int64_t(std::floor(coordinate * float(kTexels)));
        return uint32_t(((i % kTexels) + kTexels) % kTexels);
    };
    const size_t at = (size_t(wrap(uv.y)) * kTexels + wrap(uv.x)) * 4;
    return glm::vec4(image.rgba[at], image.rgba[at + 1], image.rgba[at + 2], image.rgba[at + 3]) / 255.0f;
}

// Whether `uv` is at least a tenth of a texel from every texel edge: pixels nearer an edge could
// fall either side of it by rounding, so they are not checked.
bool clearOfTexelEdges(glm::vec2 uv) {
    const glm::vec2 f = glm::fract(uv * float(kTexels));
    return f.x > 0.1f && f.x < 0.9f && f.y > 0.1f && f.y < 0.9f;
}

// The second UV set of the built-in quads: mirrored in u and halved in v, so it differs from the first everywhere but on a line.
glm::vec2 secondUvOf(glm::vec2 uv) { return {1.0f - uv.x, 0.5f * uv.y + 0.25f}; }

enum class Probe { Emissive, BaseColorMask, Occlusion, Metallic };

struct QuadCase {
    const char* name;
    Probe probe;
    TextureTransform transform;
};

TextureTransform transformOf(glm::vec2 offset, float rotation, glm::vec2 scale, uint32_t texCoord = 0) {
    TextureTransform t;
    t.offset = offset;
    t.rotation = rotation;
    t.scale = scale;
    t.texCoord = texCoord;
    return t;
}

const QuadCase kQuads[] = {
    {"emissive offset", Probe::Emissive, transformOf({0.25f, 0.5f}, 0.0f, {1.0f, 1.0f})},
    {"emissive rotation", Probe::Emissive, transformOf({0.0f, 0.0f}, 0.6f, {1.0f, 1.0f})},
    {"emissive scale", Probe::Emissive, transformOf({0.0f, 0.0f}, 0.0f, {2.0f, 0.5f})},
    {"emissive offset rotation scale", Probe::Emissive, transformOf({0.1f, -0.3f}, -1.0f, {1.5f, 2.5f})},
    {"emissive texCoord 1", Probe::Emissive, transformOf({0.0f, 0.0f}, 0.0f, {1.0f, 1.0f}, 1)},
    {"base colour alpha mask, texCoord 1 rotated", Probe::BaseColorMask, transformOf({0.3f, 0.1f}, 0.4f, {1.25f, 1.0f}, 1)},
    {"occlusion offset rotation scale", Probe::Occlusion, transformOf({-0.2f, 0.35f}, 2.0f, {0.75f, 1.5f})},
    {"metallic texCoord 1 offset rotation scale", Probe::Metallic, transformOf({0.6f, 0.2f}, -0.7f, {1.5f, 0.8f}, 1)},
};
constexpr size_t kQuadCount = std::size(kQuads);

glm::vec3 quadCenter(size_t i) { return {-1.5f + float(i % 4), i < 4 ? 0.5f : -0.5f, 0.0f}; }
constexpr float kHalfSize = 0.45f;

// The ambient light, which is also the background colour (what a discarded pixel shows).
constexpr float kAmbient = 0.5f;
// What the masked quad emits where it is not discarded: unlike the background.
const glm::vec3 kMaskedEmission(0.0f, 1.0f, 0.0f);

// Eight quads in two rows of four facing the camera. Ambient light only: emissive and masked
// quads are black metal (ambient adds nothing), so they show their emission; the occlusion and
// metallic quads are white, so ambient * (diffuse + F0) * occlusion shows the texel.
Scene quadsScene() {
    Scene scene;
    scene.name = "texture transforms";
    scene.camera.position = {0.0f, 0.0f, 2.4f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    scene.camera.fovYRadians = glm::radians(50.0f);
    scene.camera.nearPlane = 0.1f;
    scene.camera.farPlane = 20.0f;
    scene.environment.ambientColor = glm::vec3(kAmbient);
    scene.textures.push_back(checker("checker", false));
    scene.textures.push_back(checker("checker with holes", true));
    for (size_t i = 0; i < kQuadCount; ++i) {
        const QuadCase& quad = kQuads[i];
        Material material;
        material.name = quad.name;
        material.roughnessFactor = 1.0f;
        switch (quad.probe) {
            case Probe::Emissive:
                material.baseColorFactor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
                material.metallicFactor = 1.0f;
                material.emissiveFactor = glm::vec3(1.0f);
                material.emissiveTexture = 0;
                material.emissiveTransform = quad.transform;
                break;
            case Probe::BaseColorMask:
                material.baseColorFactor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
                material.metallicFactor = 1.0f;
                material.emissiveFactor = kMaskedEmission;
                material.alphaMode = AlphaMode::Mask;
                material.baseColorTexture = 1;
                material.baseColorTransform = quad.transform;
                break;
            case Probe::Occlusion:
                material.metallicFactor = 0.0f;
                material.occlusionTexture = 0;
                material.occlusionTransform = quad.transform;
                break;
            case Probe::Metallic:
                material.metallicFactor = 1.0f;
                material.metallicRoughnessTexture = 0;
                material.metallicRoughnessTransform = quad.transform;
                break;
        }
        scene.materials.push_back(material);
        Mesh mesh = detail::makeQuad(int32_t(i));
        for (Vertex& v : mesh.vertices) v.uv1 = secondUvOf(v.uv);
        scene.meshes.push_back(mesh);
        const glm::mat4 world = glm::translate(glm::mat4(1.0f), quadCenter(i)) * glm::scale(glm::mat4(1.0f), glm::vec3(kHalfSize));
        scene.instances.push_back(Instance{uint32_t(i), world});
    }
    validateScene(scene);
    return scene;
}

// The radiance the quad shows where its (TEXCOORD_0) uv is `uv`, or nothing where that point
// lies too near a texel edge to say.
std::optional<glm::vec3> expectedRadiance(const Scene& scene, const QuadCase& quad, glm::vec2 uv) {
    const glm::vec2 at = quad.transform.apply(quad.transform.texCoord == 1 ? secondUvOf(uv) : uv);
    if (!clearOfTexelEdges(at)) return std::nullopt;
    switch (quad.probe) {
        case Probe::Emissive: return glm::vec3(texel(scene.textures[0], at));
        case Probe::BaseColorMask: return texel(scene.textures[1], at).a >= 0.5f ? kMaskedEmission : glm::vec3(kAmbient);
        case Probe::Occlusion: return glm::vec3(kAmbient * 1.04f * texel(scene.textures[0], at).r);   // white: diffuse 1 + F0 0.04
        case Probe::Metallic: {
            const float metallic = texel(scene.textures[0], at).b;   // diffuse 1 - m, F0 0.04 + 0.96 m
            return glm::vec3(kAmbient * ((1.0f - metallic) + (0.04f + 0.96f * metallic)));
        }
    }
    return std::nullopt;
}

class TextureTransformTest : public test_support::ConfigTest {};

// Every pixel whose centre lies on a quad (away from its border and from texel edges) is compared
// with the texel the CPU finds through the same UV set and transform. Before Janus read texCoord
// and KHR_texture_transform every quad showed its untransformed TEXCOORD_0 texels.
TEST_P(TextureTransformTest, EachTextureIsSampledAtItsTransformedUvSet) {
    const Scene scene = quadsScene();
    const FrameOutput output = test_support::renderOneFrame(GetParam(), scene, settingsOfSize(kWidth, kHeight));
    const glm::mat4 inverseViewProjection = glm::inverse(makeCameraView(scene.camera, kWidth, kHeight).viewProjection());
    std::vector<uint32_t> checked(kQuadCount, 0), wrong(kQuadCount, 0);
    std::vector<std::string> firstWrong(kQuadCount);
    for (uint32_t y = 0; y < kHeight; ++y)
        for (uint32_t x = 0; x < kWidth; ++x) {
            // The pixel centre's ray, met with the quads' plane z = 0.
            const glm::vec2 ndc = (glm::vec2(x, y) + 0.5f) / glm::vec2(kWidth, kHeight) * 2.0f - 1.0f;
            const glm::vec4 nearPoint = inverseViewProjection * glm::vec4(ndc, 0.0f, 1.0f);
            const glm::vec4 farPoint = inverseViewProjection * glm::vec4(ndc, 0.5f, 1.0f);
            const glm::vec3 a = glm::vec3(nearPoint) / nearPoint.w, b = glm::vec3(farPoint) / farPoint.w;
            const glm::vec3 world = a + (b - a) * (-a.z / (b.z - a.z));
            for (size_t i = 0; i < kQuadCount; ++i) {
                const glm::vec2 local = (glm::vec2(world) - glm::vec2(quadCenter(i))) / kHalfSize;   // makeQuad's -1..1
                if (std::abs(local.x) > 0.95f || std::abs(local.y) > 0.95f) continue;
                const glm::vec2 uv((local.x + 1.0f) * 0.5f, (1.0f - local.y) * 0.5f);   // makeQuad's corners
                const std::optional<glm::vec3> expected = expectedRadiance(scene, kQuads[i], uv);
                if (!expected) continue;
                ++checked[i];
                const size_t at = (size_t(y) * kWidth + x) * 4;
                const glm::vec3 actual(output.hdr.pixels[at], output.hdr.pixels[at + 1], output.hdr.pixels[at + 2]);
                // The HDR target is RGBA16F: texel / 255 is stored with up to 2^-11 relative error.
                if (glm::any(glm::greaterThan(glm::abs(actual - *expected), glm::vec3(2e-3f)))) {
                    if (wrong[i]++ == 0)
                        firstWrong[i] = fmt::format("pixel ({}, {}) uv ({}, {}): ({}, {}, {}), expected ({}, {}, {})", x, y, uv.x, uv.y,
                                                    actual.r, actual.g, actual.b, expected->r, expected->g, expected->b);
                }
            }
        }
    for (size_t i = 0; i < kQuadCount; ++i) {
        EXPECT_GT(checked[i], 400u) << kQuads[i].name << ": too few pixels checked";
        EXPECT_EQ(wrong[i], 0u) << GetParam().name() << " " << kQuads[i].name << ": " << wrong[i] << " of " << checked[i]
                                << " pixels wrong, first " << firstWrong[i];
    }
    if (testing::Test::HasFailure())
        writePNG(test_support::outputDir() / fmt::format("texture-transform-quads-{}.png", GetParam().name()), output.display);
}

// --- the Khronos TextureTransformTest model ----------------------------------------------------

constexpr uint32_t kModelSize = 256;

// Seen head-on, every quad in view: offsets on the top row (y = 0.55), rotation, scale and all
// three on the bottom row (y = -0.55), each quad 1 x 1.
Scene textureTransformModel() {
    Scene scene = loadScene(fs::path(JANUS_SHARED_SCENES_DIR) / "khronos/TextureTransformTest/glTF/TextureTransformTest.gltf");
    scene.camera.position = {0.0f, 0.0f, 3.55f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    scene.camera.up = {0.0f, 1.0f, 0.0f};
    scene.camera.fovYRadians = glm::radians(50.0f);
    scene.camera.nearPlane = 0.1f;
    scene.camera.farPlane = 20.0f;
    return scene;
}

const Instance& instanceOf(const Scene& scene, const std::string& node) {
    for (const Instance& instance : scene.instances)
        if (instance.nodeName == node) return instance;
    throw std::runtime_error("TextureTransformTest has no node '" + node + "'");
}

glm::vec2 screenOf(const Scene& scene, glm::vec3 world) {
    const glm::vec4 clip = makeCameraView(scene.camera, kModelSize, kModelSize).viewProjection() * glm::vec4(world, 1.0f);
    return (glm::vec2(clip) / clip.w * 0.5f + 0.5f) * float(kModelSize);
}

glm::u8vec4 pixelAt(const ImageRGBA8& image, uint32_t x, uint32_t y) {
    const size_t at = (size_t(y) * image.width + x) * 4;
    return {image.pixels[at], image.pixels[at + 1], image.pixels[at + 2], image.pixels[at + 3]};
}

// The colour names of UV.png's quadrants (and what is not one): a channel counts when it is over
// half the brightest; white check marks and grey borders have all three, the arrow none bright.
enum class Hue { Yellow, Green, Blue, Cyan, Other };
Hue hueOf(glm::u8vec4 p) {
    const int top = std::max({int(p.r), int(p.g), int(p.b)});
    if (top < 40) return Hue::Other;
    const bool r = p.r * 2 > top, g = p.g * 2 > top, b = p.b * 2 > top;
    if (r && g && !b) return Hue::Yellow;
    if (!r && g && !b) return Hue::Green;
    if (!r && !g && b) return Hue::Blue;
    if (!r && g && b) return Hue::Cyan;
    return Hue::Other;
}

// Pixels of the arrow (black in Arrow.png, dark however lit) in the square ring around a marker
// node: inside `outer` times the marker's half size, outside 1.2 times it (the marker itself,
// drawn 0.01 in front of the arrow quad, hides what it covers).
// Only pixels on the arrow's own quad count (the marker's node name up to " - "): a marker at the
// quad's edge also borders the dark background.
uint32_t arrowPixelsAround(const Scene& scene, const ImageRGBA8& image, const std::string& marker, float outer) {
    const Instance& instance = instanceOf(scene, marker);
    const glm::vec3 quadCenter(instanceOf(scene, marker.substr(0, marker.find(" - "))).world[3]);
    const glm::vec2 quadLo = screenOf(scene, quadCenter + glm::vec3(-0.5f, 0.5f, 0.0f)) + 1.0f;
    const glm::vec2 quadHi = screenOf(scene, quadCenter + glm::vec3(0.5f, -0.5f, 0.0f)) - 1.0f;
    const glm::vec3 center(instance.world[3]);
    const float half = 0.5f * glm::length(glm::vec3(instance.world[0]));   // the marker meshes are 1 x 1 quads
    const glm::vec2 c = screenOf(scene, center);
    const float pixelsPerUnit = screenOf(scene, center + glm::vec3(1, 0, 0)).x - c.x;
    const float inner = 1.2f * half * pixelsPerUnit, reach = outer * half * pixelsPerUnit;
    uint32_t count = 0;
    for (uint32_t y = 0; y < kModelSize; ++y)
        for (uint32_t x = 0; x < kModelSize; ++x) {
            const glm::vec2 d = glm::abs(glm::vec2(x, y) + 0.5f - c);
            if (std::max(d.x, d.y) > reach || std::max(d.x, d.y) < inner) continue;
            if (float(x) < std::min(quadLo.x, quadHi.x) || float(x) > std::max(quadLo.x, quadHi.x) ||
                float(y) < std::min(quadLo.y, quadHi.y) || float(y) > std::max(quadLo.y, quadHi.y))
                continue;
            const glm::u8vec4 p = pixelAt(image, x, y);
            if (std::max({p.r, p.g, p.b}) < 60) ++count;
        }
    return count;
}

class KhronosTextureTransformTest : public test_support::ConfigTest {};

// The model says by itself what is right: the offset quads show the green U, blue V and cyan UV
// quadrants of UV.png (yellow: no offset), and each arrow's tip lies under its green "correct"
// marker, not under the yellow "not supported" one (no transform) or the red "error" one (rotation
// the wrong way round).
TEST_P(KhronosTextureTransformTest, ShowsTheModelsCorrectPatches) {
    const Scene scene = textureTransformModel();
    const FrameOutput output = test_support::renderOneFrame(GetParam(), scene, settingsOfSize(kModelSize, kModelSize));
    const ImageRGBA8& image = output.display;
    const std::string label = GetParam().name();

    const std::pair<const char*, Hue> offsets[] = {{"Offset U", Hue::Green}, {"Offset V", Hue::Blue}, {"Offset UV", Hue::Cyan}};
    for (const auto& [node, hue] : offsets) {
        const glm::vec3 center(instanceOf(scene, node).world[3]);
        const glm::vec2 lo = screenOf(scene, center + glm::vec3(-0.4f, 0.4f, 0.0f)), hi = screenOf(scene, center + glm::vec3(0.4f, -0.4f, 0.0f));
        uint32_t counts[5] = {};
        for (uint32_t y = uint32_t(std::min(lo.y, hi.y)); y < uint32_t(std::max(lo.y, hi.y)); ++y)
            for (uint32_t x = uint32_t(lo.x); x < uint32_t(hi.x); ++x) ++counts[size_t(hueOf(pixelAt(image, x, y)))];
        const uint32_t coloured = counts[0] + counts[1] + counts[2] + counts[3];
        EXPECT_GT(counts[size_t(hue)], coloured * 9 / 10) << label << " " << node << ": yellow " << counts[0] << ", green " << counts[1]
                                                          << ", blue " << counts[2] << ", cyan " << counts[3];
        EXPECT_GT(counts[size_t(hue)], 1000u) << label << " " << node;
    }

    // Each "correct" marker has the arrow right up to it; where the tip would be without the
    // transform, or with the rotation reversed, there is no arrow.
    for (const char* correct : {"Rotation - Correct", "Scale - Correct", "All - Correct"})
        EXPECT_GT(arrowPixelsAround(scene, image, correct, 2.5f), 5u) << label << " " << correct;
    for (const char* wrong : {"Rotation - Not Supported", "Rotation - Error", "Scale - Not Supported"})
        EXPECT_EQ(arrowPixelsAround(scene, image, wrong, 2.5f), 0u) << label << " " << wrong;

    if (testing::Test::HasFailure())
        writePNG(test_support::outputDir() / fmt::format("texture-transform-khronos-{}.png", label), image);
}

INSTANTIATE_TEST_SUITE_P(Configs, KhronosTextureTransformTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

INSTANTIATE_TEST_SUITE_P(Configs, TextureTransformTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
