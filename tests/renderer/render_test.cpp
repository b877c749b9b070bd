// GPU tests of the Renderer: the same scene in all five configurations (backend x feature path)
// with validation on, compared pixel by pixel against vulkan/compute.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "janus/renderer/image.h"
#include "janus/renderer/renderer.h"
#include "janus/renderer/scene.h"
#include "janus/rhi/rhi.h"
#include "renderer/renderer_test_support.h"

namespace janus::renderer {
namespace {

namespace fs = std::filesystem;

using test_support::Config;
using test_support::deviceFor;
using test_support::joinMessages;
using test_support::kSize;

// vulkan/compute first: the reference the other configurations are compared with.
const std::vector<Config>& kConfigs = test_support::allConfigs();

struct Render {
    FrameReport report;
    ImageRGBA8 display;
    ImageRGBAF hdr;
};

Render render(const Config& config, const Scene& scene) {
    rhi::IDevice& device = deviceFor(config.backend);
    device.takeDebugMessages();
    Render result;
    {
        Renderer renderer(device, scene, RenderSettings{kSize, kSize, config.path});
        result.report = renderer.renderFrame();
        result.display = renderer.readDisplayImage();
        result.hdr = renderer.readHdrImage();
    }
    const std::vector<rhi::DebugMessage> messages = device.takeDebugMessages();
    EXPECT_TRUE(messages.empty()) << config.name() << " produced validation / debug messages:" << joinMessages(messages);
    return result;
}

struct SceneCase {
    const char* name;
    Scene (*make)();
};

Scene sharedScene(const char* relative) { return loadScene(fs::path(JANUS_SHARED_SCENES_DIR) / relative); }

const SceneCase kScenes[] = {
    {"default", [] { return defaultScene(); }},
    {"MetalRoughSpheres", [] { return sharedScene("MetalRoughSpheresNoTextures/glTF/MetalRoughSpheresNoTextures.gltf"); }},
    {"BoxTextured", [] { return sharedScene("BoxTextured/glTF/BoxTextured.gltf"); }},
    // Normal, occlusion, emissive and metallic-roughness textures, tangents, a rotated root node.
    {"DamagedHelmet", [] { return sharedScene("DamagedHelmet/glTF/DamagedHelmet.gltf"); }},
    // KHR_texture_transform (offset, rotation, scale on clamped, unmipped textures) and a second UV
    // set (the emissive texture reads TEXCOORD_1).
    {"TextureTransformTest", [] { return sharedScene("khronos/TextureTransformTest/glTF/TextureTransformTest.gltf"); }},
    {"MultiUVTest", [] { return sharedScene("khronos/MultiUVTest/glTF/MultiUVTest.gltf"); }},
    // A scene file: its camera, a point light, emissive lamp, textured walls.
    {"CornellSceneFile", [] { return loadScene(fs::path(__FILE__).parent_path() / "data" / "cornell.json"); }},
    // Image-based lighting from the shared sky: metals reflect it, the background shows it.
    {"DamagedHelmetUnderSky",
     [] {
         Scene scene = sharedScene("DamagedHelmet/glTF/DamagedHelmet.gltf");
         scene.environment.map = fs::path(JANUS_SHARED_SCENES_DIR) / "env" / "chinese_garden_1k.hdr";
         return scene;
     }},
    // alphaMode BLEND: the front row of spheres as tinted glass (the glossiest one double-sided),
    // composited back to front over the room by the transparent pass.
    {"TransparentRoom",
     [] {
         Scene scene = defaultScene();
         for (Material& material : scene.materials)
             if (material.name.starts_with("plastic ")) {
                 material.alphaMode = AlphaMode::Blend;
                 material.baseColorFactor.a = 0.4f;
                 material.doubleSided = material.name == "plastic 0";
             }
         return scene;
     }},
    // A double-sided glass pane in front of the helmet and the sky: blended over both.
    {"GlassPaneUnderSky",
     [] {
         Scene scene = sharedScene("DamagedHelmet/glTF/DamagedHelmet.gltf");
         scene.environment.map = fs::path(JANUS_SHARED_SCENES_DIR) / "env" / "chinese_garden_1k.hdr";
         Material glass;
         glass.name = "glass";
         glass.baseColorFactor = {0.5f, 0.8f, 0.6f, 0.3f};
         glass.metallicFactor = 0.0f;
         glass.roughnessFactor = 0.1f;
         glass.alphaMode = AlphaMode::Blend;
         glass.doubleSided = true;
         scene.materials.push_back(glass);
         Mesh pane;
         const glm::vec4 tangent(0.0f);
         pane.vertices = {Vertex{{-1, -1, 0}, {0, 0, 1}, {0, 1}, tangent}, Vertex{{1, -1, 0}, {0, 0, 1}, {1, 1}, tangent},
                          Vertex{{1, 1, 0}, {0, 0, 1}, {1, 0}, tangent}, Vertex{{-1, 1, 0}, {0, 0, 1}, {0, 0}, tangent}};
         pane.indices = {0, 1, 2, 0, 2, 3};
         pane.material = int32_t(scene.materials.size() - 1);
         scene.meshes.push_back(pane);
         // Between the camera and the helmet, off to the right, over helmet and sky, turned a little.
         const glm::vec3 toCamera = scene.camera.position - scene.camera.target;
         const float distance = glm::length(toCamera);
         const glm::vec3 right = glm::normalize(glm::cross(-toCamera, scene.camera.up));
         const glm::vec3 centre = scene.camera.target + 0.35f * toCamera + 0.25f * distance * right;
         const glm::mat4 world = glm::inverse(glm::lookAt(centre, centre - toCamera, scene.camera.up)) *
                                 glm::rotate(glm::mat4(1.0f), 0.5f, glm::vec3(0, 1, 0)) * glm::scale(glm::mat4(1.0f), glm::vec3(0.25f * distance));
         scene.instances.push_back(Instance{uint32_t(scene.meshes.size() - 1), world});
         return scene;
     }},
};

size_t blendedInstances(const Scene& scene) {
    return size_t(std::count_if(scene.instances.begin(), scene.instances.end(), [&](const Instance& instance) {
        const int32_t material = scene.meshes[instance.mesh].material;
        return material >= 0 && scene.materials[size_t(material)].alphaMode == AlphaMode::Blend;
    }));
}

// The reference (vulkan/compute) render of each scene, made once per process.
const Render& reference(const SceneCase& sceneCase) {
    static std::map<std::string, Render> cache;
    auto it = cache.find(sceneCase.name);
    if (it == cache.end()) it = cache.emplace(sceneCase.name, render(kConfigs[0], sceneCase.make())).first;
    return it->second;
}

// Failing comparisons leave the images and a heat map here for a look.
fs::path outputDir() {
    const fs::path dir = fs::temp_directory_path() / "janus-renderer-tests";
    fs::create_directories(dir);
    return dir;
}

double averageChannel(const ImageRGBA8& image, uint32_t x0, uint32_t x1, uint32_t channel) {
    double sum = 0;
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = x0; x < x1; ++x) sum += image.pixels[(size_t(y) * image.width + x) * 4 + channel];
    return sum / (double(x1 - x0) * image.height);
}

void PrintTo(const SceneCase& sceneCase, std::ostream* os) { *os << sceneCase.name; }

using RenderParam = std::tuple<SceneCase, Config>;

class RenderTest : public testing::TestWithParam<RenderParam> {
protected:
    const SceneCase& sceneCase() const { return std::get<0>(GetParam()); }
    const Config& config() const { return std::get<1>(GetParam()); }
};

TEST_P(RenderTest, MatchesVulkanComputeAndReportsItsPasses) {
    const Scene scene = sceneCase().make();
    const Render& ref = reference(sceneCase());
    const Render result = render(config(), scene);

    // Pixel parity (test_support::expectMatchesVulkanCompute says why it allows what it allows).
    test_support::expectMatchesVulkanCompute(ref.display, result.display, sceneCase().name, config());

    // Frame report: exactly the passes this scene needs, in order, with their work counts.
    const FrameReport& report = result.report;
    EXPECT_EQ(report.backend, rhi::toString(config().backend));
    EXPECT_EQ(report.path, toString(config().path));
    EXPECT_EQ(report.width, kSize);
    EXPECT_EQ(report.height, kSize);
    // A directional light that lights something brings its shadow map first; these scenes have
    // at most a handful of point/spot lights, so Auto loops them directly (no prepass, no culling).
    const bool shadows = std::any_of(scene.lights.begin(), scene.lights.end(), [](const Light& light) {
        return light.type == LightType::Directional && light.intensity * std::max({light.color.r, light.color.g, light.color.b}) > 0.0f;
    });
    const bool compute = config().path == FeaturePath::Compute;
    const std::string path = compute ? "-compute" : "-fallback";
    const bool sky = !scene.environment.map.empty();
    // BLEND materials add the transparent pass after the sky, and leave the shadow map and forward.
    const size_t blended = blendedInstances(scene);
    std::vector<std::string> expected;
    if (sky) expected = {"equirect-to-cube" + path, "ggx-prefilter" + path, "sh-irradiance" + path, "background-cube" + path};   // once, at start-up
    // An irradiance volume (the cornell box's "IrradianceVolume" marker) is baked at start-up and
    // relit in the first frame before the probes capture: its shadow map, then per bounce the
    // bricks' radiance and the probes' SH (docs/GI.md).
    bool mapDrawn = false;   // a static scene draws its shadow map once
    if (scene.irradianceVolume) {
        expected.push_back("gi-bake");
        if (shadows) expected.push_back("shadow-map"), mapDrawn = true;
        for (uint32_t bounce = 0; bounce < scene.irradianceVolume->bounces; ++bounce) {
            expected.push_back("gi-brick-radiance" + path);
            expected.push_back("gi-probe-sh" + path);
        }
    }
    // Reflection probes (a "ReflectionCubemap" marker places one in the cornell box) update in
    // the first frame, before it: six faces with the reduced pass set, the prefilter, the copy.
    for (const ReflectionProbe& probe : scene.reflectionProbes) {
        ASSERT_EQ(probe.timeSlicing, ProbeTimeSlicing::None);
        // The map is drawn once, by the first graph of the frame that reads it: the relight's
        // with an irradiance volume, else a capture's that wants shadows, else the frame's.
        if (shadows && probe.shadows && !mapDrawn) expected.push_back("shadow-map"), mapDrawn = true;
        for (int face = 0; face < 6; ++face) {
            expected.push_back("forward");
            if (sky) expected.push_back("sky");
            if (blended > 0) expected.push_back("transparent");
        }
        expected.push_back("probe-prefilter" + path);
        expected.push_back("probe-show");
    }
    if (shadows && !mapDrawn) expected.push_back("shadow-map");
    expected.push_back("forward");
    if (sky) expected.push_back("sky");
    if (blended > 0) expected.push_back("transparent");
    expected.push_back("tonemap" + path);
    std::vector<std::string> names;
    for (const PassReport& pass : report.passes) names.push_back(pass.name);
    ASSERT_EQ(names, expected) << report.toJson().dump();
    auto pass = [&](const std::string& name) -> const PassReport& {
        return *std::find_if(report.passes.begin(), report.passes.end(), [&](const PassReport& p) { return p.name == name; });
    };
    if (shadows) {
        EXPECT_EQ(pass("shadow-map").draws, scene.instances.size() - blended);
    }
    if (scene.irradianceVolume) {
        // One dispatch each | one draw for the bricks, one per layer of probes and group of three
        // coefficients (Y x 3, three volume slices each) for the SH.
        EXPECT_EQ(pass("gi-brick-radiance" + path).dispatches, compute ? 1u : 0u);
        EXPECT_EQ(pass("gi-brick-radiance" + path).draws, compute ? 0u : 1u);
        EXPECT_EQ(pass("gi-probe-sh" + path).dispatches, compute ? 1u : 0u);
        EXPECT_EQ(pass("gi-probe-sh" + path).draws, compute ? 0u : scene.irradianceVolume->probeCounts.y * 3);
    }
    EXPECT_EQ(pass("forward").draws, scene.instances.size() - blended);
    if (blended > 0) {
        EXPECT_GE(pass("transparent").draws, blended);   // double-sided ones draw twice
    }
    ASSERT_EQ(report.probeUpdates.size(), scene.reflectionProbes.size());
    for (const ProbeUpdateReport& update : report.probeUpdates) {
        // 6 prefiltered mips: one dispatch each | one draw per face and mip (36), then 7 x 6 copies.
        EXPECT_TRUE(update.shown) << update.probe;
        EXPECT_EQ(update.prefilterDispatches, compute ? 6u : 0u) << update.probe;
        EXPECT_EQ(update.prefilterDraws, compute ? 0u : 36u) << update.probe;
        EXPECT_EQ(update.copies, 42u) << update.probe;
    }
    EXPECT_EQ(pass("forward").dispatches, 0u);
    EXPECT_EQ(pass("tonemap" + path).dispatches, compute ? 1u : 0u);
    EXPECT_EQ(pass("tonemap" + path).draws, compute ? 0u : 1u);
    if (sky) {
        // One dispatch per prefiltered mip (8 mips of a 128^2 cube) | one draw per face and mip, plus
        // the bright-texel split (docs/IBL.md): its split and its list, 1 + 1 dispatches | 6 + 1 draws.
        EXPECT_EQ(pass("ggx-prefilter" + path).dispatches, compute ? 9u : 0u);
        EXPECT_EQ(pass("ggx-prefilter" + path).draws, compute ? 0u : 49u);
        EXPECT_EQ(pass("sky").draws, 1u);
    }
    const bool timers = deviceFor(config().backend).capabilities().timestampQueries;
    for (const PassReport& pass : report.passes) {
        EXPECT_EQ(pass.gpuMs.has_value(), timers) << pass.name;
        if (pass.gpuMs) {
            EXPECT_GE(*pass.gpuMs, 0.0) << pass.name;
        }
        EXPECT_GE(pass.cpuMs, 0.0) << pass.name;
    }
}

TEST_P(RenderTest, ImageIsNotBlankAndHdrIsFinite) {
    const Render result = render(config(), sceneCase().make());
    uint32_t distinct = 0;
    std::map<uint32_t, bool> seen;
    for (size_t i = 0; i < result.display.pixels.size(); i += 4) {
        const uint32_t rgb = uint32_t(result.display.pixels[i]) << 16 | uint32_t(result.display.pixels[i + 1]) << 8 | result.display.pixels[i + 2];
        if (!seen[rgb]) {
            seen[rgb] = true;
            ++distinct;
        }
        EXPECT_EQ(result.display.pixels[i + 3], 255u);
    }
    EXPECT_GT(distinct, 50u) << "a lit scene has many shades";
    for (float v : result.hdr.pixels) {
        ASSERT_TRUE(std::isfinite(v));
        ASSERT_GE(v, 0.0f);
    }
}

INSTANTIATE_TEST_SUITE_P(Configs, RenderTest, testing::Combine(testing::ValuesIn(kScenes), testing::ValuesIn(kConfigs)),
                         [](const testing::TestParamInfo<RenderParam>& info) {
                             return fmt::format("{}_{}", std::get<0>(info.param).name, std::get<1>(info.param).name());
                         });

TEST(RenderDefaultScene, RedWallLeftGreenWallRightFloorBelowCeiling) {
    const Render result = render(kConfigs[0], defaultScene());
    const ImageRGBA8& image = result.display;
    writePNG(outputDir() / "default-vulkan_compute.png", image);   // for a human look
    // The outer quarters also show white floor and back wall, so compare how much red exceeds
    // green (and the reverse) rather than absolute levels.
    const uint32_t quarter = image.width / 4;
    const double leftRedness = averageChannel(image, 0, quarter, 0) - averageChannel(image, 0, quarter, 1);
    const double rightRedness = averageChannel(image, image.width - quarter, image.width, 0) -
                                averageChannel(image, image.width - quarter, image.width, 1);
    EXPECT_GT(leftRedness, 20.0) << "left quarter should be dominated by the red wall";
    EXPECT_LT(rightRedness, -20.0) << "right quarter should be dominated by the green wall";
    // The key light comes from above: the floor (bottom rows) is lit, the ceiling (top) is not.
    auto rowsAverage = [&](uint32_t y0, uint32_t y1) {
        double sum = 0;
        for (uint32_t y = y0; y < y1; ++y)
            for (uint32_t x = quarter; x < image.width - quarter; ++x)
                for (uint32_t c = 0; c < 3; ++c) sum += image.pixels[(size_t(y) * image.width + x) * 4 + c];
        return sum / (double(y1 - y0) * (image.width - 2 * quarter) * 3);
    };
    const uint32_t eighth = image.height / 8;
    EXPECT_GT(rowsAverage(image.height - eighth, image.height), rowsAverage(0, eighth / 2) + 40.0)
        << "the lit floor must be at the bottom of the image (row 0 is the top)";
}

TEST(RenderDefaultScene, RenderingTwiceGivesTheSameImage) {
    rhi::IDevice& device = deviceFor(rhi::Backend::Vulkan);
    Renderer renderer(device, defaultScene(), RenderSettings{kSize, kSize, FeaturePath::Compute});
    renderer.renderFrame();
    const ImageRGBA8 first = renderer.readDisplayImage();
    renderer.renderFrame();
    EXPECT_EQ(compareImages(first, renderer.readDisplayImage()).maxChannelDifference, 0u);
}

TEST(RenderEmptyScene, ShowsTheUniformBackgroundOnEveryConfiguration) {
    Scene scene;   // no meshes: the frame is the environment's radiance only
    scene.environment.ambientColor = glm::vec3(0.25f, 0.125f, 0.0625f);   // exact in half precision
    for (const Config& config : kConfigs) {
        const Render result = render(config, scene);
        EXPECT_EQ(result.report.passes.at(0).draws, 0u) << config.name();
        const uint8_t* first = result.display.pixels.data();
        EXPECT_GT(first[0], first[1]) << config.name();
        EXPECT_GT(first[1], first[2]) << config.name();
        for (size_t i = 0; i < result.display.pixels.size(); i += 4)
            ASSERT_TRUE(std::equal(first, first + 4, result.display.pixels.data() + i)) << config.name() << " pixel " << i / 4;
        EXPECT_EQ(result.hdr.pixels[0], 0.25f) << config.name();
        EXPECT_EQ(result.hdr.pixels[2], 0.0625f) << config.name();
    }
}

// One quad at the origin facing +Z, seen from -Z (its back) or +Z (its front).
Scene quadScene(bool doubleSided, float cameraZ) {
    Scene scene;
    Mesh quad;
    for (glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)})
        quad.vertices.push_back(Vertex{glm::vec3(c, 0.0f), glm::vec3(0, 0, 1), glm::vec2(0), glm::vec4(0)});
    quad.indices = {0, 1, 2, 0, 2, 3};   // counter-clockwise seen from +Z, as glTF front faces are
    quad.material = 0;
    Material material;
    material.metallicFactor = 0.0f;
    material.doubleSided = doubleSided;
    scene.materials.push_back(material);
    scene.meshes.push_back(quad);
    scene.instances.push_back(Instance{0, glm::mat4(1.0f)});
    Light light;
    light.direction = glm::vec3(0, 0, cameraZ > 0 ? -1 : 1);   // shine onto the side the camera sees
    scene.lights.push_back(light);
    scene.environment.ambientColor = glm::vec3(0.0f);
    scene.camera.position = glm::vec3(0, 0, cameraZ);
    return scene;
}

TEST(RenderCulling, FrontFacesAreCounterClockwiseAndDoubleSidedMaterialsShowTheirBack) {
    constexpr size_t centre = (size_t(kSize / 2) * kSize + kSize / 2) * 4;
    for (const Config& config : kConfigs) {
        const Render front = render(config, quadScene(false, 3.0f));
        const Render back = render(config, quadScene(false, -3.0f));
        const Render backDoubleSided = render(config, quadScene(true, -3.0f));
        EXPECT_GT(front.display.pixels[centre], 100) << config.name() << ": the lit front face must be drawn";
        EXPECT_EQ(back.display.pixels[centre], 0) << config.name() << ": a single-sided back face must be culled";
        // Double-sided: the back is drawn and lit through its flipped normal, like the front.
        EXPECT_EQ(backDoubleSided.display.pixels[centre], front.display.pixels[centre]) << config.name();
    }
}

TEST(RenderMaterials, AlphaMaskDiscardsBelowTheCutoff) {
    constexpr size_t centre = (size_t(kSize / 2) * kSize + kSize / 2) * 4;
    for (float alpha : {0.3f, 0.7f}) {
        Scene scene = quadScene(false, 3.0f);
        scene.materials[0].alphaMode = AlphaMode::Mask;
        scene.materials[0].alphaCutoff = 0.5f;
        scene.materials[0].baseColorFactor.a = alpha;
        for (const Config& config : kConfigs) {
            const Render result = render(config, scene);
            if (alpha < 0.5f)
                EXPECT_EQ(result.display.pixels[centre], 0) << config.name() << ": alpha " << alpha << " must be cut out";
            else
                EXPECT_GT(result.display.pixels[centre], 100) << config.name() << ": alpha " << alpha << " must be drawn";
        }
    }
}

TEST(RenderLights, SpotLightLightsItsConeOnly) {
    Scene scene = quadScene(false, 3.0f);
    Light spot;
    spot.type = LightType::Spot;
    spot.position = glm::vec3(0, 0, 2);
    spot.direction = glm::vec3(0, 0, -1);
    spot.intensity = 8.0f;
    spot.innerConeAngle = glm::radians(5.0f);
    spot.outerConeAngle = glm::radians(10.0f);   // lit radius on the quad: 2 * tan(10 deg) = 0.35
    scene.lights = {spot};
    const Render result = render(kConfigs[0], scene);
    auto red = [&](uint32_t x, uint32_t y) { return result.display.pixels[(size_t(y) * kSize + x) * 4]; };
    EXPECT_GT(red(kSize / 2, kSize / 2), 100) << "the cone's centre is lit";
    // 0.8 units off-centre (about 37 pixels at this camera) is outside the cone: nothing but
    // the (zero) ambient reaches it.
    EXPECT_EQ(red(kSize / 2 + 37, kSize / 2), 0);
    EXPECT_EQ(red(kSize / 2, kSize / 2 - 37), 0);
}

TEST(RendererErrors, ComputePathOnGlesNamesTheCapability) {
    rhi::IDevice& device = deviceFor(rhi::Backend::GLES);
    try {
        Renderer renderer(device, defaultScene(), RenderSettings{kSize, kSize, FeaturePath::Compute});
        FAIL() << "the compute path must be refused on gles";
    } catch (const RendererError& e) {
        EXPECT_NE(std::string(e.what()).find("compute"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("fallback"), std::string::npos) << "should say what to use instead: " << e.what();
    }
}

TEST(RendererErrors, AbsurdSizesAreRefused) {
    rhi::IDevice& device = deviceFor(rhi::Backend::Vulkan);
    const uint32_t tooBig = device.capabilities().limits.maxTextureSize2D + 1;
    for (auto [w, h] : {std::pair{0u, 128u}, {128u, 0u}, {tooBig, 16u}, {16u, tooBig}}) {
        try {
            Renderer renderer(device, defaultScene(), RenderSettings{w, h, FeaturePath::Fallback});
            ADD_FAILURE() << w << "x" << h << " was accepted";
        } catch (const RendererError& e) {
            EXPECT_NE(std::string(e.what()).find(fmt::format("{}x{}", w, h)), std::string::npos) << e.what();
        }
    }
    EXPECT_TRUE(device.takeDebugMessages().empty());
}

TEST(RendererErrors, ReadingBeforeTheFirstFrameIsRefused) {
    Renderer renderer(deviceFor(rhi::Backend::Vulkan), defaultScene(), RenderSettings{16, 16, FeaturePath::Fallback});
    EXPECT_THROW(renderer.readDisplayImage(), RendererError);
    EXPECT_THROW(renderer.readHdrImage(), RendererError);
}

TEST(RendererErrors, InvalidSceneIsRefusedBeforeTouchingTheDevice) {
    rhi::IDevice& device = deviceFor(rhi::Backend::Vulkan);
    Scene scene = defaultScene();
    scene.camera.fovYRadians = std::nanf("");
    EXPECT_THROW(Renderer(device, scene, RenderSettings{kSize, kSize, FeaturePath::Fallback}), SceneError);
}

}  // namespace
}  // namespace janus::renderer
