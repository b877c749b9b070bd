// Image-based lighting from a sky (docs/IBL.md), end to end on every configuration: under a sky
// of constant radiance L, a head-on dielectric quad must reflect exactly what the split-sum model
// says (diffuse: albedo * L from the SH; specular: L * (f0 A + B) from the prefiltered cube and
// the DFG table) and the background must show L; the sky's filtering is reported once, in the
// first frame; a scene without a sky keeps its ambient colour.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <filesystem>
#include <tuple>
#include <vector>
#include <fstream>

#include <fmt/format.h>
#include <unistd.h>

#include "ibl/dfg_lut.h"
#include "ibl/environment_map.h"
#include "ibl/image_based_lighting.h"
#include "janus/renderer/image.h"
#include "janus/renderer/renderer.h"
#include "renderer/renderer_test_support.h"

namespace janus::renderer {
namespace {

using test_support::Config;
namespace fs = std::filesystem;

constexpr float kSkyRadiance = 0.5f;
constexpr uint32_t kSize = 64;

// An equirectangular EXR of constant radiance, with `hot` texels (x, y, radiance) on top.
fs::path writeSky(const std::string& name, float radiance, std::vector<std::tuple<uint32_t, uint32_t, float>> hot = {}) {
    const fs::path path = fs::temp_directory_path() / fmt::format("janus-sky-{}-{}.exr", ::getpid(), name);
    ImageRGBAF sky{32, 16, {}};
    sky.pixels.assign(size_t(sky.width) * sky.height * 4, radiance);
    for (size_t i = 3; i < sky.pixels.size(); i += 4) sky.pixels[i] = 1.0f;
    for (const auto& [x, y, value] : hot)
        for (uint32_t c = 0; c < 3; ++c) sky.pixels[(size_t(y) * sky.width + x) * 4 + c] = value;
    writeEXR(path, sky);
    return path;
}
fs::path writeConstantSky(float radiance) { return writeSky(fmt::format("{}", radiance), radiance); }

// A quad facing the camera, centred, covering the middle of the image; the corners stay sky.
Scene quadUnderTheSky(const fs::path& sky, float intensity, float albedo, float roughness) {
    Scene scene;
    scene.name = "quad under a constant sky";
    Material material;
    material.baseColorFactor = {albedo, albedo, albedo, 1.0f};
    material.metallicFactor = 0.0f;
    material.roughnessFactor = roughness;
    scene.materials = {material};
    Mesh quad;
    const glm::vec4 tangent(0.0f);
    quad.vertices = {Vertex{{-0.5f, -0.5f, 0.0f}, {0, 0, 1}, {0, 1}, tangent}, Vertex{{0.5f, -0.5f, 0.0f}, {0, 0, 1}, {1, 1}, tangent},
                     Vertex{{0.5f, 0.5f, 0.0f}, {0, 0, 1}, {1, 0}, tangent}, Vertex{{-0.5f, 0.5f, 0.0f}, {0, 0, 1}, {0, 0}, tangent}};
    quad.indices = {0, 1, 2, 0, 2, 3};
    quad.material = 0;
    scene.meshes = {quad};
    scene.instances = {Instance{0, glm::mat4(1.0f)}};
    scene.camera.position = {0.0f, 0.0f, 2.0f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    scene.environment.map = sky;
    scene.environment.intensity = intensity;
    return scene;
}

glm::vec3 hdrAt(const ImageRGBAF& image, uint32_t x, uint32_t y) {
    const float* p = &image.pixels[(size_t(y) * image.width + x) * 4];
    return {p[0], p[1], p[2]};
}

class SkyLightingTest : public testing::TestWithParam<Config> {
protected:
    static void SetUpTestSuite() { s_sky = writeConstantSky(kSkyRadiance); }
    static void TearDownTestSuite() {
        std::error_code ec;
        fs::remove(s_sky, ec);
    }
    RenderSettings settings() const {
        RenderSettings s;
        s.width = s.height = kSize;
        return s;
    }
    static fs::path s_sky;
};
fs::path SkyLightingTest::s_sky;

TEST_P(SkyLightingTest, AConstantSkyLightsAHeadOnQuadAsTheSplitSumSays) {
    const float albedo = 0.8f, roughness = 1.0f, intensity = 1.5f;
    const test_support::FrameOutput out =
        test_support::renderOneFrame(GetParam(), quadUnderTheSky(s_sky, intensity, albedo, roughness), settings());
    const float L = kSkyRadiance * intensity;
    // Head-on at the centre: NoV = 1. Diffuse albedo * L (the SH of a constant is exact);
    // specular L * (0.04 A + B); specular occlusion is 1 without an occlusion texture.
    const glm::dvec2 dfg = integrateDfg(1.0, roughness, 4096);
    const float expected = albedo * L + L * float(0.04 * dfg.x + dfg.y);
    const glm::vec3 centre = hdrAt(out.hdr, kSize / 2, kSize / 2);
    // 1%: the DFG table is half-float and bilinearly filtered, the SH sums in float, the cube is
    // half-float; all far below what a wrong term (a missing specular adds 4%) would give.
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(centre[c], expected, 0.01f * expected) << GetParam().name() << " channel " << c;
    // The background is the sky itself, times the intensity (half-float 0.5 is exact).
    const glm::vec3 corner = hdrAt(out.hdr, 1, 1);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(corner[c], L, 1e-3f * L) << GetParam().name() << " channel " << c;
}

// A shading normal leaning 60 degrees from its triangle (smoothed normals, normal maps) takes only
// the sky above the triangle's plane: (1 + cos 60) / 2 = 3/4 of a constant sky's diffuse light.
// The plain SH evaluation gave all of it, while the irradiance volume's lookup clipped it: a
// surface at the volume's edge was lit by two rules (docs/GI.md, "Bent normals").
TEST_P(SkyLightingTest, ALeaningNormalTakesOnlyTheSkyAboveItsSurface) {
    const float albedo = 0.8f, roughness = 1.0f, intensity = 1.5f;
    const float lean = glm::radians(60.0f);
    Scene scene = quadUnderTheSky(s_sky, intensity, albedo, roughness);
    for (Vertex& v : scene.meshes[0].vertices) v.normal = glm::vec3(std::sin(lean), 0.0f, std::cos(lean));   // the quad faces +Z
    const test_support::FrameOutput out = test_support::renderOneFrame(GetParam(), scene, settings());
    const float L = kSkyRadiance * intensity;
    // Head-on camera, leaning normal: NoV = cos 60. The constant sky's specular does not depend on
    // the reflected direction.
    const glm::dvec2 dfg = integrateDfg(std::cos(lean), roughness, 4096);
    const float expected = albedo * L * 0.5f * (1.0f + std::cos(lean)) + L * float(0.04 * dfg.x + dfg.y);
    const glm::vec3 centre = hdrAt(out.hdr, kSize / 2, kSize / 2);
    // 1 %, as the head-on test; the whole sky instead of 3/4 of it would be 20 % more diffuse light.
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(centre[c], expected, 0.01f * expected) << GetParam().name() << " channel " << c;
}

TEST_P(SkyLightingTest, TheSkysFilteringIsReportedInTheFirstFrameOnly) {
    rhi::IDevice& device = test_support::deviceFor(GetParam().backend);
    device.takeDebugMessages();
    RenderSettings s = settings();
    s.path = GetParam().path;
    Renderer renderer(device, quadUnderTheSky(s_sky, 1.0f, 0.5f, 0.5f), s);
    const FrameReport first = renderer.renderFrame();
    const FrameReport second = renderer.renderFrame();
    const bool compute = GetParam().path == FeaturePath::Compute;
    for (const char* name : {compute ? "equirect-to-cube-compute" : "equirect-to-cube-fallback",
                             compute ? "ggx-prefilter-compute" : "ggx-prefilter-fallback",
                             compute ? "sh-irradiance-compute" : "sh-irradiance-fallback",
                             compute ? "background-cube-compute" : "background-cube-fallback"}) {
        EXPECT_TRUE(test_support::hasPassStartingWith(first, name)) << name << " in " << test_support::passNames(first);
        EXPECT_FALSE(test_support::hasPassStartingWith(second, name)) << name << " in " << test_support::passNames(second);
    }
    EXPECT_TRUE(test_support::hasPassStartingWith(second, "sky")) << test_support::passNames(second);
    const std::vector<rhi::DebugMessage> messages = device.takeDebugMessages();
    EXPECT_TRUE(messages.empty()) << test_support::joinMessages(messages);
}

TEST_P(SkyLightingTest, WithoutASkyThereIsNoSkyWorkAndTheAmbientColourLights) {
    Scene scene = quadUnderTheSky({}, 1.0f, 1.0f, 1.0f);
    scene.environment.ambientColor = glm::vec3(0.25f);
    const test_support::FrameOutput out = test_support::renderOneFrame(GetParam(), scene, settings());
    EXPECT_FALSE(test_support::hasPassStartingWith(out.report, "sky")) << test_support::passNames(out.report);
    EXPECT_FALSE(test_support::hasPassStartingWith(out.report, "ggx")) << test_support::passNames(out.report);
    // Background: the ambient colour (the clear colour).
    const glm::vec3 corner = hdrAt(out.hdr, 1, 1);
    EXPECT_NEAR(corner.x, 0.25f, 1e-3f);
}

// Skies that break naive filtering: a sun 1e5 times brighter than the rest, one texel at the
// half-float maximum, a sun beyond it (1e6: the RGBA16F cube must not turn it into Inf), and
// all black. Mirror-smooth and rough surfaces, on every configuration: finite, non-negative.
TEST_P(SkyLightingTest, HardSkiesGiveFiniteNonNegativeImages) {
    struct Case {
        std::string name;
        float radiance;
        std::vector<std::tuple<uint32_t, uint32_t, float>> hot;
    };
    const std::vector<Case> cases = {
        {"sun-1e5", 0.5f, {{20, 4, 5e4f}, {21, 4, 5e4f}, {20, 5, 5e4f}, {21, 5, 5e4f}}},
        {"texel-65504", 0.5f, {{8, 8, 65504.0f}}},
        {"sun-1e6", 0.5f, {{16, 7, 1e6f}}},
        {"black", 0.0f, {}},
    };
    for (const Case& c : cases) {
        const fs::path sky = writeSky(c.name, c.radiance, c.hot);
        for (float roughness : {0.0f, 1.0f}) {
            for (float metallic : {0.0f, 1.0f}) {
                Scene scene = quadUnderTheSky(sky, 1.0f, 0.9f, roughness);
                scene.materials[0].metallicFactor = metallic;
                const test_support::FrameOutput out = test_support::renderOneFrame(GetParam(), scene, settings());
                const std::string label = fmt::format("{} sky {} roughness {} metallic {}", GetParam().name(), c.name, roughness, metallic);
                test_support::expectFiniteHdr(out.hdr, label);
                if (c.name == "black") {
                    EXPECT_EQ(hdrAt(out.hdr, kSize / 2, kSize / 2), glm::vec3(0.0f)) << label;
                    EXPECT_EQ(hdrAt(out.hdr, 1, 1), glm::vec3(0.0f)) << label;
                }
            }
        }
        std::error_code ec;
        fs::remove(sky, ec);
    }
}

TEST_P(SkyLightingTest, AnUnreadableSkyIsARendererErrorNamingTheFile) {
    const fs::path garbage = fs::temp_directory_path() / fmt::format("janus-sky-garbage-{}.hdr", ::getpid());
    { std::ofstream(garbage) << "not a radiance file"; }
    rhi::IDevice& device = test_support::deviceFor(GetParam().backend);
    RenderSettings s = settings();
    s.path = GetParam().path;
    try {
        Renderer renderer(device, quadUnderTheSky(garbage, 1.0f, 0.5f, 0.5f), s);
        ADD_FAILURE() << "a garbage sky was accepted";
    } catch (const RendererError& e) {
        EXPECT_NE(std::string(e.what()).find(garbage.filename().string()), std::string::npos) << e.what();
    }
    std::error_code ec;
    fs::remove(garbage, ec);
    device.takeDebugMessages();
}

// A 1024x512 sky of 8-texel checker cells (radiance 0.1 and 2): the background has edges at the
// sky file's own resolution.
std::shared_ptr<ImageRGBAF> checkerSky() {
    auto sky = std::make_shared<ImageRGBAF>(ImageRGBAF{1024, 512, {}});
    sky->pixels.resize(size_t(sky->width) * sky->height * 4);
    for (uint32_t y = 0; y < sky->height; ++y)
        for (uint32_t x = 0; x < sky->width; ++x) {
            const float value = ((x / 8 + y / 8) % 2) ? 2.0f : 0.1f;
            float* p = &sky->pixels[(size_t(y) * sky->width + x) * 4];
            p[0] = value, p[1] = value * 0.5f, p[2] = 0.25f, p[3] = 1.0f;
        }
    return sky;
}

// The sky's radiance along `direction`, bilinear in the equirect (u wraps, v clamps), as the
// conversion samples it.
glm::vec3 equirectRadiance(const ImageRGBAF& sky, const glm::dvec3& direction) {
    const glm::dvec2 uv = equirectUv(direction);
    const double x = uv.x * sky.width - 0.5, y = std::clamp(uv.y * sky.height - 0.5, 0.0, double(sky.height - 1));
    const double x0 = std::floor(x), y0 = std::floor(y), fx = x - x0, fy = y - y0;
    glm::dvec3 sum(0.0);
    for (int dy = 0; dy <= 1; ++dy)
        for (int dx = 0; dx <= 1; ++dx) {
            const uint32_t tx = uint32_t((int64_t(x0) + dx + sky.width) % sky.width);
            const uint32_t ty = uint32_t(std::min<double>(y0 + dy, sky.height - 1));
            const float* p = &sky.pixels[(size_t(ty) * sky.width + tx) * 4];
            sum += glm::dvec3(p[0], p[1], p[2]) * ((dx ? fx : 1.0 - fx) * (dy ? fy : 1.0 - fy));
        }
    return glm::vec3(sum);
}

// The background against the sky file itself: each pixel's mean over its footprint (`rays`^2
// rays through the pixel, the sky sampled along each), error per pixel the largest channel's
// |difference| in x/(1+x); returns its mean over the image.
double backgroundError(const Scene& scene, const ImageRGBAF& rendered, uint32_t rays) {
    const SceneView view = makeCameraView(scene.camera, rendered.width, rendered.height);
    const glm::dmat4 toDirection = glm::inverse(glm::dmat4(view.projection) * glm::dmat4(glm::dmat3(glm::dmat4(view.view))));
    auto compressed = [](double x) { return std::max(x, 0.0) / (1.0 + std::max(x, 0.0)); };
    double sum = 0.0;
    for (uint32_t y = 0; y < rendered.height; ++y)
        for (uint32_t x = 0; x < rendered.width; ++x) {
            glm::dvec3 expected(0.0);
            for (uint32_t sy = 0; sy < rays; ++sy)
                for (uint32_t sx = 0; sx < rays; ++sx) {
                    // Row 0 is the top of the image, where NDC y is -1 (the RHI's convention).
                    const glm::dvec2 ndc((x + (sx + 0.5) / rays) / rendered.width * 2.0 - 1.0,
                                         (y + (sy + 0.5) / rays) / rendered.height * 2.0 - 1.0);
                    const glm::dvec4 nearPoint = toDirection * glm::dvec4(ndc, 0.0, 1.0), farPoint = toDirection * glm::dvec4(ndc, 1.0, 1.0);
                    const glm::dvec3 direction = glm::normalize(glm::dvec3(farPoint) / farPoint.w - glm::dvec3(nearPoint) / nearPoint.w);
                    expected += glm::dvec3(equirectRadiance(*scene.environment.image, direction));
                }
            expected /= double(rays * rays);
            const glm::vec3 got = hdrAt(rendered, x, y);
            double error = 0.0;
            for (int c = 0; c < 3; ++c) error = std::max(error, std::abs(compressed(got[c]) - compressed(expected[c])));
            sum += error;
        }
    return sum / double(size_t(rendered.width) * rendered.height);
}

// The background is as sharp as the sky file (its own cube of a quarter of the file's width a
// face, 256^2 here, not the 128^2 lighting cube) and, in an image smaller than the sky, the mean
// of each pixel's footprint (the cube's box-filtered mips at the pixel's level of detail, not mip
// 0 point-sampled). Camera at the horizon, 90 degrees, looking away from the quad: all sky.
TEST_P(SkyLightingTest, TheBackgroundIsAsSharpAsTheSkyAndAveragedWhereSmaller) {
    EXPECT_EQ(ImageBasedLighting::backgroundFaceSize(1024, 16384), 256u);
    EXPECT_EQ(ImageBasedLighting::backgroundFaceSize(64, 16384), ImageBasedLighting::kSkyFaceSize);
    EXPECT_EQ(ImageBasedLighting::backgroundFaceSize(16384, 16384), ImageBasedLighting::kMaxBackgroundFaceSize);
    EXPECT_EQ(ImageBasedLighting::backgroundFaceSize(16384, 512), 512u);
    Scene scene = quadUnderTheSky({}, 1.0f, 0.5f, 0.5f);
    scene.environment.map.clear();
    scene.environment.image = checkerSky();
    scene.camera.position = {0.0f, 0.0f, 2.0f};
    scene.camera.target = {0.7f, 0.1f, 12.0f};
    scene.camera.fovYRadians = glm::radians(90.0f);
    RenderSettings large = settings(), small = settings();
    large.width = large.height = 256;
    small.width = small.height = 32;
    const test_support::FrameOutput sharp = test_support::renderOneFrame(GetParam(), scene, large);
    const test_support::FrameOutput averaged = test_support::renderOneFrame(GetParam(), scene, small);
    const double sharpError = backgroundError(scene, sharp.hdr, 1), averagedError = backgroundError(scene, averaged.hdr, 8);
    // Here 0.0245 and 0.054 on every configuration. From the 128^2 cube the large image's error
    // is 0.066 (twice as blurred); with mip 0 point-sampled the small image's is 0.166. What is
    // left is the two bilinear resamplings (equirect -> cube -> pixel) and, small, how closely a
    // trilinear lookup approximates the footprint's box.
    EXPECT_LT(sharpError, 0.04) << "the background is blurred: sampled from a cube coarser than the sky";
    EXPECT_LT(averagedError, 0.09) << "the background aliases: mip 0 point-sampled where a pixel covers many texels";
}

INSTANTIATE_TEST_SUITE_P(Configs, SkyLightingTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
