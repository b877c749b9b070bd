// Renderer: uploads a Scene once, then records one frame per renderFrame() from a plan of the
// passes the scene needs (docs/ARCHITECTURE.md, "Data flow of a frame"):
//   shadow-map     (main directional light, when there is one and shadows are on)
//   depth-prepass  (tiled light culling only) meshes -> D32F depth
//   light-cull-*   (tiled only) compute: light_cull.comp | fallback: CPU builder -> tile lists
//   forward        meshes -> RGBA16F HDR radiance (+ depth, or tested against the prepass depth)
//   tonemap        (compute: storage-image dispatch | fallback: fullscreen triangle) HDR -> RGBA8 display
//   tile-heatmap   (DebugView::Tiles) lights per tile blended over the display image
// Both tonemap paths include shaders/renderer/tonemap_common.glsl, so they compute the same bits.
// This file: construction (the order the pieces are made in), the frame plan, renderFrame, the
// readbacks and the public Renderer. Renderer::Impl is declared in renderer_impl.h; its other
// methods live by topic in renderer_settings.cpp, renderer_resources.cpp, renderer_lights.cpp,
// renderer_shadows.cpp and renderer_passes.cpp.
#include "janus/renderer/renderer.h"

#include <chrono>
#include <cstddef>
#include <cstring>

#include <fmt/format.h>
#include <glm/gtc/packing.hpp>

#include "renderer_impl.h"

namespace janus::renderer {

Renderer::Impl::Impl(rhi::IDevice& d, const Scene& scene, const RenderSettings& s) : device(d), settings(s) {
    validateScene(scene);
    checkSettings();
    resolveLighting(scene);
    packLights(scene);
    chooseCulling();
    createTargets();
    uploadTextures(scene);
    uploadMeshes(scene);
    createShadows(scene);
    createLightArrays();
    createForward(scene);
    createCulling();
    createTonemap(scene);
    createHeatmap();
    commandList = device.createCommandList();
    planFrame();
}

// A frame that threw half-way (e.g. in the CPU step between its submissions) may leave work
// in flight that uses the resources about to be destroyed: wait for it first.
Renderer::Impl::~Impl() {
    try {
        device.waitIdle();
    } catch (const std::exception& e) {
        fmt::print(stderr, "janus renderer: warning: waiting for the GPU before teardown failed: {}\n", e.what());
    }
}

// The passes this scene needs, in order. Every frame produces HDR radiance and a display
// image, so forward and tonemap are always there; the rest join only when the scene has
// what they work on.
void Renderer::Impl::planFrame() {
    if (shadowMap) plan.push_back({"shadow-map", &Impl::recordShadowMap, nullptr, nullptr});
    if (tiled()) {
        plan.push_back({"depth-prepass", &Impl::recordDepthPrepass, nullptr, nullptr});
        if (settings.path == FeaturePath::Compute)
            plan.push_back({"light-cull-compute", &Impl::recordLightCullCompute, nullptr, nullptr});
        else
            plan.push_back({"light-cull-cpu", nullptr, &Impl::buildTilesOnCpu, nullptr});
    }
    plan.push_back({"forward", &Impl::recordForward, nullptr, nullptr});
    if (settings.path == FeaturePath::Compute)
        plan.push_back({"tonemap-compute", &Impl::recordTonemapCompute, nullptr, nullptr});
    else
        plan.push_back({"tonemap-fallback", &Impl::recordTonemapFallback, nullptr, nullptr});
    if (heatmapPipeline) plan.push_back({"tile-heatmap", &Impl::recordHeatmap, nullptr, nullptr});
    if (device.capabilities().timestampQueries)
        for (PlannedPass& pass : plan)
            if (pass.record) pass.timer = device.createTimerQuery();
}

FrameReport Renderer::Impl::renderFrame() {
    FrameReport frame;
    frame.backend = rhi::toString(device.info().backend);
    frame.path = toString(settings.path);
    frame.width = settings.width;
    frame.height = settings.height;

    rhi::ICommandList& cmd = *commandList;
    bool recording = false;
    auto submit = [&] {
        if (!recording) return;
        cmd.end();
        device.execute(commandList);
        recording = false;
    };
    for (const PlannedPass& pass : plan) {
        PassReport report{pass.name};
        if (pass.cpuWork) {
            submit();
            (this->*pass.cpuWork)(report);
        } else {
            if (!recording) {
                cmd.begin();
                recording = true;
            }
            const auto start = std::chrono::steady_clock::now();
            if (pass.timer) cmd.beginTimer(pass.timer);
            cmd.pushDebugGroup(pass.name);
            (this->*pass.record)(cmd, report);
            cmd.popDebugGroup();
            if (pass.timer) cmd.endTimer(pass.timer);
            report.cpuMs = millisecondsSince(start);
        }
        frame.passes.push_back(std::move(report));
    }
    submit();
    frameRendered = true;

    for (size_t i = 0; i < plan.size(); ++i) {
        if (!plan[i].timer) continue;
        if (std::optional<double> seconds = device.timerSeconds(plan[i].timer)) frame.passes[i].gpuMs = *seconds * 1000.0;
    }
    if (cullingReport && tiled() && settings.path == FeaturePath::Compute) readCullStats(*cullingReport);
    if (cullingReport) warnOverflowOnce(*cullingReport);
    frame.lightCulling = cullingReport;
    return frame;
}

void Renderer::Impl::requireFrame(const char* what) const {
    if (!frameRendered) throw RendererError(fmt::format("{} was called before any frame was rendered; call renderFrame() first", what));
}

ImageRGBA8 Renderer::Impl::readDisplayImage() {
    requireFrame("readDisplayImage()");
    ImageRGBA8 image{settings.width, settings.height, {}};
    const std::vector<std::byte> bytes = device.readTexture(displayImage, {});
    if (bytes.size() != size_t(settings.width) * settings.height * 4)
        throw RendererError(fmt::format("display readback returned {} bytes, expected {} for {}x{} RGBA8", bytes.size(),
                                        size_t(settings.width) * settings.height * 4, settings.width, settings.height));
    image.pixels.resize(bytes.size());
    std::memcpy(image.pixels.data(), bytes.data(), bytes.size());
    return image;
}

ImageRGBAF Renderer::Impl::readHdrImage() {
    requireFrame("readHdrImage()");
    ImageRGBAF image{settings.width, settings.height, {}};
    const std::vector<std::byte> bytes = device.readTexture(hdrTarget, {});
    const size_t values = size_t(settings.width) * settings.height * 4;
    if (bytes.size() != values * 2)
        throw RendererError(fmt::format("HDR readback returned {} bytes, expected {} for {}x{} RGBA16F", bytes.size(), values * 2,
                                        settings.width, settings.height));
    image.pixels.resize(values);
    for (size_t i = 0; i < values; ++i) {
        uint16_t half;
        std::memcpy(&half, bytes.data() + i * 2, 2);
        image.pixels[i] = glm::unpackHalf1x16(half);
    }
    return image;
}

std::vector<float> Renderer::Impl::readDepth() {
    requireFrame("readDepth()");
    return readDepthTarget();
}

std::vector<float> Renderer::Impl::readDepthTarget() {
    const std::vector<std::byte> bytes = device.readTexture(depthTarget, {});
    const size_t pixels = size_t(settings.width) * settings.height;
    if (bytes.size() != pixels * 4)
        throw RendererError(fmt::format("depth readback returned {} bytes, expected {} for {}x{} D32F", bytes.size(), pixels * 4,
                                        settings.width, settings.height));
    std::vector<float> depth(pixels);
    std::memcpy(depth.data(), bytes.data(), bytes.size());
    return depth;
}

Renderer::Renderer(rhi::IDevice& device, const Scene& scene, const RenderSettings& settings)
    : m_impl(std::make_unique<Impl>(device, scene, settings)) {}
Renderer::~Renderer() = default;
FrameReport Renderer::renderFrame() { return m_impl->renderFrame(); }
ImageRGBA8 Renderer::readDisplayImage() { return m_impl->readDisplayImage(); }
ImageRGBAF Renderer::readHdrImage() { return m_impl->readHdrImage(); }
TileLists Renderer::readTileLists() { return m_impl->readTileLists(); }
std::vector<float> Renderer::readDepth() { return m_impl->readDepth(); }

}  // namespace janus::renderer
