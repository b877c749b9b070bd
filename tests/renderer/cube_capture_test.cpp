// Scene views: the six cube-face views of a point render straight into a cube map's faces, and
// each face shows what a 90-degree perspective camera at that point, looking along the face's
// axis with the face's up vector, sees (mirrored left to right, as the cube map layout is).
// On every configuration: into one cube of a cube array where the device has cube arrays (the
// middle one of three, so the layer-face arithmetic is exercised), into a cube map on gles,
// which has none (Capability::CubeArrays).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <fmt/format.h>
#include <glm/gtc/packing.hpp>

#include "janus/renderer/renderer.h"
#include "janus/renderer/scene_view.h"
#include "renderer/renderer_test_support.h"

namespace janus::renderer {
namespace {

using test_support::Config;

constexpr uint32_t kFaceSize = 64;
const glm::vec3 kCapturePoint(0.35f, 0.9f, -0.6f);   // inside the default scene's room, off-centre

std::vector<float> halfsToFloats(const std::vector<std::byte>& bytes) {
    std::vector<float> values(bytes.size() / 2);
    for (size_t i = 0; i < values.size(); ++i) {
        uint16_t half;
        std::memcpy(&half, bytes.data() + i * 2, 2);
        values[i] = glm::unpackHalf1x16(half);
    }
    return values;
}

class CubeCaptureTest : public testing::TestWithParam<Config> {
protected:
    rhi::IDevice& device() { return test_support::deviceFor(GetParam().backend); }
    RenderSettings settings() const {
        RenderSettings s;
        s.width = s.height = kFaceSize;
        s.path = GetParam().path;
        return s;
    }
    rhi::TextureHandle makeCube(rhi::Format format = rhi::Format::RGBA16_FLOAT) {
        return device().createTexture(rhi::TextureDesc{}
                                          .setDimension(rhi::TextureDimension::TextureCube)
                                          .setFormat(format)
                                          .setSize(kFaceSize, kFaceSize)
                                          .setUsage(rhi::TextureUsage::RenderTarget | rhi::TextureUsage::Sampled)
                                          .setDebugName("capture cube"));
    }
    bool hasCubeArrays() { return device().capabilities().has(rhi::Capability::CubeArrays); }
    // Three cubes where the device has cube arrays; a cube map otherwise.
    rhi::TextureHandle makeCaptureTarget() {
        if (!hasCubeArrays()) return makeCube();
        return device().createTexture(rhi::TextureDesc{}
                                          .setDimension(rhi::TextureDimension::TextureCubeArray)
                                          .setFormat(rhi::Format::RGBA16_FLOAT)
                                          .setSize(kFaceSize, kFaceSize)
                                          .setArrayLayers(3 * 6)
                                          .setUsage(rhi::TextureUsage::RenderTarget | rhi::TextureUsage::Sampled)
                                          .setDebugName("capture cube array"));
    }
    void expectNoMessages() {
        const std::vector<rhi::DebugMessage> messages = device().takeDebugMessages();
        EXPECT_TRUE(messages.empty()) << GetParam().name() << ":" << test_support::joinMessages(messages);
    }
};

TEST_P(CubeCaptureTest, EachFaceShowsWhatAPerspectiveCameraAlongItsAxisSees) {
    device().takeDebugMessages();
    const Scene scene = defaultScene();
    const rhi::TextureHandle cube = makeCaptureTarget();
    const uint32_t cubeIndex = hasCubeArrays() ? 1 : 0;
    FrameReport report;
    {
        Renderer renderer(device(), scene, settings());
        CubeCaptureDesc capture;
        capture.position = kCapturePoint;
        capture.nearPlane = scene.camera.nearPlane;
        capture.farPlane = scene.camera.farPlane;
        capture.target = cube;
        capture.cube = cubeIndex;
        report = renderer.renderCubeCapture(capture);
    }
    ASSERT_EQ(report.views.size(), 6u);
    std::vector<std::string> forwardViews;
    for (const PassReport& pass : report.passes)
        if (pass.name == "forward") forwardViews.push_back(pass.view);
    EXPECT_EQ(forwardViews, (std::vector<std::string>{"cube +X", "cube -X", "cube +Y", "cube -Y", "cube +Z", "cube -Z"}))
        << test_support::passNames(report);
    for (uint32_t face = 0; face < 6; ++face) EXPECT_EQ(report.views[face].name, forwardViews.at(face));
    // The shadow map does not depend on the camera: one pass serves all six faces.
    EXPECT_EQ(std::count_if(report.passes.begin(), report.passes.end(), [](const PassReport& p) { return p.name == "shadow-map"; }), 1)
        << test_support::passNames(report);

    for (uint32_t face = 0; face < 6; ++face) {
        SCOPED_TRACE(fmt::format("{} face {}", GetParam().name(), cubeFaceName(face)));
        const std::vector<float> faceRadiance = halfsToFloats(device().readTexture(cube, {0, cubeIndex * 6 + face}));
        ASSERT_EQ(faceRadiance.size(), size_t(kFaceSize) * kFaceSize * 4);

        Scene camera = scene;
        camera.camera.position = kCapturePoint;
        camera.camera.target = kCapturePoint + cubeFaceDirection(face);
        camera.camera.up = cubeFaceUp(face);
        camera.camera.fovYRadians = glm::radians(90.0f);
        const test_support::FrameOutput expected = test_support::renderOneFrame(GetParam(), camera, settings());

        // Column x of the face is column size-1-x of the camera's image. The mirrored projection
        // negates clip x exactly, so coverage and interpolation mirror; a pixel may still differ
        // where an edge passes exactly through pixel centres (the tie-break rule is not
        // mirror-symmetric) and by a rounding step in the interpolated attributes. Hence: almost
        // every pixel within 0.5% (+1e-3 absolute), and at most 1% of pixels anywhere else.
        size_t outliers = 0;
        double sum = 0.0;
        for (uint32_t y = 0; y < kFaceSize; ++y) {
            for (uint32_t x = 0; x < kFaceSize; ++x) {
                const size_t f = (size_t(y) * kFaceSize + x) * 4;
                const size_t c = (size_t(y) * kFaceSize + (kFaceSize - 1 - x)) * 4;
                bool close = true;
                for (size_t ch = 0; ch < 3; ++ch) {
                    const float a = faceRadiance[f + ch], b = expected.hdr.pixels[c + ch];
                    sum += a;
                    if (!(std::fabs(a - b) <= 1e-3f + 5e-3f * std::fabs(b))) close = false;
                }
                if (!close) ++outliers;
            }
        }
        EXPECT_GT(sum, 0.0) << "the face is black";
        EXPECT_LE(outliers, size_t(kFaceSize) * kFaceSize / 100) << outliers << " pixels differ from the camera's view";
    }
    expectNoMessages();
}

TEST_P(CubeCaptureTest, ACaptureWithoutShadowsRunsNoShadowPass) {
    device().takeDebugMessages();
    Renderer renderer(device(), defaultScene(), settings());
    CubeCaptureDesc capture;
    capture.position = kCapturePoint;
    capture.target = makeCube();
    capture.shadows = false;
    const FrameReport report = renderer.renderCubeCapture(capture);
    EXPECT_FALSE(test_support::hasPassStartingWith(report, "shadow-map")) << test_support::passNames(report);
    EXPECT_EQ(report.passes.size(), 6u) << test_support::passNames(report);
    // The main frame still has its shadow pass.
    EXPECT_TRUE(test_support::hasPassStartingWith(renderer.renderFrame(), "shadow-map"));
    expectNoMessages();
}

TEST_P(CubeCaptureTest, CapturingAgainGivesTheSameFacesAndAMainFrameInBetweenChangesNothing) {
    device().takeDebugMessages();
    Renderer renderer(device(), defaultScene(), settings());
    CubeCaptureDesc capture;
    capture.position = kCapturePoint;
    capture.target = makeCube();
    renderer.renderCubeCapture(capture);
    std::vector<std::vector<std::byte>> first;
    for (uint32_t face = 0; face < 6; ++face) first.push_back(device().readTexture(capture.target, {0, face}));
    const FrameReport main = renderer.renderFrame();
    const FrameReport again = renderer.renderCubeCapture(capture);
    EXPECT_EQ(again.views.size(), 6u);
    for (uint32_t face = 0; face < 6; ++face)
        EXPECT_EQ(device().readTexture(capture.target, {0, face}), first[face]) << "face " << cubeFaceName(face);
    EXPECT_EQ(main.views.size(), 1u);
    expectNoMessages();
}

TEST_P(CubeCaptureTest, RefusesTargetsThatAreNotFloatCubeRenderTargets) {
    Renderer renderer(device(), defaultScene(), settings());
    CubeCaptureDesc capture;
    EXPECT_THROW(renderer.renderCubeCapture(capture), RendererError);   // no target
    capture.target = device().createTexture(rhi::TextureDesc{}
                                                .setFormat(rhi::Format::RGBA16_FLOAT)
                                                .setSize(kFaceSize, kFaceSize)
                                                .setUsage(rhi::TextureUsage::RenderTarget));
    EXPECT_THROW(renderer.renderCubeCapture(capture), RendererError);   // a 2D texture
    capture.target = makeCube(rhi::Format::RGBA8_UNORM);
    EXPECT_THROW(renderer.renderCubeCapture(capture), RendererError);   // radiance would clamp at 1
    capture.target = makeCube();
    capture.mipLevel = 1;
    EXPECT_THROW(renderer.renderCubeCapture(capture), RendererError);   // no mip 1
    capture.mipLevel = 0;
    capture.cube = 1;
    EXPECT_THROW(renderer.renderCubeCapture(capture), RendererError);   // a cube map holds one cube
    device().takeDebugMessages();
}

// A NaN or infinite position or an infinite far plane made NaN view or projection matrices and a
// capture of nothing (no error); now each is a RendererError naming it.
TEST_P(CubeCaptureTest, RefusesANonFinitePositionOrFarPlane) {
    Renderer renderer(device(), defaultScene(), settings());
    CubeCaptureDesc capture;
    capture.target = makeCube();
    capture.farPlane = std::numeric_limits<float>::infinity();
    EXPECT_THROW(renderer.renderCubeCapture(capture), RendererError);
    capture.farPlane = 100.0f;
    for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        capture.position = glm::vec3(0.0f, bad, 0.0f);
        try {
            renderer.renderCubeCapture(capture);
            ADD_FAILURE() << "position y " << bad << " was accepted";
        } catch (const RendererError& e) {
            EXPECT_NE(std::string(e.what()).find("position"), std::string::npos) << e.what();
        }
    }
    expectNoMessages();
}

TEST_P(CubeCaptureTest, TheMainFrameReportListsItsView) {
    const test_support::FrameOutput output = test_support::renderOneFrame(GetParam(), defaultScene(), settings());
    ASSERT_EQ(output.report.views.size(), 1u);
    EXPECT_EQ(output.report.views[0].name, "main");
    EXPECT_EQ(output.report.views[0].width, kFaceSize);
    // Every pass works for the main view, except the shadow map, which serves any view.
    for (const PassReport& pass : output.report.passes) EXPECT_EQ(pass.view, pass.name == "shadow-map" ? "" : "main") << pass.name;
}

INSTANTIATE_TEST_SUITE_P(Configs, CubeCaptureTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
