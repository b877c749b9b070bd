// --debug gi's probes (docs/GI.md, debug_views/gi_probe_view.*), on every configuration: in a
// closed room with coloured glowing walls and one probe boxed in (invalid), the pixel at a valid
// probe's projected centre shows that probe's SH irradiance / pi at the sphere's normal there, the
// boxed probe's pixel is the invalid colour, and the "gi-probes" pass exists only in that view
// and only with a volume.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "ibl/spherical_harmonics.h"
#include "janus/renderer/renderer.h"
#include "renderer/renderer_test_support.h"
#include "scene/scene_internal.h"

namespace janus::renderer {
namespace {

namespace fs = std::filesystem;
using test_support::Config;

const fs::path kCornellBox = fs::path(JANUS_SHARED_SCENES_DIR) / "cornell-box" / "cornellBox.gltf";

class GiProbeViewTest : public test_support::ConfigTest {};

using test_support::countPasses;

constexpr float kSpacing = 0.6f;                      // 3 x 3 x 3 probes at -0.6, 0, 0.6 on each axis
constexpr float kRadius = 0.1f * kSpacing;            // gi_probe_view.h: 0.1 x the smallest spacing
const glm::vec3 kBoxedProbe(-0.6f, -0.6f, -0.6f);     // inside a closed box: sees back faces only
constexpr float kBoxHalfSize = 0.15f;

// A closed 2 m room whose double-sided walls glow in six colours (black albedo), a closed box
// around one probe, and a camera in a corner with a wide view over the probes.
Scene probeRoom() {
    Scene scene;
    scene.name = "probe room";
    scene.environment.ambientColor = glm::vec3(0.0f);
    test_support::addGlowingRoom(scene, {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1), glm::vec3(1, 1, 0),
                                         glm::vec3(0, 1, 1), glm::vec3(0.5f)});
    const int32_t grey = detail::addMaterial(scene, "box", glm::vec3(0.5f), 0.0f, 1.0f);
    const uint32_t box = detail::addMesh(scene, detail::makeBox(grey));   // -1..1, faces outwards
    glm::mat4 world(kBoxHalfSize);
    world[3] = glm::vec4(kBoxedProbe, 1.0f);
    scene.instances.push_back(Instance{box, world, 1u, "box"});
    scene.camera.position = glm::vec3(0.85f, 0.8f, 0.9f);
    scene.camera.target = glm::vec3(-0.5f, -0.6f, -0.6f);
    scene.camera.fovYRadians = glm::radians(80.0f);
    IrradianceVolume volume;
    volume.bounds = Box{glm::vec3(-0.9f), glm::vec3(0.9f)};
    volume.probeCounts = glm::uvec3(3);
    volume.surfelsPerProbe = 256;
    volume.bounces = 1;
    volume.relocateProbes = false;   // the boxed probe stays in its box: invalid, to be shown so
    scene.irradianceVolume = volume;
    scene.lights.clear();
    return scene;
}

// Where the ray from `origin` along unit `direction` enters the sphere, if it does.
std::optional<double> hitSphere(const glm::dvec3& origin, const glm::dvec3& direction, const glm::dvec3& centre, double radius) {
    const glm::dvec3 oc = origin - centre;
    const double b = glm::dot(oc, direction);
    const double h = b * b - (glm::dot(oc, oc) - radius * radius);
    if (h < 0.0) return std::nullopt;
    return -b - std::sqrt(h);
}

bool rayHitsBox(const glm::dvec3& origin, const glm::dvec3& direction, const glm::dvec3& lo, const glm::dvec3& hi, double before) {
    double t0 = 0.0, t1 = before;
    for (int a = 0; a < 3; ++a) {
        const double inv = 1.0 / direction[a];
        double ta = (lo[a] - origin[a]) * inv, tb = (hi[a] - origin[a]) * inv;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1;
}

// Through a perspective camera and an orthographic one (parallel rays: the quads face the view
// axis and the spheres are cut out along it).
TEST_P(GiProbeViewTest, ProbesShowTheirIrradianceAndInvalidProbesTheInvalidColour) {
    for (const bool orthographic : {false, true}) {
        SCOPED_TRACE(orthographic ? "orthographic" : "perspective");
        device().takeDebugMessages();
        Scene scene = probeRoom();
        if (orthographic) {
            // Its rays start on the near plane, which must lie inside the glowing room (from
            // outside, the walls hide everything): a near plane at the eye, the eye near the front
            // wall looking nearly along -Z, so the front layer of probes shows and the boxed one too.
            scene.camera.projection = CameraProjection::Orthographic;
            scene.camera.position = glm::vec3(0.0f, 0.0f, 0.85f);
            scene.camera.target = glm::vec3(-0.08f, -0.06f, 0.0f);
            scene.camera.orthographicHalfHeight = 0.8f;
            scene.camera.nearPlane = 0.0f;
        }
        constexpr uint32_t kWidth = 96, kHeight = 96;
        RenderSettings settings = settingsOfSize(kWidth, kHeight);
        settings.debugView = DebugView::Gi;
        Renderer renderer(device(), scene, settings);
        const FrameReport report = renderer.renderFrame();
        EXPECT_EQ(countPasses(report, "gi-probes"), 1u) << test_support::passNames(report);
        const ImageRGBAF hdr = renderer.readHdrImage();
        const std::vector<IrradianceProbe> probes = renderer.readIrradianceProbes();
        expectNoMessages();
        ASSERT_EQ(probes.size(), 27u);
        for (const IrradianceProbe& probe : probes)
            ASSERT_EQ(probe.valid, glm::distance(probe.position, kBoxedProbe) > 1e-3f)
                << "only the boxed probe is invalid; probe at " << probe.position.x << " " << probe.position.y << " " << probe.position.z;

        const SceneView view = makeCameraView(scene.camera, kWidth, kHeight);
        const glm::dmat4 viewProjection = glm::dmat4(view.viewProjection());
        const glm::dmat4 inverse = glm::inverse(viewProjection);
        uint32_t checked = 0;
        bool invalidSeen = false;
        for (size_t i = 0; i < probes.size(); ++i) {
            const glm::dvec4 clip = viewProjection * glm::dvec4(glm::dvec3(probes[i].position), 1.0);
            if (clip.w <= 0.0) continue;
            const double px = (clip.x / clip.w * 0.5 + 0.5) * kWidth, py = (clip.y / clip.w * 0.5 + 0.5) * kHeight;   // row 0: NDC y = -1
            if (px < 1.0 || py < 1.0 || px >= kWidth - 1.0 || py >= kHeight - 1.0) continue;
            const uint32_t x = uint32_t(px), y = uint32_t(py);
            const float* pixel = &hdr.pixels[(size_t(y) * kWidth + x) * 4];
            const glm::dvec3 shown(pixel[0], pixel[1], pixel[2]);
            const std::string where = fmt::format("{} probe {} at pixel ({}, {}): shows ({:.4f}, {:.4f}, {:.4f})", GetParam().name(), i, x, y,
                                                  shown.r, shown.g, shown.b);
            if (!probes[i].valid) {
                // Drawn in front of everything: exactly the invalid colour.
                EXPECT_EQ(shown, glm::dvec3(1.0, 0.0, 1.0)) << where;
                invalidSeen = true;
                continue;
            }
            // The ray through the pixel's centre from the near plane to the far plane (from the eye's
            // side either way, as the fragment shader casts it).
            const glm::dvec2 ndc((x + 0.5) / kWidth * 2.0 - 1.0, (y + 0.5) / kHeight * 2.0 - 1.0);
            const glm::dvec4 near = inverse * glm::dvec4(ndc, 0.0, 1.0), far = inverse * glm::dvec4(ndc, 1.0, 1.0);
            const glm::dvec3 eye = glm::dvec3(near) / near.w;
            const glm::dvec3 direction = glm::normalize(glm::dvec3(far) / far.w - eye);
            const std::optional<double> t = hitSphere(eye, direction, glm::dvec3(probes[i].position), kRadius);
            if (!t) continue;   // the projected centre's pixel centre misses a tiny sphere: not this test's case
            // Only where this probe is what the pixel shows: no other sphere, and not the box, in front.
            bool hidden = rayHitsBox(eye, direction, glm::dvec3(kBoxedProbe - kBoxHalfSize), glm::dvec3(kBoxedProbe + kBoxHalfSize), *t);
            for (size_t j = 0; j < probes.size() && !hidden; ++j) {
                if (j == i) continue;
                const std::optional<double> other = hitSphere(eye, direction, glm::dvec3(probes[j].position), kRadius);
                hidden = other && (*other < *t || !probes[j].valid);
            }
            if (hidden) continue;
            const glm::dvec3 normal = glm::normalize(eye + direction * *t - glm::dvec3(probes[i].position));
            ShRgb sh{};
            for (size_t k = 0; k < 9; ++k) sh[k] = glm::dvec3(probes[i].sh[k]);
            const glm::dvec3 expected = shEvaluateIrradiance(sh, normal);
            // The GPU reads the same half-float coefficients; the result is stored as a half float
            // (2^-11 relative) and the shader's float ray gives a normal a few 1e-6 off: 0.3 % + 1e-3.
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(shown[c], expected[c], 3e-3 * expected[c] + 1e-3) << where << " channel " << c;
            // The walls' colours differ, so the probes do: a sphere of one flat colour would not pass.
            ++checked;
        }
        EXPECT_TRUE(invalidSeen) << GetParam().name() << ": the boxed probe must be in view";
        EXPECT_GE(checked, 6u) << GetParam().name() << ": too few valid probes in view to test";
        if (HasFailure())
            writePNG(test_support::outputDir() / fmt::format("gi-probe-view-{}{}.png", GetParam().name(), orthographic ? "-orthographic" : ""),
                     renderer.readDisplayImage());
    }
}

TEST_P(GiProbeViewTest, ThePassExistsOnlyInTheGiViewWithAVolume) {
    device().takeDebugMessages();
    Scene scene = loadScene(kCornellBox);
    scene.reflectionProbes.clear();
    scene.irradianceVolume->probeCounts = glm::uvec3(2);
    RenderSettings settings = settingsOfSize(32, 32);
    for (DebugView debugView : {DebugView::None, DebugView::Tiles, DebugView::Gi, DebugView::GiLight}) {
        settings.debugView = debugView;
        Renderer renderer(device(), scene, settings);
        const FrameReport report = renderer.renderFrame();
        EXPECT_EQ(countPasses(report, "gi-probes"), debugView == DebugView::Gi ? 1u : 0u)
            << GetParam().name() << " " << toString(debugView) << ": " << test_support::passNames(report);
    }
    scene.irradianceVolume.reset();
    settings.debugView = DebugView::Gi;
    Renderer renderer(device(), scene, settings);
    const FrameReport report = renderer.renderFrame();
    EXPECT_EQ(countPasses(report, "gi-probes"), 0u) << GetParam().name() << " without a volume: " << test_support::passNames(report);
    expectNoMessages();
}

INSTANTIATE_TEST_SUITE_P(Configs, GiProbeViewTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
