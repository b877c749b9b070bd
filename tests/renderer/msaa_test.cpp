// Multisampled rendering (RenderSettings::msaaSamples; docs/LIGHTING.md, "Anti-aliasing"): the
// main view shades into multisampled targets, "msaa-resolve" averages them before the tonemap;
// cube captures (CubeCaptureDesc::msaaSamples, reflection probes) resolve each face.
// On every configuration: edges get the covered fraction of their samples and everything else
// stays as it was, blended surfaces and tiled culling keep working, the five configurations
// agree, and what cannot be done says so.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/packing.hpp>

#include "janus/renderer/renderer.h"
#include "janus/renderer/scene_view.h"
#include "renderer/renderer_test_support.h"
#include "scene/scene_internal.h"

namespace janus::renderer {
namespace {

using test_support::Config;
using test_support::FrameOutput;

constexpr uint32_t kSize = 64;
constexpr uint32_t kSamples = 4;

// A camera at z = 4 looking at the origin; no light, no ambient: surfaces show their emission.
Scene stage() {
    Scene scene;
    scene.name = "msaa stage";
    scene.camera.position = {0.0f, 0.0f, 4.0f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    scene.camera.fovYRadians = glm::radians(50.0f);
    scene.camera.nearPlane = 0.1f;
    scene.camera.farPlane = 50.0f;
    scene.environment.ambientColor = glm::vec3(0.0f);
    return scene;
}

void addEmissiveQuad(Scene& scene, glm::vec3 emission, float alpha, AlphaMode mode, glm::vec3 center, float turnZ) {
    Material material;
    material.name = fmt::format("emissive {}", scene.materials.size());
    material.baseColorFactor = glm::vec4(0.0f, 0.0f, 0.0f, alpha);
    material.metallicFactor = 0.0f;
    material.roughnessFactor = 1.0f;
    material.emissiveFactor = emission;
    material.alphaMode = mode;
    scene.materials.push_back(material);
    scene.meshes.push_back(detail::makeQuad(int32_t(scene.materials.size() - 1)));
    const glm::mat4 world = glm::translate(glm::mat4(1.0f), center) * glm::rotate(glm::mat4(1.0f), turnZ, glm::vec3(0, 0, 1)) *
                            glm::scale(glm::mat4(1.0f), glm::vec3(0.8f, 0.8f, 1.0f));
    scene.instances.push_back(Instance{uint32_t(scene.meshes.size() - 1), world});
}

RenderSettings settings(uint32_t samples) {
    RenderSettings s;
    s.width = s.height = kSize;
    s.msaaSamples = samples;
    return s;
}

// The six faces (+X .. -Z, rows top down) of a capture at `position` into a new RGBA16F cube.
std::vector<glm::vec4> captureFaces(rhi::IDevice& device, Renderer& renderer, uint32_t samples, uint32_t size, glm::vec3 position,
                                    FrameReport& report) {
    const rhi::TextureHandle cube = device.createTexture(rhi::TextureDesc{}
                                                             .setDimension(rhi::TextureDimension::TextureCube)
                                                             .setFormat(rhi::Format::RGBA16_FLOAT)
                                                             .setSize(size, size)
                                                             .setUsage(rhi::TextureUsage::RenderTarget | rhi::TextureUsage::Sampled)
                                                             .setDebugName(fmt::format("cube {} samples", samples)));
    CubeCaptureDesc desc;
    desc.position = position;
    desc.target = cube;
    desc.msaaSamples = samples;
    report = renderer.renderCubeCapture(desc);
    std::vector<glm::vec4> texels;
    for (uint32_t face = 0; face < 6; ++face) {
        const std::vector<std::byte> bytes = device.readTexture(cube, {0, face});
        EXPECT_EQ(bytes.size(), size_t(size) * size * 8);
        for (size_t texel = 0; texel + 8 <= bytes.size(); texel += 8) {
            uint64_t halves;
            std::memcpy(&halves, bytes.data() + texel, 8);
            texels.push_back(glm::unpackHalf4x16(halves));
        }
    }
    return texels;
}

class MsaaTest : public testing::TestWithParam<Config> {
protected:
    const Config& config() const { return GetParam(); }
};

// A red quad turned 20 degrees: with 4 samples each pixel's red is the covered quarter of its
// samples times the emission (exact in fp16), flat areas are exactly what one sample gives, the
// edges have values between, and the covered area is the one-sample image's within 3 %.
TEST_P(MsaaTest, EdgesGetTheirCoveredFractionAndFlatAreasStay) {
    Scene scene = stage();
    addEmissiveQuad(scene, {1.0f, 0.0f, 0.0f}, 1.0f, AlphaMode::Opaque, {0.0f, 0.0f, 0.0f}, glm::radians(20.0f));
    const FrameOutput one = test_support::renderOneFrame(config(), scene, settings(1));
    const FrameOutput four = test_support::renderOneFrame(config(), scene, settings(kSamples));
    ASSERT_EQ(four.hdr.pixels.size(), one.hdr.pixels.size());
    EXPECT_TRUE(test_support::hasPassStartingWith(four.report, "msaa-resolve")) << test_support::passNames(four.report);
    EXPECT_FALSE(test_support::hasPassStartingWith(one.report, "msaa-resolve")) << test_support::passNames(one.report);
    EXPECT_EQ(four.report.msaaSamples, kSamples);
    EXPECT_EQ(one.report.msaaSamples, 1u);
    EXPECT_EQ(four.report.toJson().at("msaaSamples"), kSamples);

    auto red = [](const ImageRGBAF& image, uint32_t x, uint32_t y) { return image.pixels[(size_t(y) * image.width + x) * 4]; };
    size_t partial = 0, flat = 0;
    double areaOne = 0.0, areaFour = 0.0;
    for (uint32_t y = 0; y < kSize; ++y)
        for (uint32_t x = 0; x < kSize; ++x) {
            const float r4 = red(four.hdr, x, y), r1 = red(one.hdr, x, y);
            areaOne += r1;
            areaFour += r4;
            const float steps = r4 * kSamples;
            EXPECT_EQ(steps, std::round(steps)) << "pixel (" << x << ", " << y << ") holds " << r4 << ", no multiple of 1/4";
            // A pixel whose 3x3 neighbourhood is one colour in the one-sample image lies away from
            // the quad's edges: all its samples see what its centre sees.
            bool uniform = true;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = std::clamp(int(x) + dx, 0, int(kSize) - 1), ny = std::clamp(int(y) + dy, 0, int(kSize) - 1);
                    uniform = uniform && red(one.hdr, uint32_t(nx), uint32_t(ny)) == r1;
                }
            if (uniform) {
                EXPECT_EQ(r4, r1) << "flat pixel (" << x << ", " << y << ")";
                ++flat;
            }
            if (r4 > 0.0f && r4 < 1.0f) ++partial;
        }
    EXPECT_GT(flat, size_t(kSize) * kSize / 2);
    EXPECT_GE(partial, 60u) << "too few partly covered edge pixels: the edges were not multisampled";
    EXPECT_NEAR(areaFour, areaOne, 0.03 * areaOne);
    test_support::expectFiniteHdr(four.hdr, config().name());
}

// A half-transparent blue quad over the red one: the transparent pass draws into the samples
// too, so where both cover a pixel wholly it is half blue over red, exactly, and the blended
// quad's own edges are averaged like the opaque one's.
TEST_P(MsaaTest, BlendedSurfacesAreDrawnIntoTheSamples) {
    Scene scene = stage();
    addEmissiveQuad(scene, {1.0f, 0.0f, 0.0f}, 1.0f, AlphaMode::Opaque, {0.0f, 0.0f, 0.0f}, 0.0f);
    addEmissiveQuad(scene, {0.0f, 0.0f, 1.0f}, 0.5f, AlphaMode::Blend, {0.3f, 0.2f, 0.5f}, glm::radians(30.0f));
    const FrameOutput four = test_support::renderOneFrame(config(), scene, settings(kSamples));
    EXPECT_TRUE(test_support::hasPassStartingWith(four.report, "transparent")) << test_support::passNames(four.report);
    const SceneView view = makeCameraView(scene.camera, kSize, kSize);
    const glm::vec4 clip = view.viewProjection() * glm::vec4(0.3f, 0.2f, 0.5f, 1.0f);
    const glm::uvec2 p = glm::uvec2(glm::floor((glm::vec2(clip) / clip.w * 0.5f + 0.5f) * float(kSize)));
    const size_t i = (size_t(p.y) * kSize + p.x) * 4;
    // Premultiplied blue (0.5 x emission, alpha 0.5) over red: 0.5 red + 0.5 blue.
    EXPECT_NEAR(four.hdr.pixels[i + 0], 0.5f, 1e-3f);
    EXPECT_NEAR(four.hdr.pixels[i + 2], 0.5f, 1e-3f);
    size_t blendedEdges = 0;
    for (size_t k = 0; k < size_t(kSize) * kSize; ++k) {
        const float b = four.hdr.pixels[k * 4 + 2];
        if (b > 0.0f && b < 0.5f) ++blendedEdges;
    }
    EXPECT_GE(blendedEdges, 20u) << "the blended quad's edges are not averaged";
}

// Many lights: Auto culls them in screen tiles without depth bounds (the depth is multisampled),
// and the tiled image is the naive one's: the same lights reach every sample.
TEST_P(MsaaTest, TiledCullingWithoutDepthBoundsMatchesTheNaiveImage) {
    const Scene scene = manyLightsScene(ManyLightsOptions{.lightCount = 48});
    RenderSettings tiled = settings(kSamples);
    RenderSettings naive = settings(kSamples);
    naive.lighting.culling = LightCulling::Naive;
    const FrameOutput a = test_support::renderOneFrame(config(), scene, tiled);
    const FrameOutput b = test_support::renderOneFrame(config(), scene, naive);
    ASSERT_TRUE(a.report.lightCulling.has_value());
    EXPECT_EQ(a.report.lightCulling->mode, LightCulling::Tiles2D);
    EXPECT_TRUE(test_support::hasPassStartingWith(a.report, "depth-prepass")) << test_support::passNames(a.report);
    test_support::expectSameImage(b, a, config().name() + "-msaa-tiled-vs-naive");
}

// A green quad, and in front of it a red alpha-masked one turned 20 degrees whose alpha (its
// vertex colours) ramps from 0 at its left edge to 1 at its right, cut off at 0.55; a point
// light behind both (it lights neither: they face away) so that tiled culling can run.
Scene cutOutStage() {
    Scene scene = stage();
    addEmissiveQuad(scene, {0.0f, 1.0f, 0.0f}, 1.0f, AlphaMode::Opaque, {0.0f, 0.0f, -0.5f}, 0.0f);
    scene.instances.back().world = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, -0.5f)) * glm::scale(glm::mat4(1.0f), glm::vec3(3.0f));
    addEmissiveQuad(scene, {1.0f, 0.0f, 0.0f}, 1.0f, AlphaMode::Mask, {0.0f, 0.0f, 0.0f}, glm::radians(20.0f));
    scene.materials.back().alphaCutoff = 0.55f;
    for (Vertex& v : scene.meshes.back().vertices) v.color = glm::vec4(1.0f, 1.0f, 1.0f, (v.position.x + 1.0f) * 0.5f);
    Light light;
    light.type = LightType::Point;
    light.position = {0.0f, 0.0f, -3.0f};
    light.intensity = 10.0f;
    scene.lights.push_back(light);
    return scene;
}

// Alpha to coverage (RenderSettings::alphaToCoverage, on by default with samples): the cut-out's
// edge covers samples as a triangle's edge does, so it has partly covered pixels where the
// per-pixel cut-off has none; every sample is red or green (the cut-out is opaque inside: its
// alpha goes through a ramp one pixel wide); away from the edge nothing changes; the covered area
// stays within 3 %; and tiled culling, whose depth prepass leaves masked draws to the forward
// pass, gives the naive image (with them in the prepass, the green behind their uncovered samples
// would be hidden). The report says which it used; with one sample it does nothing.
TEST_P(MsaaTest, AlphaToCoverageSmoothsACutOutsEdge) {
    const Scene scene = cutOutStage();
    RenderSettings coverage = settings(kSamples), cutOff = settings(kSamples), tiled = settings(kSamples);
    coverage.lighting.culling = cutOff.lighting.culling = LightCulling::Naive;
    cutOff.alphaToCoverage = false;
    tiled.lighting.culling = LightCulling::Tiles2D;
    const FrameOutput a = test_support::renderOneFrame(config(), scene, coverage);
    const FrameOutput b = test_support::renderOneFrame(config(), scene, cutOff);
    const FrameOutput t = test_support::renderOneFrame(config(), scene, tiled);
    EXPECT_TRUE(a.report.alphaToCoverage);
    EXPECT_EQ(a.report.toJson().at("alphaToCoverage"), true);
    EXPECT_FALSE(b.report.alphaToCoverage);
    EXPECT_TRUE(test_support::hasPassStartingWith(t.report, "depth-prepass")) << test_support::passNames(t.report);
    test_support::expectSameImage(a, t, config().name() + "-alpha-to-coverage-tiled-vs-naive");

    auto at = [](const ImageRGBAF& image, uint32_t x, uint32_t y, int c) { return image.pixels[(size_t(y) * image.width + x) * 4 + c]; };
    size_t partialCoverage = 0, partialCutOff = 0, flat = 0;
    double areaCoverage = 0.0, areaCutOff = 0.0;
    for (uint32_t y = 0; y < kSize; ++y)
        for (uint32_t x = 0; x < kSize; ++x) {
            const float red = at(a.hdr, x, y, 0), green = at(a.hdr, x, y, 1);
            SCOPED_TRACE(fmt::format("pixel ({}, {}): red {} green {}", x, y, red, green));
            EXPECT_EQ(red * kSamples, std::round(red * kSamples)) << "no multiple of 1/4";
            EXPECT_NEAR(red + green, 1.0f, 1e-3f) << "a sample is neither the cut-out nor the quad behind it";
            areaCoverage += red;
            areaCutOff += at(b.hdr, x, y, 0);
            partialCoverage += red > 0.0f && red < 1.0f;
            const float cut = at(b.hdr, x, y, 0);
            partialCutOff += cut > 0.0f && cut < 1.0f;
            bool uniform = true;
            for (int dy = -2; dy <= 2; ++dy)
                for (int dx = -2; dx <= 2; ++dx) {
                    const int nx = std::clamp(int(x) + dx, 0, int(kSize) - 1), ny = std::clamp(int(y) + dy, 0, int(kSize) - 1);
                    uniform = uniform && at(b.hdr, uint32_t(nx), uint32_t(ny), 0) == cut;
                }
            if (uniform) {
                EXPECT_EQ(red, cut) << "away from every edge";
                ++flat;
            }
        }
    EXPECT_GT(flat, size_t(kSize) * kSize / 2);
    // The cut line crosses about 40 rows; the quad's own (geometric) edges are partly covered in both.
    EXPECT_GE(partialCoverage, partialCutOff + 25) << "the cut-out's edge was not anti-aliased";
    EXPECT_NEAR(areaCoverage, areaCutOff, 0.03 * areaCutOff);
    RenderSettings oneSample = settings(1);
    oneSample.lighting.culling = LightCulling::Naive;
    const FrameOutput c = test_support::renderOneFrame(config(), scene, oneSample);
    EXPECT_FALSE(c.report.alphaToCoverage);
}

// A scene file's quality key "alphaToCoverage" applies where the settings leave it unset.
TEST_P(MsaaTest, TheScenesQualityKeyTurnsAlphaToCoverageOff) {
    Scene scene = cutOutStage();
    scene.quality = nlohmann::json{{"alphaToCoverage", false}};
    EXPECT_FALSE(test_support::renderOneFrame(config(), scene, settings(kSamples)).report.alphaToCoverage);
    RenderSettings given = settings(kSamples);
    given.alphaToCoverage = true;
    EXPECT_TRUE(test_support::renderOneFrame(config(), scene, given).report.alphaToCoverage);
}

// A scene file's quality key "msaa" chooses the count where the settings leave it (0); settings
// that give one win.
TEST_P(MsaaTest, TheScenesQualityKeyChoosesTheCountUnlessTheSettingsDo) {
    Scene scene = stage();
    addEmissiveQuad(scene, {1.0f, 0.0f, 0.0f}, 1.0f, AlphaMode::Opaque, {0.0f, 0.0f, 0.0f}, glm::radians(20.0f));
    scene.quality = nlohmann::json{{"msaa", 4}};
    const FrameOutput fromScene = test_support::renderOneFrame(config(), scene, settings(0));
    EXPECT_EQ(fromScene.report.msaaSamples, kSamples);
    EXPECT_TRUE(test_support::hasPassStartingWith(fromScene.report, "msaa-resolve")) << test_support::passNames(fromScene.report);
    const FrameOutput fromSettings = test_support::renderOneFrame(config(), scene, settings(1));
    EXPECT_EQ(fromSettings.report.msaaSamples, 1u);
    EXPECT_FALSE(test_support::hasPassStartingWith(fromSettings.report, "msaa-resolve")) << test_support::passNames(fromSettings.report);
    scene.quality = nlohmann::json::object();
    EXPECT_EQ(test_support::renderOneFrame(config(), scene, settings(0)).report.msaaSamples, 1u);
}

// What cannot be done is a RendererError naming it.
TEST_P(MsaaTest, ImpossibleRequestsSaySo) {
    const Scene scene = defaultScene();
    rhi::IDevice& device = test_support::deviceFor(config().backend);
    auto message = [&](RenderSettings s, auto&& body) -> std::string {
        s.path = config().path;
        try {
            Renderer renderer(device, scene, s);
            body(renderer);
        } catch (const RendererError& e) {
            return e.what();
        }
        return "(no error)";
    };
    auto nothing = [](Renderer&) {};
    EXPECT_NE(message(settings(3), nothing).find("msaa 3 is not possible"), std::string::npos);
    EXPECT_NE(message(settings(64), nothing).find("msaa 64 is not possible"), std::string::npos);
    RenderSettings depthBounds = settings(kSamples);
    depthBounds.lighting.culling = LightCulling::TilesDepth;
    const Scene lights = manyLightsScene(ManyLightsOptions{.lightCount = 16});
    std::string culling = "(no error)";
    try {
        depthBounds.path = config().path;
        Renderer renderer(device, lights, depthBounds);
    } catch (const RendererError& e) {
        culling = e.what();
    }
    EXPECT_NE(culling.find("tiles-depth"), std::string::npos) << culling;
    EXPECT_NE(message(settings(kSamples), [](Renderer& r) { r.renderFrame(); r.readDepth(); }).find("multisampled"), std::string::npos);
    device.takeDebugMessages();
}

// A cube capture with samples (CubeCaptureDesc::msaaSamples): each face is shaded into the
// multisampled targets and resolved into its face, so the red quad of
// EdgesGetTheirCoveredFractionAndFlatAreasStay, seen by the capture's -Z face, gets partly covered
// pixels at its edges, exact quarters, and everything else (the rest of that face, the five faces
// that see nothing) is what one sample gives. The report says so per view.
TEST_P(MsaaTest, ACubeCaptureResolvesEachFaceOfItsSamples) {
    Scene scene = stage();
    addEmissiveQuad(scene, {1.0f, 0.0f, 0.0f}, 1.0f, AlphaMode::Opaque, {0.0f, 0.0f, -1.5f}, glm::radians(20.0f));
    rhi::IDevice& device = test_support::deviceFor(config().backend);
    device.takeDebugMessages();
    RenderSettings s = settings(1);
    s.path = config().path;
    Renderer renderer(device, scene, s);
    constexpr uint32_t kFace = 48;
    auto capture = [&](uint32_t samples, FrameReport& report) {
        std::vector<float> red;   // faces 0..5, rows top down
        for (const glm::vec4& texel : captureFaces(device, renderer, samples, kFace, glm::vec3(0.0f), report)) red.push_back(texel.r);
        return red;
    };
    // One view name for every count: the features' per-view state follows the view's count.
    FrameReport oneReport, fourReport, againReport;
    const std::vector<float> one = capture(1, oneReport), four = capture(kSamples, fourReport);
    EXPECT_EQ(capture(1, againReport), one) << "a capture with one sample after one with samples differs from the first";
    const std::vector<rhi::DebugMessage> messages = device.takeDebugMessages();
    EXPECT_TRUE(messages.empty()) << test_support::joinMessages(messages);
    ASSERT_EQ(one.size(), four.size());
    ASSERT_EQ(one.size(), size_t(6) * kFace * kFace);

    EXPECT_EQ(fourReport.msaaSamples, kSamples);
    EXPECT_EQ(oneReport.msaaSamples, 1u);
    ASSERT_EQ(fourReport.views.size(), 6u);
    for (const ViewReport& view : fourReport.views) EXPECT_EQ(view.sampleCount, kSamples) << view.name;
    EXPECT_EQ(fourReport.toJson().at("views").at(0).at("samples"), kSamples);
    auto resolves = [](const FrameReport& report) {
        return std::count_if(report.passes.begin(), report.passes.end(), [](const PassReport& p) { return p.name == "msaa-resolve"; });
    };
    EXPECT_EQ(resolves(fourReport), 6);
    EXPECT_EQ(resolves(oneReport), 0);

    const size_t faceTexels = size_t(kFace) * kFace;
    size_t partial = 0, flat = 0, lit = 0;
    double areaOne = 0.0, areaFour = 0.0;
    for (uint32_t face = 0; face < 6; ++face)
        for (uint32_t y = 0; y < kFace; ++y)
            for (uint32_t x = 0; x < kFace; ++x) {
                const size_t i = face * faceTexels + size_t(y) * kFace + x;
                SCOPED_TRACE(fmt::format("face {} texel ({}, {})", face, x, y));
                EXPECT_EQ(four[i] * kSamples, std::round(four[i] * kSamples)) << four[i] << " is no multiple of 1/4";
                areaOne += one[i];
                areaFour += four[i];
                lit += one[i] > 0.0f;
                bool uniform = true;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int nx = std::clamp(int(x) + dx, 0, int(kFace) - 1), ny = std::clamp(int(y) + dy, 0, int(kFace) - 1);
                        uniform = uniform && one[face * faceTexels + size_t(ny) * kFace + size_t(nx)] == one[i];
                    }
                if (uniform) {
                    EXPECT_EQ(four[i], one[i]) << "away from every edge";
                    ++flat;
                }
                partial += four[i] > 0.0f && four[i] < 1.0f;
            }
    EXPECT_GT(lit, 100u) << "the capture's -Z face does not see the quad";
    EXPECT_GT(flat, 5 * faceTexels);
    EXPECT_GE(partial, 40u) << "too few partly covered edge texels: the faces were not multisampled";
    EXPECT_NEAR(areaFour, areaOne, 0.03 * areaOne);
}

// A capture's masked cut-out (cutOutStage, seen from z = 2 by the -Z face) gets alpha to coverage
// as the main view's does: more partly covered texels than with the renderer's alphaToCoverage off,
// every sample the cut-out's or the quad's behind it, and the capture's report says it was used.
TEST_P(MsaaTest, ACubeCaptureGivesCutOutsAlphaToCoverage) {
    const Scene scene = cutOutStage();
    rhi::IDevice& device = test_support::deviceFor(config().backend);
    device.takeDebugMessages();
    constexpr uint32_t kFace = 64;
    auto partlyRed = [&](bool alphaToCoverage) {
        RenderSettings s = settings(1);
        s.path = config().path;
        s.alphaToCoverage = alphaToCoverage;
        Renderer renderer(device, scene, s);
        FrameReport report;
        const std::vector<glm::vec4> faces = captureFaces(device, renderer, kSamples, kFace, glm::vec3(0.0f, 0.0f, 2.0f), report);
        EXPECT_EQ(report.alphaToCoverage, alphaToCoverage);
        size_t partial = 0;
        for (size_t i = 5 * size_t(kFace) * kFace; i < faces.size(); ++i) {   // the -Z face
            EXPECT_NEAR(faces[i].r + faces[i].g, 1.0f, 1e-3f) << "texel " << i << ": a sample is neither the cut-out nor the quad behind it";
            partial += faces[i].r > 0.0f && faces[i].r < 1.0f;
        }
        return partial;
    };
    const size_t coverage = partlyRed(true), cutOff = partlyRed(false);
    const std::vector<rhi::DebugMessage> messages = device.takeDebugMessages();
    EXPECT_TRUE(messages.empty()) << test_support::joinMessages(messages);
    // The cut line crosses about 25 rows of the face; the quad's own edges are partly covered in both.
    EXPECT_GE(coverage, cutOff + 15) << "the capture's cut-out edge was not anti-aliased";
}

// A count the device does not allow, or none at all, is a RendererError naming it.
TEST_P(MsaaTest, ACubeCaptureRefusesSampleCountsTheDeviceLacks) {
    rhi::IDevice& device = test_support::deviceFor(config().backend);
    RenderSettings s = settings(1);
    s.path = config().path;
    Renderer renderer(device, stage(), s);
    CubeCaptureDesc desc;
    desc.target = device.createTexture(rhi::TextureDesc{}
                                           .setDimension(rhi::TextureDimension::TextureCube)
                                           .setFormat(rhi::Format::RGBA16_FLOAT)
                                           .setSize(16, 16)
                                           .setUsage(rhi::TextureUsage::RenderTarget | rhi::TextureUsage::Sampled)
                                           .setDebugName("refused capture"));
    auto message = [&](uint32_t samples) -> std::string {
        desc.msaaSamples = samples;
        try {
            renderer.renderCubeCapture(desc);
        } catch (const RendererError& e) {
            return e.what();
        }
        return "(no error)";
    };
    EXPECT_NE(message(3).find("msaa 3 must be 1 (off), 2, 4, 8 or 16"), std::string::npos) << message(3);
    EXPECT_NE(message(0).find("msaa 0 must be"), std::string::npos) << message(0);
    const uint32_t allowed = device.formatCapabilities(rhi::Format::RGBA16_FLOAT).sampleCounts &
                             device.formatCapabilities(rhi::Format::D32_FLOAT).sampleCounts;
    for (uint32_t samples : {2u, 8u, 16u}) {
        if (allowed & samples) continue;
        const std::string text = message(samples);
        EXPECT_NE(text.find(fmt::format("cube capture into 'refused capture': msaa {} is not possible on this {} device", samples,
                                        rhi::toString(config().backend))),
                  std::string::npos)
            << text;
    }
    device.takeDebugMessages();
}

INSTANTIATE_TEST_SUITE_P(Configs, MsaaTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

// The default scene with 4 samples on the five configurations, held to the suite's parity rule
// against vulkan/compute.
class MsaaParity : public testing::TestWithParam<Config> {
protected:
    // `scene` at 128x128 with 4 samples here and on vulkan/compute, held to the parity rule.
    FrameOutput expectParity(const Scene& scene, const std::string& name) {
        RenderSettings s = settings(kSamples);
        s.width = s.height = 128;
        const FrameOutput reference = test_support::renderOneFrame(test_support::allConfigs().front(), scene, s);
        FrameOutput result = test_support::renderOneFrame(GetParam(), scene, s);
        test_support::expectMatchesVulkanCompute(reference.display, result.display, name, GetParam());
        return result;
    }
};

TEST_P(MsaaParity, MatchesVulkanCompute) { expectParity(defaultScene(), "msaa-default"); }

// The alpha-masked cut-out of AlphaToCoverageSmoothsACutOutsEdge, with alpha to coverage, under
// the same rule: which samples an alpha covers is each driver's, but one driver is one pattern.
TEST_P(MsaaParity, CutOutWithAlphaToCoverageMatchesVulkanCompute) {
    EXPECT_TRUE(expectParity(cutOutStage(), "msaa-cut-out").report.alphaToCoverage);
}

INSTANTIATE_TEST_SUITE_P(Configs, MsaaParity, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
