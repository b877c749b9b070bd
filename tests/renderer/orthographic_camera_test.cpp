// Orthographic cameras on all five configurations: the image is the CPU's parallel projection of
// the scene, every surface sees the camera in one direction (specular does not vary across a
// flat surface), the sky is seen along the view axis, and the lit, tiled room agrees with
// vulkan/compute. Tile culling for orthographic views: forward_plus_test.cpp and light_grid_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "janus/renderer/renderer.h"
#include "renderer/renderer_test_support.h"
#include "scene/scene_internal.h"

namespace janus::renderer {
namespace {

using test_support::FrameOutput;

Camera orthographicCamera(glm::vec3 position, glm::vec3 target, float halfHeight, float near, float far) {
    Camera camera;
    camera.projection = CameraProjection::Orthographic;
    camera.position = position;
    camera.target = target;
    camera.orthographicHalfHeight = halfHeight;
    camera.nearPlane = near;
    camera.farPlane = far;
    return camera;
}

// An axis-aligned square in the XY plane facing +Z (makeQuad is 2 x 2).
struct Square {
    glm::vec3 center;
    float size;
    glm::vec3 color;
};

int32_t addUnlitMaterial(Scene& scene, const std::string& name, glm::vec3 color) {
    const int32_t material = detail::addMaterial(scene, name, color, 0.0f, 1.0f);
    scene.materials[size_t(material)].unlit = true;
    return material;
}

Scene squaresScene(const std::vector<Square>& squares, const Camera& camera) {
    Scene scene;
    for (size_t i = 0; i < squares.size(); ++i) {
        const Square& square = squares[i];
        scene.meshes.push_back(detail::makeQuad(addUnlitMaterial(scene, fmt::format("square {}", i), square.color)));
        scene.instances.push_back(Instance{uint32_t(i), glm::scale(glm::translate(glm::mat4(1.0f), square.center), glm::vec3(square.size * 0.5f))});
    }
    scene.environment.ambientColor = glm::vec3(0.0f);
    scene.camera = camera;
    return scene;
}

// The CPU's parallel projection: pixel (x, y)'s ray starts on the view plane at the pixel centre's
// offset from the axis and runs along the view direction; the nearest square it meets between
// the near and far planes gives the pixel its colour. Pixels whose ray passes within `margin`
// (world units) of a square's edge are left unjudged (nullopt): rasterisation decides those.
struct Expected {
    std::optional<int> square;   // -1 = background
};
std::vector<Expected> castParallelRays(const std::vector<Square>& squares, const Camera& camera, uint32_t width, uint32_t height,
                                       double margin) {
    const glm::dvec3 eye(camera.position), forward = glm::normalize(glm::dvec3(camera.target) - eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(camera.up)));
    const glm::dvec3 up = glm::cross(right, forward);
    const double halfHeight = camera.orthographicHalfHeight, halfWidth = halfHeight * width / height;
    std::vector<Expected> expected(size_t(width) * height);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            // Row 0 is the top of the view (NDC y = -1, docs/ARCHITECTURE.md).
            const double u = (2.0 * (x + 0.5) / width - 1.0) * halfWidth, v = (1.0 - 2.0 * (y + 0.5) / height) * halfHeight;
            const glm::dvec3 origin = eye + right * u + up * v;
            double nearest = camera.farPlane;
            int hit = -1;
            bool judged = true;
            for (size_t i = 0; i < squares.size(); ++i) {
                const glm::dvec3 center(squares[i].center);
                const double t = (center.z - origin.z) / forward.z;   // the squares face +Z
                if (t < camera.nearPlane || t > camera.farPlane) continue;
                const glm::dvec3 p = origin + forward * t;
                const double outside = std::max(std::abs(p.x - center.x), std::abs(p.y - center.y)) - squares[i].size * 0.5;
                if (std::abs(outside) < margin) judged = false;
                if (outside < 0.0 && t < nearest) nearest = t, hit = int(i);
            }
            expected[size_t(y) * width + x].square = judged ? std::optional<int>(hit) : std::nullopt;
        }
    return expected;
}

// Which square's colour a display pixel shows (-1: black background; nullopt: neither).
std::optional<int> classify(const ImageRGBA8& image, uint32_t x, uint32_t y, const std::vector<Square>& squares) {
    const uint8_t* p = &image.pixels[(size_t(y) * image.width + x) * 4];
    if (p[0] < 8 && p[1] < 8 && p[2] < 8) return -1;
    for (size_t i = 0; i < squares.size(); ++i) {
        const glm::vec3 c = squares[i].color;
        auto near = [](uint8_t value, float channel) { return channel > 0.5f ? value > 180 : value < 40; };
        if (near(p[0], c.r) && near(p[1], c.g) && near(p[2], c.b)) return int(i);
    }
    return std::nullopt;
}

class OrthographicCameraTest : public test_support::ConfigTest {
protected:
    FrameOutput render(const Scene& scene, uint32_t width, uint32_t height, bool shadows = true) {
        RenderSettings settings = settingsOfSize(width, height);
        settings.lighting.shadows = shadows;
        return test_support::renderOneFrame(GetParam(), scene, settings);
    }
};

// Equal squares at different distances appear equally large (perspective would shrink the far
// one), a square behind the near plane does not appear, and every pixel is where the CPU's
// parallel projection puts it, through an oblique camera in a wide (non-square) image.
TEST_P(OrthographicCameraTest, TheImageIsTheParallelProjectionOfTheScene) {
    const std::vector<Square> squares = {
        {{-1.0f, 0.0f, 0.0f}, 1.0f, {1, 0, 0}},    // red, near
        {{1.0f, 0.0f, -6.0f}, 1.0f, {0, 1, 0}},    // green, the same size 6 units further
        {{0.0f, 0.6f, -3.0f}, 0.8f, {0, 0, 1}},    // blue, between, partly hidden
        {{0.0f, 0.0f, 4.9f}, 3.0f, {1, 1, 0}},     // yellow, before the near plane: clipped
    };
    const Camera camera = orthographicCamera({0.6f, 0.9f, 5.0f}, {0.1f, 0.2f, -2.0f}, 1.6f, 0.5f, 30.0f);
    constexpr uint32_t kWidth = 96, kHeight = 64;
    const FrameOutput output = render(squaresScene(squares, camera), kWidth, kHeight);
    // A third of a pixel (1 px = 3.2 / 64 = 0.05 world units): closer than that, coverage is the rasteriser's call.
    const std::vector<Expected> expected = castParallelRays(squares, camera, kWidth, kHeight, 0.05 / 3.0);
    uint32_t judged = 0, wrong = 0;
    std::vector<uint32_t> pixelsPerSquare(squares.size(), 0);
    std::string first;
    for (uint32_t y = 0; y < kHeight; ++y)
        for (uint32_t x = 0; x < kWidth; ++x) {
            const std::optional<int> want = expected[size_t(y) * kWidth + x].square;
            if (!want) continue;
            ++judged;
            if (*want >= 0) ++pixelsPerSquare[size_t(*want)];
            const std::optional<int> got = classify(output.display, x, y, squares);
            if (got != want && wrong++ == 0)
                first = fmt::format("pixel ({}, {}) shows {} where the projection puts {}", x, y, got ? fmt::format("{}", *got) : "?", *want);
        }
    EXPECT_EQ(wrong, 0u) << GetParam().name() << ": " << wrong << " of " << judged << " pixels; first: " << first;
    EXPECT_GT(judged, kWidth * kHeight * 9 / 10);
    // The scene tests what it should: red and green seen whole and equally large, blue partly, yellow not at all.
    EXPECT_GT(pixelsPerSquare[0], 200u);
    EXPECT_NEAR(double(pixelsPerSquare[1]), double(pixelsPerSquare[0]), 0.05 * pixelsPerSquare[0]);
    EXPECT_GT(pixelsPerSquare[2], 50u);
    EXPECT_EQ(pixelsPerSquare[3], 0u);
}

// A flat glossy surface under a directional light: through an orthographic camera the view
// direction is the same at every pixel, so so is the shading; through a perspective camera at
// the same place it is not (which shows the test can fail: the view vector from the camera's
// position to each surface point is what an orthographic camera must not use).
TEST_P(OrthographicCameraTest, EverySurfaceSeesTheCameraAlongTheViewAxis) {
    Scene scene;
    const int32_t material = detail::addMaterial(scene, "gloss", {0.6f, 0.6f, 0.6f}, 0.0f, 0.3f);
    scene.meshes.push_back(detail::makeQuad(material));
    scene.instances.push_back(Instance{0, glm::scale(glm::mat4(1.0f), glm::vec3(4.0f))});   // 8 x 8 at z = 0, facing +Z
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(0.15f, -0.1f, -1.0f));   // a highlight near the view axis
    sun.intensity = 3.0f;
    scene.lights.push_back(sun);
    scene.environment.ambientColor = glm::vec3(0.0f);
    scene.camera = orthographicCamera({0.0f, 0.0f, 3.0f}, {0.0f, 0.0f, 0.0f}, 2.0f, 0.1f, 10.0f);
    auto spread = [](const ImageRGBAF& hdr) {   // (max - min) / max of the red channel over the image
        float lo = INFINITY, hi = 0.0f;
        for (size_t i = 0; i < hdr.pixels.size(); i += 4) lo = std::min(lo, hdr.pixels[i]), hi = std::max(hi, hdr.pixels[i]);
        return hi > 0.0f ? (hi - lo) / hi : 1.0f;
    };
    const FrameOutput orthographic = render(scene, 48, 48, false);
    test_support::expectFiniteHdr(orthographic.hdr, "orthographic");
    // Half-float steps are 1/1024 relative: the interpolated normal's rounding may move a pixel by one.
    EXPECT_LE(spread(orthographic.hdr), 2.0f / 1024.0f) << GetParam().name();
    Scene perspective = scene;
    perspective.camera.projection = CameraProjection::Perspective;
    perspective.camera.fovYRadians = glm::radians(67.0f);   // about the same view of the plane
    EXPECT_GT(spread(render(perspective, 48, 48, false).hdr), 0.05f) << GetParam().name() << ": the control must vary";
}

// Parallel rays meet the sky at one point: the background is one colour.
TEST_P(OrthographicCameraTest, TheSkyIsSeenAlongTheViewAxis) {
    // A sky that changes with every direction: radiance from the direction's longitude and latitude.
    auto sky = std::make_shared<ImageRGBAF>();
    sky->width = 64;
    sky->height = 32;
    for (uint32_t y = 0; y < sky->height; ++y)
        for (uint32_t x = 0; x < sky->width; ++x)
            sky->pixels.insert(sky->pixels.end(), {0.2f + 0.8f * float(x) / 63.0f, 0.2f + 0.8f * float(y) / 31.0f, 0.5f, 1.0f});
    const std::vector<Square> squares = {{{0.0f, 0.0f, 0.0f}, 0.5f, {1, 1, 1}}};
    Scene scene = squaresScene(squares, orthographicCamera({0.3f, 0.2f, 4.0f}, {0.0f, 0.0f, 0.0f}, 1.5f, 0.1f, 20.0f));
    scene.environment.image = sky;
    auto backgroundSpread = [](const ImageRGBAF& hdr) {   // over the outer border, which only sky covers
        float lo = INFINITY, hi = 0.0f;
        for (uint32_t y = 0; y < hdr.height; ++y)
            for (uint32_t x = 0; x < hdr.width; ++x) {
                if (x > 3 && x + 4 < hdr.width && y > 3 && y + 4 < hdr.height) continue;
                const float r = hdr.pixels[(size_t(y) * hdr.width + x) * 4];
                lo = std::min(lo, r), hi = std::max(hi, r);
            }
        return (hi - lo) / hi;
    };
    const FrameOutput orthographic = render(scene, 48, 48);
    test_support::expectFiniteHdr(orthographic.hdr, "orthographic sky");
    EXPECT_EQ(backgroundSpread(orthographic.hdr), 0.0f) << GetParam().name();
    Scene perspective = scene;
    perspective.camera.projection = CameraProjection::Perspective;
    EXPECT_GT(backgroundSpread(render(perspective, 48, 48).hdr), 0.02f) << GetParam().name() << ": the control must vary";
}

// The default room with local lights (tiled culling) and its shadowed sun, seen through an
// orthographic camera, agrees with vulkan/compute.
TEST_P(OrthographicCameraTest, TheLitRoomMatchesVulkanCompute) {
    Scene scene = defaultScene();
    scene.camera = orthographicCamera(scene.camera.position, scene.camera.target, 1.6f, 0.0f, scene.camera.farPlane);
    for (int i = 0; i < 12; ++i)
        scene.lights.push_back(test_support::pointLight({-1.6f + 0.3f * float(i), 0.2f + 0.2f * float(i % 4), -1.5f + 0.25f * float(i)},
                                                        {1.0f, 0.5f + 0.04f * float(i), 0.3f}, 1.5f, 1.2f));
    RenderSettings settings = settingsOfSize(test_support::kSize, test_support::kSize);
    settings.lighting.culling = LightCulling::TilesDepth;
    static std::optional<FrameOutput> reference;
    if (!reference) reference = test_support::renderOneFrame(test_support::allConfigs()[0], scene, settings);
    const FrameOutput result = test_support::renderOneFrame(GetParam(), scene, settings);
    ASSERT_TRUE(result.report.lightCulling.has_value());
    EXPECT_EQ(result.report.lightCulling->mode, LightCulling::TilesDepth);
    test_support::expectFiniteHdr(result.hdr, "orthographic room");
    test_support::expectMatchesVulkanCompute(reference->display, result.display, "orthographic-room", GetParam());
}

INSTANTIATE_TEST_SUITE_P(Configs, OrthographicCameraTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<test_support::Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
