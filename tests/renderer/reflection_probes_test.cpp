// Reflection probes (docs/PROBES.md): the time-slicing plans (CPU), the probes of scene files and
// glTF markers, and on every configuration: parity of the built-in `probes` scene, updates that
// are shown only whole, update modes, what a capture leaves out, and hard cases that must stay
// finite.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <set>

#include <fmt/format.h>

#include "janus/renderer/renderer.h"
#include "probes/probe_update_plan.h"
#include "renderer/renderer_test_support.h"

namespace janus::renderer {
namespace {

namespace fs = std::filesystem;
using test_support::Config;

// ---- Time-slicing plans -------------------------------------------------------------------

// Every face captured exactly once, before any prefiltering; mips 0..N-1 prefiltered exactly once,
// in order; only the last step shows.
void expectCompletePlan(const std::vector<ProbeUpdateStep>& plan, uint32_t mips, const std::string& label) {
    ASSERT_FALSE(plan.empty()) << label;
    uint32_t faces = 0, nextMip = 0;
    for (size_t i = 0; i < plan.size(); ++i) {
        const ProbeUpdateStep& step = plan[i];
        EXPECT_EQ(faces & step.captureFaces, 0u) << label << " step " << i << " captures a face twice";
        faces |= step.captureFaces;
        if (step.firstMip < step.endMip) {
            EXPECT_EQ(faces, kAllCubeFaces) << label << " step " << i << " prefilters before every face is captured";
            EXPECT_EQ(step.firstMip, nextMip) << label << " step " << i;
            nextMip = step.endMip;
        }
        EXPECT_EQ(step.show, i + 1 == plan.size()) << label << " step " << i;
    }
    EXPECT_EQ(faces, kAllCubeFaces) << label;
    EXPECT_EQ(nextMip, mips) << label;
}

TEST(ProbeUpdatePlan, EachModeHasItsFrameCountAndCoversEveryFaceAndMipOnce) {
    const std::vector<double> costs = {0, 6 * 32 * 32 * 21, 6 * 16 * 16 * 34, 6 * 8 * 8 * 55, 6 * 4 * 4 * 89, 6 * 2 * 2 * 89, 6 * 89};
    const std::vector<ProbeUpdateStep> none = planProbeUpdate(ProbeTimeSlicing::None, costs);
    ASSERT_EQ(none.size(), 1u);
    EXPECT_EQ(none[0], (ProbeUpdateStep{kAllCubeFaces, 0, 7, true}));
    expectCompletePlan(none, 7, "none");

    const std::vector<ProbeUpdateStep> allFaces = planProbeUpdate(ProbeTimeSlicing::AllFacesThenMips, costs);
    ASSERT_EQ(allFaces.size(), 3u);
    EXPECT_EQ(allFaces[0].captureFaces, kAllCubeFaces);
    expectCompletePlan(allFaces, 7, "all faces then mips");

    const std::vector<ProbeUpdateStep> individual = planProbeUpdate(ProbeTimeSlicing::IndividualFaces, costs);
    ASSERT_EQ(individual.size(), 8u);
    for (uint32_t face = 0; face < 6; ++face) EXPECT_EQ(individual[face].captureFaces, 1u << face);
    expectCompletePlan(individual, 7, "individual faces");
}

TEST(ProbeUpdatePlan, TheTwoMipStepsSplitThePrefilterWorkEvenly) {
    // Mip 1 alone is 86016, mips 2..6 together 78568: the split after mip 1 is the most even.
    const std::vector<double> costs = {0, 6 * 32 * 32 * 14, 6 * 16 * 16 * 34, 6 * 8 * 8 * 55, 6 * 4 * 4 * 89, 6 * 2 * 2 * 89, 6 * 89};
    const std::vector<ProbeUpdateStep> plan = planProbeUpdate(ProbeTimeSlicing::AllFacesThenMips, costs);
    ASSERT_EQ(plan.size(), 3u);
    EXPECT_EQ(plan[1].endMip, 2u);
    // Equal costs per mip: three and three.
    const std::vector<ProbeUpdateStep> even = planProbeUpdate(ProbeTimeSlicing::AllFacesThenMips, {0, 1, 1, 1, 1, 1, 1});
    EXPECT_EQ(even[1].endMip, 4u);
    // A probe with a single level (nothing to prefilter) still copies its mip 0 and shows.
    expectCompletePlan(planProbeUpdate(ProbeTimeSlicing::IndividualFaces, {0}), 1, "one level");
}

// ---- Scenes -------------------------------------------------------------------------------

fs::path writeSceneFile(const std::string& name, const std::string& probesJson) {
    const fs::path dir = fs::temp_directory_path() / "janus-probe-scenes";
    fs::create_directories(dir);
    const fs::path path = dir / (name + ".json");
    std::ofstream(path) << fmt::format(R"({{ "gltf": "{}", "reflectionProbes": {} }})",
                                       (fs::path(JANUS_SHARED_SCENES_DIR) / "cornell-box" / "cornellBox.gltf").string(), probesJson);
    return path;
}

TEST(ReflectionProbeScenes, ASceneFileGivesEveryFieldAndReplacesTheMarkersProbe) {
    const Scene scene = loadScene(writeSceneFile("full", R"([{
        "name": "hall", "position": [0, 1, 0], "influence": {"min": [-1, 0, -1], "max": [1, 2, 1]}, "blendDistance": 0.3,
        "parallax": {"center": [0, 1.5, 0], "size": [4, 3, 4]}, "resolution": 64, "near": 0.1, "far": 20,
        "update": "on-request", "timeSlicing": "individual-faces", "shadows": false, "shadowMapSize": 256, "layers": 6,
        "samplesPerMip": [21, 34, 55], "brightTexels": 32, "msaa": 4, "seesProbes": true }, {"samplesPerMip": 8}])"));
    ASSERT_EQ(scene.reflectionProbes.size(), 2u);   // the cornell box's marker adds none: the file has probes
    const ReflectionProbe& p = scene.reflectionProbes[0];
    EXPECT_EQ(p.name, "hall");
    EXPECT_EQ(p.position, glm::vec3(0, 1, 0));
    EXPECT_EQ(p.influence, (Box{{-1, 0, -1}, {1, 2, 1}}));
    EXPECT_FLOAT_EQ(p.blendDistance, 0.3f);
    ASSERT_TRUE(p.parallax.has_value());
    EXPECT_EQ(*p.parallax, (Box{{-2, 0, -2}, {2, 3, 2}}));
    EXPECT_EQ(p.resolution, 64u);
    EXPECT_FLOAT_EQ(p.nearPlane, 0.1f);
    EXPECT_FLOAT_EQ(p.farPlane, 20.0f);
    EXPECT_EQ(p.update, ProbeUpdate::OnRequest);
    EXPECT_EQ(p.timeSlicing, ProbeTimeSlicing::IndividualFaces);
    EXPECT_FALSE(p.shadows);
    EXPECT_EQ(p.shadowMapSize, 256u);
    EXPECT_EQ(p.renderingLayers, 6u);
    EXPECT_EQ(p.samplesPerMip, (std::vector<uint32_t>{21, 34, 55}));
    EXPECT_EQ(p.brightTexels, 32u);
    EXPECT_EQ(p.msaaSamples, 4u);
    EXPECT_TRUE(p.seesProbes);
    // Defaults: the scene's bounds, at their centre, at infinity, once, all at once.
    const ReflectionProbe& d = scene.reflectionProbes[1];
    EXPECT_EQ(d.name, "probe 1");
    EXPECT_EQ(d.position, d.influence.center());
    EXPECT_FALSE(d.parallax.has_value());
    EXPECT_EQ(d.update, ProbeUpdate::Once);
    EXPECT_EQ(d.timeSlicing, ProbeTimeSlicing::None);
    EXPECT_EQ(d.samplesPerMip, std::vector<uint32_t>{8});   // one number: every mip
    EXPECT_EQ(d.brightTexels, 0u);
    EXPECT_EQ(d.msaaSamples, 1u);
    EXPECT_FALSE(d.seesProbes);
    EXPECT_GT(d.influence.size().x, 1.0f);
}

TEST(ReflectionProbeScenes, AReflectionCubemapMarkerPlacesAProbeCoveringTheScene) {
    const Scene scene = loadScene(fs::path(JANUS_SHARED_SCENES_DIR) / "cornell-box" / "cornellBox.gltf");
    ASSERT_EQ(scene.reflectionProbes.size(), 1u);
    const ReflectionProbe& probe = scene.reflectionProbes[0];
    EXPECT_EQ(probe.name, "ReflectionCubemap");
    EXPECT_NEAR(probe.position.y, 1.5f, 1e-5f);   // the marker's translation
    ASSERT_TRUE(probe.parallax.has_value());
    EXPECT_EQ(*probe.parallax, probe.influence);
    for (const Instance& instance : scene.instances)
        for (const Vertex& v : scene.meshes[instance.mesh].vertices) {
            const glm::vec3 p = glm::vec3(instance.world * glm::vec4(v.position, 1.0f));
            ASSERT_TRUE(glm::all(glm::greaterThanEqual(p, probe.influence.min)) && glm::all(glm::lessThanEqual(p, probe.influence.max)));
        }
}

TEST(ReflectionProbeScenes, BadProbesAreSceneErrorsNamingTheProblem) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {R"([{"resolution": 100}])", "power of two"},
        {R"([{"resolution": 2048}])", "power of two"},
        {R"([{"influence": {"min": [1, 0, 0], "max": [0, 1, 1]}}])", "above max"},
        {R"([{"influence": [0, 1]}])", "must be a box"},
        {R"([{"update": "sometimes"}])", "\"once\" | \"every-frame\" | \"on-request\""},
        {R"([{"timeSlicing": 3}])", "\"individual-faces\""},
        {R"([{"near": 5, "far": 1}])", "0 < near < far"},
        {R"([{"blendDistance": -1}])", "blend distance"},
        {R"([{"layers": -2}])", "layer mask"},
        {R"([{"shadowMapSize": 100}])", "shadow map size 100"},
        {R"([{"samplesPerMip": []}])", "samplesPerMip must be a sample count"},
        {R"([{"samplesPerMip": [34, -1]}])", "samplesPerMip must be a sample count"},
        {R"([{"samplesPerMip": [34, 0]}])", "0 GGX samples per mip"},
        {R"([{"samplesPerMip": 5000}])", "5000 GGX samples per mip"},
        {R"([{"brightTexels": 4096}])", "4096 bright texels"},
        {R"([{"brightTexels": true}])", "brightTexels must be 0 (off)"},
        {R"([{"msaa": 3}])", "msaa 3 must be 1 (off), 2, 4, 8 or 16"},
        {R"([{"msaa": 0}])", "msaa 0 must be"},
        {R"([{"msaa": 32}])", "msaa 32 must be"},
        {R"([{"msaa": "4"}])", "msaa must be the capture's samples per pixel"},
        {R"([{"msaa": true}])", "msaa must be the capture's samples per pixel"},
        {R"([{"seesProbes": 1}])", "seesProbes must be true or false"},
        {R"({"name": "x"})", "must be an array"},
    };
    for (size_t i = 0; i < cases.size(); ++i) {
        try {
            loadScene(writeSceneFile(fmt::format("bad{}", i), cases[i].first));
            ADD_FAILURE() << cases[i].first << " was accepted";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(cases[i].second), std::string::npos) << e.what();
        }
    }
    Scene scene = probesScene();
    scene.reflectionProbes[0].position.x = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(validateScene(scene), SceneError);
    // A zero-size box is valid (it reaches no surface); hard cases below render it.
    scene = probesScene();
    scene.reflectionProbes[0].influence = Box{glm::vec3(1.0f), glm::vec3(1.0f)};
    EXPECT_NO_THROW(validateScene(scene));
}

// ---- On every configuration ---------------------------------------------------------------

class ReflectionProbesTest : public test_support::ConfigTest {
protected:
    RenderSettings settings(uint32_t width = 128, uint32_t height = 96) const { return settingsOfSize(width, height); }
};

// Renders until every probe is shown (at most 16 frames); returns the last frame.
test_support::FrameOutput renderSettled(rhi::IDevice& device, const Scene& scene, const RenderSettings& settings) {
    test_support::FrameOutput output;
    Renderer renderer(device, scene, settings);
    for (int frame = 0; frame < 16; ++frame) {
        output.report = renderer.renderFrame();
        if (!renderer.probesPending()) break;
    }
    EXPECT_FALSE(renderer.probesPending());
    output.display = renderer.readDisplayImage();
    output.hdr = renderer.readHdrImage();
    return output;
}

TEST_P(ReflectionProbesTest, TheProbesSceneMatchesVulkanCompute) {
    device().takeDebugMessages();
    const Scene scene = probesScene();
    static const test_support::FrameOutput reference = renderSettled(test_support::deviceFor(rhi::Backend::Vulkan), scene, [] {
        RenderSettings s;
        s.width = 128, s.height = 96, s.path = FeaturePath::Compute;
        return s;
    }());
    const test_support::FrameOutput result = renderSettled(device(), scene, settings());
    expectNoMessages();
    test_support::expectFiniteHdr(result.hdr, GetParam().name());
    // A probe shown from a different update, a wrong face or a missing blend changes whole regions.
    test_support::expectMatchesVulkanCompute(reference.display, result.display, "probes", GetParam());
}

TEST_P(ReflectionProbesTest, ProbesChangeTheImageWhereTheyReachAndNowhereElse) {
    device().takeDebugMessages();
    const Scene withProbes = probesScene();
    Scene without = withProbes;
    without.reflectionProbes.clear();
    const test_support::FrameOutput a = renderSettled(device(), withProbes, settings());
    const test_support::FrameOutput b = renderSettled(device(), without, settings());
    expectNoMessages();
    // The chrome spheres inside the alcove reflect its walls instead of the sky; the sky above
    // the walls (no surface) is the same.
    const ImageDifference diff = compareImages(a.display, b.display, 1);
    EXPECT_GT(diff.differingPixels, 200u);
    const size_t topRow = 0;
    for (uint32_t x = 0; x < a.display.width; ++x)
        for (uint32_t c = 0; c < 3; ++c)
            EXPECT_EQ(a.display.pixels[(topRow * a.display.width + x) * 4 + c], b.display.pixels[(topRow * b.display.width + x) * 4 + c]);
}

// One probe, one face per frame: frames 1-7 show no probe (bit for bit the image without it),
// frame 8 shows it, and a requested second update shows nothing new until its own frame 8.
TEST_P(ReflectionProbesTest, AnUpdateIsShownOnlyWhenAllItsFacesAndMipsAreDone) {
    device().takeDebugMessages();
    Scene scene = probesScene();
    scene.reflectionProbes.resize(1);
    ReflectionProbe& probe = scene.reflectionProbes[0];
    probe.update = ProbeUpdate::Once;
    probe.timeSlicing = ProbeTimeSlicing::IndividualFaces;
    Scene without = scene;
    without.reflectionProbes.clear();
    const test_support::FrameOutput noProbe = renderSettled(device(), without, settings());

    Renderer renderer(device(), scene, settings());
    ImageRGBA8 shown;
    for (uint32_t frame = 1; frame <= 17; ++frame) {
        if (frame == 10) renderer.requestProbeUpdate(probe.name);
        const FrameReport report = renderer.renderFrame();
        const ImageRGBA8 image = renderer.readDisplayImage();
        const std::string label = fmt::format("{} frame {}", GetParam().name(), frame);
        if (frame == 9) {
            EXPECT_TRUE(report.probeUpdates.empty()) << label << ": a 'once' probe updated again";
            EXPECT_EQ(image.pixels, shown.pixels) << label;
            continue;
        }
        const uint32_t step = frame <= 8 ? frame : frame - 9;
        ASSERT_EQ(report.probeUpdates.size(), 1u) << label;
        const ProbeUpdateReport& update = report.probeUpdates[0];
        EXPECT_EQ(update.update, frame <= 8 ? 1u : 2u) << label;
        EXPECT_EQ(update.step, step) << label;
        EXPECT_EQ(update.steps, 8u) << label;
        EXPECT_EQ(update.shown, step == 8) << label;
        // Steps 1-6 render exactly face step - 1.
        std::set<std::string> faceViews;
        for (const ViewReport& view : report.views)
            if (view.name.rfind("probe ", 0) == 0) faceViews.insert(view.name);
        if (step <= 6)
            EXPECT_EQ(faceViews, std::set<std::string>{fmt::format("probe {} {}", probe.name, cubeFaceName(step - 1))}) << label;
        else
            EXPECT_TRUE(faceViews.empty()) << label;
        if (frame < 8) {
            EXPECT_EQ(image.pixels, noProbe.display.pixels) << label << ": a probe was sampled before its update was done";
            EXPECT_TRUE(renderer.probesPending()) << label;
        } else if (frame == 8) {
            EXPECT_NE(image.pixels, noProbe.display.pixels) << label << ": the finished probe is not shown";
            EXPECT_FALSE(renderer.probesPending()) << label;
            shown = image;
        } else {
            EXPECT_EQ(image.pixels, shown.pixels) << label << ": the second update changed what is shown before it was done";
        }
    }
    expectNoMessages();
    EXPECT_THROW(renderer.requestProbeUpdate("no such probe"), RendererError);
}

TEST_P(ReflectionProbesTest, EveryFrameProbesUpdateContinuouslyAndOnRequestProbesWait) {
    device().takeDebugMessages();
    Scene scene = probesScene();
    scene.reflectionProbes[0].update = ProbeUpdate::EveryFrame;
    scene.reflectionProbes[0].timeSlicing = ProbeTimeSlicing::AllFacesThenMips;
    scene.reflectionProbes[1].update = ProbeUpdate::OnRequest;
    Renderer renderer(device(), scene, settings(64, 48));
    std::vector<std::string> sequence;
    for (int frame = 0; frame < 7; ++frame) {
        if (frame == 4) renderer.requestProbeUpdate("right");
        for (const ProbeUpdateReport& u : renderer.renderFrame().probeUpdates)
            sequence.push_back(fmt::format("{}#{}:{}/{}{}", u.probe, u.update, u.step, u.steps, u.shown ? "!" : ""));
    }
    expectNoMessages();
    const std::vector<std::string> expected = {"left#1:1/3", "left#1:2/3", "left#1:3/3!", "left#2:1/3", "left#2:2/3", "right#1:1/1!",
                                               "left#2:3/3!", "left#3:1/3"};
    EXPECT_EQ(sequence, expected);
}

TEST_P(ReflectionProbesTest, ACaptureRunsOnlyThePassesItsProbeAsksFor) {
    device().takeDebugMessages();
    Scene scene = probesScene();
    scene.reflectionProbes.resize(1);
    scene.reflectionProbes[0].shadows = false;
    scene.reflectionProbes[0].renderingLayers = 2;   // sees only the spheres
    for (Instance& instance : scene.instances) instance.renderingLayers = scene.meshes[instance.mesh].vertices.size() > 100 ? 3u : 1u;
    Renderer renderer(device(), scene, settings(64, 48));
    const FrameReport report = renderer.renderFrame();
    expectNoMessages();
    uint32_t captureForward = 0, spheres = 0;
    for (const Instance& instance : scene.instances) spheres += (instance.renderingLayers & 2u) ? 1 : 0;
    for (const PassReport& pass : report.passes) {
        if (pass.view.rfind("probe ", 0) != 0) continue;
        EXPECT_NE(pass.name, "depth-prepass") << "captures do not cull lights by tiles";
        EXPECT_EQ(pass.name.find("tonemap"), std::string::npos);
        if (pass.name == "forward") {
            ++captureForward;
            EXPECT_EQ(pass.draws, spheres) << pass.view;
        }
    }
    EXPECT_EQ(captureForward, 6u);
    // Only the main frame renders the shadow map: the capture asked for none.
    EXPECT_EQ(std::count_if(report.passes.begin(), report.passes.end(), [](const PassReport& p) { return p.name == "shadow-map"; }), 1);
}

// A probe's shadow-map size reaches its capture: the renderer's size gives the very faces the
// default does, a 16^2 map gives other (blockier) shadows.
TEST_P(ReflectionProbesTest, ACaptureUsesItsOwnShadowMapSize) {
    device().takeDebugMessages();
    const Scene scene = probesScene();
    RenderSettings s = settings(64, 48);
    s.lighting.shadowMapSize = 512;
    Renderer renderer(device(), scene, s);
    // A map is drawn once per size and reused while the light stays (a static scene): the 512^2
    // map of the first capture serves the second.
    auto capture = [&](uint32_t shadowMapSize, int shadowPasses) {
        const rhi::TextureHandle cube = device().createTexture(rhi::TextureDesc{}
                                                                    .setDimension(rhi::TextureDimension::TextureCube)
                                                                    .setFormat(rhi::Format::RGBA16_FLOAT)
                                                                    .setSize(32, 32)
                                                                    .setUsage(rhi::TextureUsage::RenderTarget | rhi::TextureUsage::Sampled));
        CubeCaptureDesc desc;
        desc.position = glm::vec3(0.0f, 1.2f, 0.2f);
        desc.farPlane = 60.0f;
        desc.target = cube;
        desc.shadowMapSize = shadowMapSize;
        const FrameReport report = renderer.renderCubeCapture(desc);
        EXPECT_EQ(std::count_if(report.passes.begin(), report.passes.end(), [](const PassReport& p) { return p.name == "shadow-map"; }),
                  shadowPasses)
            << "map size " << shadowMapSize;
        std::vector<std::byte> faces;
        for (uint32_t face = 0; face < 6; ++face) {
            const std::vector<std::byte> bytes = device().readTexture(cube, {0, face});
            faces.insert(faces.end(), bytes.begin(), bytes.end());
        }
        return faces;
    };
    const std::vector<std::byte> byDefault = capture(0, 1), same = capture(512, 0), coarse = capture(16, 1);
    expectNoMessages();
    EXPECT_EQ(byDefault, same);
    EXPECT_NE(byDefault, coarse);
}

TEST_P(ReflectionProbesTest, HardCasesStayFinite) {
    device().takeDebugMessages();
    struct Case {
        const char* name;
        void (*edit)(Scene&);
    };
    const Case cases[] = {
        {"probe inside a sphere", [](Scene& s) { s.reflectionProbes[0].position = glm::vec3(-1.8f, 0.45f, -1.0f); }},
        {"zero-size influence box",
         [](Scene& s) { s.reflectionProbes[0].influence = Box{glm::vec3(0.0f, 0.45f, -1.0f), glm::vec3(0.0f, 0.45f, -1.0f)}; }},
        {"zero-size parallax box, no blend",
         [](Scene& s) {
             s.reflectionProbes[1].parallax = Box{glm::vec3(1.5f, 1.0f, -0.75f), glm::vec3(1.5f, 1.0f, -0.75f)};
             s.reflectionProbes[1].blendDistance = 0.0f;
         }},
        {"camera at a probe's centre",
         [](Scene& s) {
             s.camera.position = s.reflectionProbes[0].position;
             s.camera.target = s.camera.position + glm::vec3(0.3f, -0.5f, -1.0f);
         }},
        {"roughness 0 and 1",
         [](Scene& s) {
             for (Material& m : s.materials) m.roughnessFactor = (&m - s.materials.data()) % 2 == 0 ? 0.0f : 1.0f;
         }},
        {"a sun 1e5 times the sky", [](Scene& s) {
             auto sky = std::make_shared<ImageRGBAF>(*s.environment.image);
             sky->pixels[0] = sky->pixels[1] = sky->pixels[2] = 60000.0f;
             s.environment.image = sky;
         }},
    };
    for (const Case& c : cases) {
        Scene scene = probesScene();
        c.edit(scene);
        const test_support::FrameOutput output = renderSettled(device(), scene, settings(64, 48));
        test_support::expectFiniteHdr(output.hdr, fmt::format("{} {}", GetParam().name(), c.name));
    }
    expectNoMessages();
}

// A probe's prefilter settings reach its updates: the bright-texel split costs its 7 draws | 2
// dispatches and adds the sun exactly (the probe changes where it reflects the sky); fewer samples
// change the prefiltered mips, not the draw count.
TEST_P(ReflectionProbesTest, AProbesPrefilterSettingsReachItsUpdates) {
    device().takeDebugMessages();
    Scene scene = probesScene();
    scene.reflectionProbes.resize(1);
    scene.reflectionProbes[0].timeSlicing = ProbeTimeSlicing::None;   // the whole update in the first frame
    auto sky = std::make_shared<ImageRGBAF>(*scene.environment.image);
    for (uint32_t y = sky->height / 4; y < sky->height / 4 + 2; ++y)   // a sun 1e4 x the sky, above the horizon
        for (uint32_t x = sky->width / 3; x < sky->width / 3 + 2; ++x)
            for (uint32_t c = 0; c < 3; ++c) sky->pixels[(size_t(y) * sky->width + x) * 4 + c] = 5000.0f;
    scene.environment.image = sky;
    const bool compute = GetParam().path == FeaturePath::Compute;
    auto render = [&](uint32_t brightTexels, std::vector<uint32_t> samples) {
        Scene s = scene;
        s.reflectionProbes[0].brightTexels = brightTexels;
        s.reflectionProbes[0].samplesPerMip = std::move(samples);
        Renderer renderer(device(), s, settings(64, 48));
        const FrameReport report = renderer.renderFrame();
        EXPECT_EQ(report.probeUpdates.size(), 1u);
        if (report.probeUpdates.empty()) return ImageRGBA8{};
        const ProbeUpdateReport& update = report.probeUpdates[0];
        const std::string label = fmt::format("{} bright texels {}", GetParam().name(), brightTexels);
        EXPECT_TRUE(update.shown) << label;
        EXPECT_EQ(update.prefilterDraws, compute ? 0u : (brightTexels > 0 ? 43u : 36u)) << label;
        EXPECT_EQ(update.prefilterDispatches, compute ? (brightTexels > 0 ? 8u : 6u) : 0u) << label;
        const ImageRGBAF hdr = renderer.readHdrImage();
        test_support::expectFiniteHdr(hdr, label);
        return renderer.readDisplayImage();
    };
    const ImageRGBA8 plain = render(0, {}), split = render(64, {}), fewSamples = render(0, {4});
    expectNoMessages();
    EXPECT_GT(compareImages(plain, split, 0).differingPixels, 0u) << "the split did not change the probe";
    EXPECT_GT(compareImages(plain, fewSamples, 0).differingPixels, 0u) << "4 samples per mip gave the default's image";
}

// Multisampled captures (ReflectionProbe::msaaSamples, RenderSettings::probeMsaaSamples): a
// probe's own count reaches its updates and their capture views, the settings' count overrides
// every probe's, the mirror spheres' reflections change (their edges) and nothing the probes do
// not reach, and the image holds the parity rule against vulkan/compute with the same samples.
TEST_P(ReflectionProbesTest, MultisampledCapturesReachTheUpdatesAndKeepParity) {
    device().takeDebugMessages();
    Scene scene = probesScene();
    scene.reflectionProbes[0].msaaSamples = 4;   // its own; the other keeps 1
    auto samplesOf = [](const FrameReport& report) {
        std::map<std::string, uint32_t> samples;
        for (const ProbeUpdateReport& u : report.probeUpdates) samples[u.probe] = u.msaaSamples;
        for (const ViewReport& v : report.views)
            if (v.name.rfind("probe ", 0) == 0) samples[v.name] = v.sampleCount;
        return samples;
    };
    {
        Renderer renderer(device(), scene, settings(64, 48));
        const std::map<std::string, uint32_t> samples = samplesOf(renderer.renderFrame());
        const std::string own = scene.reflectionProbes[0].name, other = scene.reflectionProbes[1].name;
        EXPECT_EQ(samples.at(own), 4u);
        EXPECT_EQ(samples.at(other), 1u);
        EXPECT_EQ(samples.at(fmt::format("probe {} +X", own)), 4u);
        EXPECT_EQ(samples.at(fmt::format("probe {} +X", other)), 1u);
    }
    RenderSettings four = settings();
    four.probeMsaaSamples = 4;
    RenderSettings one = settings();
    one.probeMsaaSamples = 1;   // overrides the probe's own 4
    const test_support::FrameOutput a = renderSettled(device(), scene, four);
    const test_support::FrameOutput b = renderSettled(device(), scene, one);
    expectNoMessages();
    for (const auto& [name, count] : samplesOf(a.report)) EXPECT_EQ(count, 4u) << name;
    for (const auto& [name, count] : samplesOf(b.report)) EXPECT_EQ(count, 1u) << name;
    test_support::expectFiniteHdr(a.hdr, GetParam().name());
    // The chrome spheres reflect the alcove's edges; the sky above the walls stays.
    EXPECT_GT(compareImages(a.display, b.display, 0).differingPixels, 0u) << "4 samples gave the one-sample captures' image";
    for (uint32_t x = 0; x < a.display.width; ++x)
        for (uint32_t c = 0; c < 3; ++c) EXPECT_EQ(a.display.pixels[x * 4 + c], b.display.pixels[x * 4 + c]) << "top row, x " << x;
    static const test_support::FrameOutput reference = renderSettled(test_support::deviceFor(rhi::Backend::Vulkan), scene, [&] {
        RenderSettings s = four;
        s.path = FeaturePath::Compute;
        return s;
    }());
    test_support::expectMatchesVulkanCompute(reference.display, a.display, "probes-msaa", GetParam());
}

// Probes that see probes (ReflectionProbe::seesProbes): the every-frame "left" probe's captures
// shade their glossy ground and chrome spheres with the probes shown at the time (its own last
// update and "right"), so from its second update on the image differs from the one where it sees
// only the sky, and the difference is confined to where the left probe reaches; "right", updated
// once in the first frame before any probe was shown, sees none and changes nothing. Parity with
// vulkan/compute holds.
TEST_P(ReflectionProbesTest, AProbeThatSeesProbesCapturesTheirReflections) {
    device().takeDebugMessages();
    auto render = [&](bool leftSees, bool rightSees, uint32_t frames, rhi::IDevice& on, FeaturePath path) {
        Scene scene = probesScene();
        scene.reflectionProbes[0].seesProbes = leftSees;
        scene.reflectionProbes[1].seesProbes = rightSees;
        RenderSettings s = settings();
        s.path = path;
        Renderer renderer(on, scene, s);
        for (uint32_t frame = 1; frame < frames; ++frame) renderer.renderFrame();
        test_support::FrameOutput output;
        output.report = renderer.renderFrame();
        output.display = renderer.readDisplayImage();
        output.hdr = renderer.readHdrImage();
        return output;
    };
    // Frame 6: "left" has completed its second update (3 frames each), captured while the first was shown.
    const test_support::FrameOutput skyOnly = render(false, false, 6, device(), GetParam().path);
    const test_support::FrameOutput seeing = render(true, false, 6, device(), GetParam().path);
    const test_support::FrameOutput rightSeeing = render(false, true, 6, device(), GetParam().path);
    expectNoMessages();
    test_support::expectFiniteHdr(seeing.hdr, GetParam().name());
    const ImageDifference diff = compareImages(skyOnly.display, seeing.display, 1);
    EXPECT_GT(diff.differingPixels, 100u) << "the left probe's captures did not change when it saw the probes";
    EXPECT_EQ(compareImages(skyOnly.display, rightSeeing.display, 0).differingPixels, 0u)
        << "a probe whose only update ran before any probe was shown saw something";
    // The right third of the image is outside the left probe's influence (x > 0.5): unchanged.
    for (uint32_t y = 0; y < seeing.display.height; ++y)
        for (uint32_t x = seeing.display.width * 4 / 5; x < seeing.display.width; ++x)
            for (uint32_t c = 0; c < 3; ++c) {
                const size_t i = (size_t(y) * seeing.display.width + x) * 4 + c;
                ASSERT_EQ(seeing.display.pixels[i], skyOnly.display.pixels[i]) << "pixel (" << x << ", " << y << ")";
            }
    static const test_support::FrameOutput reference =
        render(true, false, 6, test_support::deviceFor(rhi::Backend::Vulkan), FeaturePath::Compute);
    test_support::expectMatchesVulkanCompute(reference.display, seeing.display, "probes-seeing-probes", GetParam());
}

// Feedback stays bounded: two every-frame probes that see probes, facing each other across
// mirror walls (metallic, roughness 0, base colour 1: every reflection keeps all its light), for
// 12 frames (12 bounces). Light is only passed on, never made, so no pixel exceeds the brightest the scene
// has without probes by more than rounding, and nothing turns NaN or infinite.
TEST_P(ReflectionProbesTest, ProbesThatSeeProbesStayBoundedBetweenMirrors) {
    device().takeDebugMessages();
    Scene scene = probesScene();
    for (Material& material : scene.materials) {
        if (material.name != "red wall" && material.name != "green wall" && material.name != "chrome") continue;
        material.baseColorFactor = glm::vec4(1.0f);
        material.metallicFactor = 1.0f;
        material.roughnessFactor = 0.0f;
    }
    Scene mirrors = scene;
    for (ReflectionProbe& probe : mirrors.reflectionProbes) {
        probe.seesProbes = true;
        probe.update = ProbeUpdate::EveryFrame;
        probe.timeSlicing = ProbeTimeSlicing::None;
    }
    auto brightest = [](const ImageRGBAF& image) {
        float most = 0.0f;
        for (size_t i = 0; i < image.pixels.size(); ++i)
            if (i % 4 != 3) most = std::max(most, image.pixels[i]);
        return most;
    };
    const float skyOnly = brightest(renderSettled(device(), scene, settings(64, 48)).hdr);
    Renderer renderer(device(), mirrors, settings(64, 48));
    for (int frame = 0; frame < 12; ++frame) renderer.renderFrame();
    const ImageRGBAF hdr = renderer.readHdrImage();
    expectNoMessages();
    test_support::expectFiniteHdr(hdr, GetParam().name());
    EXPECT_LE(brightest(hdr), skyOnly * 1.05f) << "reflections between the mirror walls gained light";
}

// A probe's count the device does not allow is a RendererError naming the probe when the renderer
// is made; so is a settings count that no probe could use.
TEST_P(ReflectionProbesTest, SampleCountsTheDeviceLacksAreRefusedNamingTheProbe) {
    const uint32_t allowed = device().formatCapabilities(rhi::Format::RGBA16_FLOAT).sampleCounts &
                             device().formatCapabilities(rhi::Format::D32_FLOAT).sampleCounts;
    auto message = [&](const Scene& scene, const RenderSettings& s) -> std::string {
        try {
            Renderer renderer(device(), scene, s);
        } catch (const RendererError& e) {
            return e.what();
        }
        return "(no error)";
    };
    const std::string backend = rhi::toString(GetParam().backend);
    RenderSettings odd = settings(64, 48);
    odd.probeMsaaSamples = 3;
    EXPECT_NE(message(probesScene(), odd).find(fmt::format("probe msaa 3 is not possible on this {} device", backend)), std::string::npos)
        << message(probesScene(), odd);
    size_t lacking = 0;
    for (uint32_t samples : {2u, 8u, 16u}) {
        if (allowed & samples) continue;
        ++lacking;
        Scene scene = probesScene();
        scene.reflectionProbes[1].msaaSamples = samples;
        const std::string text = message(scene, settings(64, 48));
        EXPECT_NE(text.find(fmt::format("reflection probe '{}': msaa {} is not possible on this {} device", scene.reflectionProbes[1].name,
                                        samples, backend)),
                  std::string::npos)
            << text;
    }
    RecordProperty("countsTheDeviceLacks", int(lacking));
    device().takeDebugMessages();
}

TEST_P(ReflectionProbesTest, WithoutCubeArraysTwoProbesAreShownAndTheRestLeftOut) {
    device().takeDebugMessages();
    Scene scene = probesScene();
    ReflectionProbe far = scene.reflectionProbes[1];
    far.name = "far away";
    far.position = glm::vec3(0.0f, 1.0f, -40.0f);
    far.influence = Box{glm::vec3(-2.0f, 0.0f, -42.0f), glm::vec3(2.0f, 2.0f, -38.0f)};
    scene.reflectionProbes.push_back(far);
    Renderer renderer(device(), scene, settings(64, 48));
    std::set<std::string> updated;
    for (const ProbeUpdateReport& u : renderer.renderFrame().probeUpdates) updated.insert(u.probe);
    expectNoMessages();
    if (device().capabilities().cubeArrays)
        EXPECT_EQ(updated, (std::set<std::string>{"left", "right", "far away"}));
    else
        EXPECT_EQ(updated, (std::set<std::string>{"left", "right"}));   // the farthest from the camera is left out
}

INSTANTIATE_TEST_SUITE_P(Configs, ReflectionProbesTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
