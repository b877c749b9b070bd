#include "probes/reflection_probes.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "core/gpu_util.h"
#include "janus/shaders/bindings.h"
#include "msaa/sample_count.h"

namespace janus::renderer {
namespace {

// std140 mirror of probe_access.glsl's ReflectionProbeUniforms (the larger, cube-array size;
// the two-cube variant reads the first two entries).
struct ProbeShadingData {
    glm::vec4 influenceMin, influenceMax, parallaxMin, parallaxMax, position;
};
struct ReflectionProbeUniforms {
    glm::ivec4 count;
    ProbeShadingData probes[ReflectionProbes::kMaxShownWithCubeArrays];
};
static_assert(sizeof(ReflectionProbeUniforms) == 16 + 80 * ReflectionProbes::kMaxShownWithCubeArrays, "must match std140");

// Distance from p to the box (0 inside).
float distanceToBox(const glm::vec3& p, const Box& box) { return glm::length(glm::max(glm::max(box.min - p, p - box.max), glm::vec3(0.0f))); }
float volume(const Box& box) {
    const glm::vec3 size = box.size();
    return size.x * size.y * size.z;
}
uint32_t log2u(uint32_t v) {
    uint32_t n = 0;
    while (v > 1) v >>= 1, ++n;
    return n;
}

}  // namespace

CubeCaptureDesc cubeCaptureOf(const ReflectionProbe& probe) {
    CubeCaptureDesc capture;
    capture.position = probe.position;
    capture.nearPlane = probe.nearPlane;
    capture.farPlane = probe.farPlane;
    capture.shadows = probe.shadows;
    capture.shadowMapSize = probe.shadowMapSize;
    capture.renderingLayers = probe.renderingLayers;
    capture.msaaSamples = probe.msaaSamples;
    capture.reflectionProbes = probe.seesProbes;
    return capture;
}

ReflectionProbes::ReflectionProbes(rhi::IDevice& device, const Scene& scene, FeaturePath path, const glm::vec3& cameraPosition,
                                   uint32_t msaaSamples, CaptureFunction capture)
    : m_device(device), m_path(path), m_capture(std::move(capture)) {
    m_cubeArrays = device.capabilities().cubeArrays;
    // Which probes the main view shows: all, or the nearest to the camera that fit.
    std::vector<size_t> order(scene.reflectionProbes.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        return distanceToBox(cameraPosition, scene.reflectionProbes[a].influence) <
               distanceToBox(cameraPosition, scene.reflectionProbes[b].influence);
    });
    const size_t capacity = m_cubeArrays ? kMaxShownWithCubeArrays : kMaxShownWithoutCubeArrays;
    if (order.size() > capacity) {
        std::string leftOut;
        for (size_t i = capacity; i < order.size(); ++i) leftOut += fmt::format("{}'{}'", leftOut.empty() ? "" : ", ", scene.reflectionProbes[order[i]].name);
        fmt::print(stderr, "janus renderer: warning: this {} device shows at most {} reflection probes per view{}; left out (farthest from the camera): {}\n",
                   rhi::toString(device.info().backend), capacity, m_cubeArrays ? "" : " (it has no cube arrays)", leftOut);
        order.resize(capacity);
    }
    // Blend order: the most local probe (smallest influence) first; ties keep the scene's order.
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        return volume(scene.reflectionProbes[a].influence) < volume(scene.reflectionProbes[b].influence);
    });
    // Views without probes (captures; every view when there are none) bind the stand-ins: probeCount 0
    // keeps the cubes unread.
    m_sampler = device.createSampler(rhi::SamplerDesc{}.setFilter(rhi::Filter::Linear).setAddress(rhi::AddressMode::ClampToEdge));
    m_standInUniforms = makeUniformBuffer(device, ReflectionProbeUniforms{}, "no reflection probes");
    if (order.empty()) {
        m_standInCube = device.createTexture(rhi::TextureDesc{}
                                                 .setDimension(m_cubeArrays ? rhi::TextureDimension::TextureCubeArray
                                                                            : rhi::TextureDimension::TextureCube)
                                                 .setFormat(rhi::Format::RGBA16_FLOAT)
                                                 .setArrayLayers(m_cubeArrays ? 6 : 1)
                                                 .setUsage(rhi::TextureUsage::Sampled)
                                                 .setDebugName("no reflection probes"));
        return;
    }

    uint32_t largest = 0;
    for (size_t index : order) largest = std::max(largest, scene.reflectionProbes[index].resolution);
    for (size_t index : order) {
        Probe probe;
        probe.desc = scene.reflectionProbes[index];
        if (msaaSamples != 0) probe.desc.msaaSamples = msaaSamples;
        requireSampleCount(device, probe.desc.msaaSamples, kCaptureFormat, kCaptureDepthFormat,
                           fmt::format("reflection probe '{}': msaa", probe.desc.name));
        probe.slot = uint32_t(m_probes.size());
        probe.baseMip = m_cubeArrays ? log2u(largest / probe.desc.resolution) : 0;
        probe.capture = device.createTexture(rhi::TextureDesc{}
                                                 .setDimension(rhi::TextureDimension::TextureCube)
                                                 .setFormat(kCaptureFormat)
                                                 .setSize(probe.desc.resolution, probe.desc.resolution)
                                                 .setMipLevels(0)
                                                 .setUsage(rhi::TextureUsage::RenderTarget | rhi::TextureUsage::Sampled)
                                                 .setDebugName(fmt::format("probe '{}' capture", probe.desc.name)));
        GgxPrefilterSettings settings;
        settings.mipCount = std::min(kPrefilteredMips, rhi::fullMipCount(probe.desc.resolution, probe.desc.resolution));
        settings.debugName = fmt::format("probe '{}' staging", probe.desc.name);
        if (!probe.desc.samplesPerMip.empty()) settings.samplesPerMip = probe.desc.samplesPerMip;
        settings.brightTexels = probe.desc.brightTexels;
        probe.prefilter = std::make_unique<GgxPrefilter>(device, path, settings);
        probe.prefilter->prepare(probe.capture);
        std::vector<double> costs(probe.prefilter->mipCount());
        for (uint32_t mip = 0; mip < costs.size(); ++mip) costs[mip] = probe.prefilter->mipCost(mip);
        probe.plan = planProbeUpdate(probe.desc.timeSlicing, costs);
        m_probes.push_back(std::move(probe));
    }
    createShownTextures();
    m_uniforms = device.createBuffer(
        rhi::BufferDesc{}.setSize(sizeof(ReflectionProbeUniforms)).setUsage(rhi::BufferUsage::Uniform).setDebugName("reflection probes"));
    const ReflectionProbeUniforms none{};
    device.writeBuffer(m_uniforms, &none, sizeof(none));
    m_commandList = device.createCommandList();
}

void ReflectionProbes::createShownTextures() {
    const rhi::TextureUsage usage = rhi::TextureUsage::Sampled | rhi::TextureUsage::RenderTarget;   // copy destination
    if (!m_cubeArrays) {
        for (Probe& probe : m_probes)
            probe.shownCube = m_device.createTexture(rhi::TextureDesc{}
                                                         .setDimension(rhi::TextureDimension::TextureCube)
                                                         .setFormat(rhi::Format::RGBA16_FLOAT)
                                                         .setSize(probe.desc.resolution, probe.desc.resolution)
                                                         .setMipLevels(probe.prefilter->mipCount())
                                                         .setUsage(usage)
                                                         .setDebugName(fmt::format("probe '{}'", probe.desc.name)));
        return;
    }
    uint32_t largest = 0, levels = 1;
    for (const Probe& probe : m_probes) {
        largest = std::max(largest, probe.desc.resolution);
        levels = std::max(levels, probe.baseMip + probe.prefilter->mipCount());
    }
    m_shownArray = m_device.createTexture(rhi::TextureDesc{}
                                              .setDimension(rhi::TextureDimension::TextureCubeArray)
                                              .setFormat(rhi::Format::RGBA16_FLOAT)
                                              .setSize(largest, largest)
                                              .setArrayLayers(uint32_t(6 * m_probes.size()))
                                              .setMipLevels(levels)
                                              .setUsage(usage)
                                              .setDebugName("reflection probes"));
}

void ReflectionProbes::addPasses(PassGraph& graph, const SceneView& view) {
    if (!active() || !view.passes.reflectionProbes || graph.find("", probe_resources::kReflectionProbes)) return;
    const PassGraph::ResourceId probes = graph.importResource(probe_resources::kReflectionProbes);
    graph.publish("", probe_resources::kReflectionProbes, ViewTarget{probes, m_shownArray, {}});
}

void ReflectionProbes::addViewBindings(rhi::BindingSetDesc& set, const SceneView& view) const {
    const bool shows = active() && view.passes.reflectionProbes;
    set.add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_REFLECTION_PROBES, shows ? m_uniforms : m_standInUniforms));
    if (m_cubeArrays) {
        set.add(rhi::BindingItem::sampledTexture(JANUS_BINDING_PROBE_CUBES, active() ? m_shownArray : m_standInCube, m_sampler));
        return;
    }
    for (uint32_t slot = 0; slot < kMaxShownWithoutCubeArrays; ++slot) {
        const rhi::TextureHandle& cube = slot < m_probes.size() ? m_probes[slot].shownCube : m_probes.empty() ? m_standInCube : m_probes[0].shownCube;
        set.add(rhi::BindingItem::sampledTexture(slot == 0 ? JANUS_BINDING_PROBE_CUBES : JANUS_BINDING_PROBE_CUBE_1, cube, m_sampler));
    }
}

void ReflectionProbes::requestUpdate(std::string_view probeName) {
    bool found = false;
    for (Probe& probe : m_probes)
        if (probeName.empty() || probe.desc.name == probeName) probe.requested = true, found = true;
    if (!found && !probeName.empty())
        throw RendererError(fmt::format("requestProbeUpdate: the scene has no reflection probe named '{}' that the main view shows", probeName));
}

bool ReflectionProbes::pending() const {
    return std::any_of(m_probes.begin(), m_probes.end(), [this](const Probe& p) { return !p.shown && (p.step >= 0 || due(p)); });
}

bool ReflectionProbes::due(const Probe& probe) const {
    if (probe.requested) return true;
    switch (probe.desc.update) {
        case ProbeUpdate::Once: return probe.updates == 0;
        case ProbeUpdate::EveryFrame: return true;
        case ProbeUpdate::OnRequest: return false;
    }
    return false;
}

void ReflectionProbes::beginFrame(FrameReport& frame) {
    for (Probe& probe : m_probes) {
        if (probe.step < 0) {
            if (!due(probe)) continue;
            probe.requested = false;
            probe.step = 0;
            ++probe.updates;
            probe.report = ProbeUpdateReport{};
            probe.report.probe = probe.desc.name;
            probe.report.update = probe.updates;
            probe.report.steps = uint32_t(probe.plan.size());
            probe.report.msaaSamples = probe.desc.msaaSamples;
        }
        runStep(probe, frame);
    }
}

void ReflectionProbes::runStep(Probe& probe, FrameReport& frame) {
    const ProbeUpdateStep& step = probe.plan[size_t(probe.step)];
    ProbeUpdateReport& update = probe.report;
    update.step = uint32_t(probe.step) + 1;
    update.draws = update.dispatches = 0;
    update.gpuMs.reset();
    const std::string view = fmt::format("probe {}", probe.desc.name);
    auto account = [&](const PassReport& pass) {
        update.draws += pass.draws;
        update.dispatches += pass.dispatches;
        if (pass.gpuMs) update.gpuMs = update.gpuMs.value_or(0.0) + *pass.gpuMs;
        frame.passes.push_back(pass);
    };

    if (step.captureFaces != 0) {
        CubeCaptureDesc capture = cubeCaptureOf(probe.desc);
        capture.target = probe.capture;
        capture.faces = step.captureFaces;
        capture.viewPrefix = view;
        FrameReport captured = m_capture(capture);
        for (const PassReport& pass : captured.passes) account(pass);
        for (const ViewReport& v : captured.views) frame.views.push_back(v);
    }

    PassGraph graph;
    const PassGraph::ResourceId staging = graph.addResource(fmt::format("probe '{}' staging", probe.desc.name));
    if (step.firstMip < step.endMip) {
        PassGraph::PassDesc prefilter;
        prefilter.name = m_path == FeaturePath::Compute ? "probe-prefilter-compute" : "probe-prefilter-fallback";
        prefilter.view = view;
        prefilter.writes = {staging};
        prefilter.sideEffect = true;
        prefilter.record = [&probe, step](rhi::ICommandList& cmd, PassReport& report) {
            probe.prefilter->recordMips(cmd, report, step.firstMip, step.endMip);
        };
        graph.addPass(std::move(prefilter));
    }
    if (step.show) {
        PassGraph::PassDesc show;
        show.name = "probe-show";
        show.view = view;
        show.writes = {staging};
        show.sideEffect = true;
        show.record = [this, &probe](rhi::ICommandList& cmd, PassReport&) {
            // Every face and mip of this update at once, then the probe is listed: shading never
            // reads a mix of two updates.
            const rhi::TextureHandle& source = probe.prefilter->prefiltered();
            const rhi::TextureHandle& shown = m_cubeArrays ? m_shownArray : probe.shownCube;
            const uint32_t cube = m_cubeArrays ? probe.slot : 0;
            for (uint32_t mip = 0; mip < probe.prefilter->mipCount(); ++mip)
                for (uint32_t face = 0; face < 6; ++face) cmd.copyTexture(shown, {probe.baseMip + mip, cube * 6 + face}, source, {mip, face});
            probe.report.copies = probe.prefilter->mipCount() * 6;
            probe.shown = true;
            writeUniforms(cmd);
        };
        graph.addPass(std::move(show));
    }
    graph.compile(m_device);
    for (const PassReport& pass : graph.execute(m_device, m_commandList)) {
        account(pass);
        update.prefilterDraws += pass.name == "probe-show" ? 0 : pass.draws;
        update.prefilterDispatches += pass.name == "probe-show" ? 0 : pass.dispatches;
    }
    update.updateDraws += update.draws;
    update.updateDispatches += update.dispatches;
    update.shown = step.show;
    frame.probeUpdates.push_back(update);
    probe.step = step.show ? -1 : probe.step + 1;
}

void ReflectionProbes::writeUniforms(rhi::ICommandList& cmd) {
    ReflectionProbeUniforms uniforms{};
    int count = 0;
    for (const Probe& probe : m_probes) {
        if (!probe.shown) continue;
        const ReflectionProbe& p = probe.desc;
        const Box parallax = p.parallax.value_or(p.influence);
        ProbeShadingData& d = uniforms.probes[count++];
        d.influenceMin = glm::vec4(p.influence.min, p.blendDistance);
        d.influenceMax = glm::vec4(p.influence.max, p.parallax ? 1.0f : 0.0f);
        d.parallaxMin = glm::vec4(parallax.min, float(probe.baseMip));
        d.parallaxMax = glm::vec4(parallax.max, float(probe.baseMip + probe.prefilter->mipCount() - 1));
        d.position = glm::vec4(p.position, float(probe.slot));
    }
    uniforms.count = glm::ivec4(count, 0, 0, 0);
    cmd.writeBuffer(m_uniforms, &uniforms, sizeof(uniforms));
}

}  // namespace janus::renderer
