// janus_bench_renderer: what the renderer's CPU spends recording a frame of many mesh draws, per
// draw, on each backend. A grid of boxes (kMaterials materials, one directional light with a
// shadow map, 16 point lights) is rendered frame after frame; each frame's report gives the recording time of its
// mesh passes (shadow map, depth prepass, forward), and the benchmark reports them per draw.
// What the GPU (lavapipe / llvmpipe: the CPU) does with the frame is not timed.
//
// JANUS_BENCH_VALIDATE=1 runs with validation layers / GL debug output and fails on any message
// (tests/bench/renderer_smoke.sh); --janus_instances=N changes the grid (default 1024),
// --janus_frames=N runs N timed frames per repetition (default 30).
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "janus/renderer/renderer.h"
#include "janus/rhi/rhi.h"

namespace {

using namespace janus;

constexpr uint32_t kMaterials = 8;
uint32_t g_instances = 1024;
// --janus_frames=N: timed frames per repetition. Fixed, as Google Benchmark would pick the count
// from the recording time alone (well under a millisecond a frame) and run for minutes: each
// frame also executes on llvmpipe / lavapipe, which is untimed and a thousand times longer.
uint32_t g_frames = 30;

bool validationRequested() {
    const char* value = std::getenv("JANUS_BENCH_VALIDATE");
    return value && std::string_view(value) == "1";
}

// A -1..1 box, faces outwards, one material.
renderer::Mesh boxMesh(int32_t material) {
    renderer::Mesh mesh;
    mesh.material = material;
    const glm::vec3 normals[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const glm::vec3& n : normals) {
        // Two axes spanning the face, u x v = n, so the face winds counter-clockwise seen from outside.
        const glm::vec3 u = std::abs(n.y) > 0.5f ? glm::vec3(0, 0, n.y) : glm::vec3(-n.z, 0, n.x);
        const glm::vec3 v = glm::cross(n, u);
        const uint32_t base = uint32_t(mesh.vertices.size());
        const glm::vec2 corners[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        for (const glm::vec2& c : corners) {
            renderer::Vertex vertex;
            vertex.position = n + u * c.x + v * c.y;
            vertex.normal = n;
            vertex.uv = c * 0.5f + 0.5f;
            mesh.vertices.push_back(vertex);
        }
        for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.indices.push_back(base + i);
    }
    return mesh;
}

// kMaterials meshes (a mesh has one material), instances on a square grid over a ground box.
renderer::Scene gridScene(uint32_t instances) {
    renderer::Scene scene;
    scene.name = "renderer bench grid";
    for (uint32_t m = 0; m < kMaterials; ++m) {
        renderer::Material material;
        material.baseColorFactor = glm::vec4(0.2f + 0.1f * float(m), 0.8f - 0.08f * float(m), 0.5f, 1.0f);
        material.metallicFactor = 0.0f;
        material.roughnessFactor = 0.3f + 0.08f * float(m);
        scene.materials.push_back(material);
        scene.meshes.push_back(boxMesh(int32_t(m)));
    }
    const uint32_t side = uint32_t(std::ceil(std::sqrt(double(instances))));
    const float spacing = 2.5f;
    const float half = 0.5f * spacing * float(side - 1);
    for (uint32_t i = 0; i < instances; ++i) {
        renderer::Instance instance;
        instance.mesh = i % kMaterials;
        const glm::vec3 position(float(i % side) * spacing - half, 1.0f, float(i / side) * spacing - half);
        instance.world = glm::translate(glm::mat4(1.0f), position) * glm::scale(glm::mat4(1.0f), glm::vec3(0.8f));
        scene.instances.push_back(instance);
    }
    renderer::Instance ground;
    ground.mesh = 0;
    ground.world = glm::scale(glm::mat4(1.0f), glm::vec3(half + 2.0f, 0.05f, half + 2.0f));
    scene.instances.push_back(ground);
    renderer::Light sun;
    sun.direction = glm::normalize(glm::vec3(-0.4f, -1.0f, -0.3f));
    sun.intensity = 3.0f;
    scene.lights.push_back(sun);
    // Local lights: tiled culling, so the frame has its depth prepass too.
    for (uint32_t i = 0; i < 16; ++i) {
        renderer::Light light;
        light.type = renderer::LightType::Point;
        const float angle = float(i) * 0.3927f;
        light.position = glm::vec3(std::cos(angle) * half * 0.7f, 3.0f, std::sin(angle) * half * 0.7f);
        light.color = glm::vec3(1.0f, 0.6f + 0.02f * float(i), 0.4f);
        light.intensity = 20.0f;
        light.range = 3.0f * spacing;
        scene.lights.push_back(light);
    }
    scene.camera.position = glm::vec3(0.0f, half * 1.2f + 4.0f, half * 1.5f + 4.0f);
    scene.camera.target = glm::vec3(0.0f);
    scene.camera.farPlane = 4.0f * (half + 10.0f);
    return scene;
}

struct Measured {
    double seconds = 0.0;
    uint64_t draws = 0;
};

void recordScene(benchmark::State& state, rhi::Backend backend, renderer::FeaturePath path) {
    const std::unique_ptr<rhi::IDevice> device =
        rhi::createDevice(rhi::DeviceDesc{}.setBackend(backend).setEnableValidation(validationRequested()));
    const renderer::Scene scene = gridScene(g_instances);
    renderer::RenderSettings settings;
    settings.width = settings.height = 128;
    settings.path = path;
    renderer::Renderer renderer(*device, scene, settings);
    renderer.renderFrame();   // first use: pipelines, uploads, caches
    // A static scene draws its shadow map once (docs/SHADOWS.md): the sun turns a little between
    // frames, so every frame draws it and its recording is measured.
    const std::optional<size_t> sun = renderer::mainDirectionalLight(scene);
    if (!sun) throw std::runtime_error("the bench scene has no main light");
    std::vector<renderer::Light> lights[2] = {scene.lights, scene.lights};
    lights[1][*sun].direction = glm::normalize(lights[1][*sun].direction + glm::vec3(0.01f, 0.0f, 0.0f));
    const char* meshPasses[] = {"shadow-map", "depth-prepass", "forward"};
    Measured measured[3];
    size_t frame = 0;
    for (auto _ : state) {
        renderer.setLights(lights[++frame % 2]);
        const renderer::FrameReport report = renderer.renderFrame();
        double seconds = 0.0;
        for (const renderer::PassReport& pass : report.passes)
            for (int p = 0; p < 3; ++p)
                if (pass.name == meshPasses[p]) {
                    if (pass.draws != scene.instances.size())
                        throw std::runtime_error(fmt::format("{}: {} draws, not one per instance ({})", pass.name, pass.draws,
                                                             scene.instances.size()));
                    measured[p].seconds += pass.cpuMs * 1e-3;
                    measured[p].draws += pass.draws;
                    seconds += pass.cpuMs * 1e-3;
                }
        state.SetIterationTime(seconds);
    }
    for (int p = 0; p < 3; ++p)
        if (measured[p].draws == 0) throw std::runtime_error(fmt::format("no '{}' pass ran", meshPasses[p]));
    state.counters["shadow_ns_per_draw"] = measured[0].seconds * 1e9 / double(measured[0].draws);
    state.counters["prepass_ns_per_draw"] = measured[1].seconds * 1e9 / double(measured[1].draws);
    state.counters["forward_ns_per_draw"] = measured[2].seconds * 1e9 / double(measured[2].draws);
    state.counters["draws_per_pass"] = double(scene.instances.size());
    if (validationRequested()) {
        const std::vector<rhi::DebugMessage> messages = device->takeDebugMessages();
        if (!messages.empty()) throw std::runtime_error(fmt::format("{} validation messages, first: {}", messages.size(), messages[0].text));
    }
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<char*> args;
    // Our own flags, each a count in 1..most.
    auto countFlag = [](std::string_view arg, std::string_view flag, uint32_t most, uint32_t& value) {
        if (!arg.starts_with(flag)) return false;
        const unsigned long parsed = std::strtoul(std::string(arg.substr(flag.size())).c_str(), nullptr, 10);
        if (parsed == 0 || parsed > most) {
            std::fprintf(stderr, "%.*s: give a count in 1..%u\n", int(flag.size() - 1), flag.data(), most);
            std::exit(2);
        }
        value = uint32_t(parsed);
        return true;
    };
    for (int i = 0; i < argc; ++i)
        if (!countFlag(argv[i], "--janus_instances=", 65536, g_instances) && !countFlag(argv[i], "--janus_frames=", 100000, g_frames))
            args.push_back(argv[i]);
    struct Config {
        const char* name;
        rhi::Backend backend;
        renderer::FeaturePath path;
    };
    const Config configs[] = {{"vulkan/compute", rhi::Backend::Vulkan, renderer::FeaturePath::Compute},
                              {"gl/compute", rhi::Backend::GL, renderer::FeaturePath::Compute},
                              {"gles/fallback", rhi::Backend::GLES, renderer::FeaturePath::Fallback}};
    for (const Config& config : configs) {
        auto run = [config](benchmark::State& state) {
            // A failure is the run's error, which the smoke test reads.
            try {
                recordScene(state, config.backend, config.path);
            } catch (const std::exception& error) {
                state.SkipWithError(error.what());
            }
        };
        benchmark::internal::Benchmark* registered =
            benchmark::RegisterBenchmark(fmt::format("record_scene/{}", config.name).c_str(), run);
        registered->UseManualTime()->Unit(benchmark::kMicrosecond)->Iterations(g_frames);
    }
    int count = int(args.size());
    benchmark::Initialize(&count, args.data());
    if (benchmark::ReportUnrecognizedArguments(count, args.data())) return 2;
    benchmark::AddCustomContext("instances", std::to_string(g_instances));
    benchmark::AddCustomContext("validation", validationRequested() ? "on" : "off");
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
