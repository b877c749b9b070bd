// Renderer: the composition root (renderer_impl.h). Construction uploads the scene once and
// builds the main view's frame graph from the features the scene and settings call for
// (docs/ARCHITECTURE.md, "Data flow of a frame"):
//   shadow-map     (shadows/)   main directional light, when there is one and shadows are on
//   depth-prepass  (forward/)   tiled light culling only: meshes -> D32F depth
//   light-cull-*   (forward/)   tiled only. compute: light_cull.comp | fallback: CPU builder -> tile lists
//   probe updates  (probes/)    before the frame: due reflection probes capture (six views with these passes), prefilter, show
//   gi relight     (gi/)        before the frame, while due: shadow map, brick radiance, probe SH -> the irradiance volume
//   forward        (forward/)   opaque and masked meshes -> RGBA16F HDR radiance (+ depth, or tested against the prepass depth)
//   sky            (ibl/)       with a sky: its radiance where no surface is
//   transparent    (forward/)   alphaMode BLEND meshes, back to front, blended over the HDR radiance (only with such meshes)
//   gi-probes      (debug_views/) DebugView::Gi with a volume: the probes as spheres over the HDR image
//   tonemap-*      (tonemap/)   HDR -> RGBA8 display (compute: storage-image dispatch | fallback: fullscreen triangle)
//   tile-heatmap   (debug_views/) DebugView::Tiles: lights per tile blended over the display image
// The pass graph keeps only passes whose output the frame needs. renderCubeCapture() renders six
// more views with the same features into a cube map.
#include "janus/renderer/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstring>

#include <fmt/format.h>
#include <glm/gtc/packing.hpp>

#include "core/gpu_util.h"
#include "deform/mesh_deformer.h"
#include "gi/gi_bake_file.h"
#include "renderer_impl.h"
#include "scene/scene_internal.h"

namespace janus::renderer {

Renderer::Impl::Impl(rhi::IDevice& d, const Scene& scene, const RenderSettings& s)
    : device(d), deviceLifetime(d.lifetime()), settings(s) {
    validateScene(scene);
    settings.msaaSamples = resolveMsaaSamples(s.msaaSamples, scene.quality);
    settings.alphaToCoverage = resolveAlphaToCoverage(s.alphaToCoverage, scene.quality);
    checkSettings();
    lighting = resolveLighting(settings.lighting, scene.quality);
    mainView = makeCameraView(scene.camera, settings.width, settings.height, "main");
    mainView.debugView = settings.debugView;
    mainView.sampleCount = settings.msaaSamples;
    mainView.alphaToCoverage = settings.msaaSamples > 1 && *settings.alphaToCoverage;
    createTargets();
    gpuScene = std::make_unique<GpuScene>(device, scene);
    createFeatures(scene);
    lights = scene.lights;
    commandList = device.createCommandList();
    buildFrameGraph();
}

// The one place that knows which features exist. Order matters twice: a feature may take
// another in its constructor, and passes are added (and so run) in this order for each view.
void Renderer::Impl::createFeatures(const Scene& scene) {
    // First, as the features that draw meshes (and the GI bake, which draws while it is made)
    // draw skinned and morphed instances from its posed buffers.
    if (MeshDeformer::needed(scene)) features.push_back(std::make_unique<MeshDeformer>(device, scene, *gpuScene, settings.path));
    localLights = std::make_unique<LocalLights>(device, scene, lighting, settings.path, mainView, gpuScene->pointSampler());
    auto shadows = std::make_unique<MainLightShadows>(device, scene, *gpuScene, lighting.shadows, lighting.shadowMapSize,
                                                      kMaxDirectionalLights);
    this->shadows = shadows.get();
    auto imageBasedLighting = std::make_unique<ImageBasedLighting>(device, scene.environment, settings.path, gpuScene->pointSampler());
    auto probes = std::make_unique<ReflectionProbes>(device, scene, settings.path, mainView.position, settings.probeMsaaSamples,
                                                     [this](const CubeCaptureDesc& capture) { return renderCubeCapture(capture); });
    reflectionProbes = probes.get();
    auto gi = std::make_unique<ProbeGi>(device, scene, *gpuScene, *localLights, *shadows, *imageBasedLighting, settings.path,
                                        mainView.position, settings.giBakeFile);
    probeGi = gi.get();
    auto forward = std::make_unique<ForwardShading>(device, scene, *gpuScene, *localLights, *shadows, *imageBasedLighting, *probes, *gi,
                                                    settings.path);
    this->forward = forward.get();
    auto sky = std::make_unique<SkyBackground>(device, *imageBasedLighting);
    // Blended surfaces composite over the sky, so their pass comes after it.
    std::unique_ptr<TransparentShading> transparent;
    if (!gpuScene->blendedDraws().empty()) transparent = std::make_unique<TransparentShading>(device, scene, *gpuScene, *forward);
    features.push_back(std::move(shadows));
    features.push_back(std::move(imageBasedLighting));
    // The GI relight runs before probe captures, so captures see the bounced light.
    features.push_back(std::move(gi));
    features.push_back(std::move(probes));
    features.push_back(std::move(forward));
    features.push_back(std::move(sky));
    if (transparent) features.push_back(std::move(transparent));
    // The probes go over the finished HDR image, before the tonemap.
    if (settings.debugView == DebugView::Gi && scene.irradianceVolume)
        features.push_back(std::make_unique<GiProbeView>(device, *scene.irradianceVolume, *probeGi));
    if ((settings.debugView == DebugView::Gi || settings.debugView == DebugView::GiLight) && !scene.irradianceVolume)
        fmt::print(stderr, "janus renderer: warning: no GI to show: scene '{}' has no irradiance volume, so the {} debug view is black; "
                           "give the scene an \"irradianceVolume\" (docs/SCENES.md) or a glTF node named IrradianceVolume...\n",
                   scene.name, toString(settings.debugView));
    if (settings.probeMsaaSamples > 1 && scene.reflectionProbes.empty())
        fmt::print(stderr, "janus renderer: warning: probe msaa {} has nothing to do: scene '{}' has no reflection probes (docs/PROBES.md)\n",
                   settings.probeMsaaSamples, scene.name);
    if (settings.debugView == DebugView::Shadow && !this->shadows->active())
        fmt::print(stderr, "janus renderer: warning: no shadow to show: scene '{}' has {}, so the shadow debug view is white "
                           "(every surface fully lit)\n",
                   scene.name, !lighting.shadows ? "shadows turned off (quality.shadows / --no-shadows)"
                                                 : "no directional light that gives light, or nothing to cast a shadow");
    // Every pass that shades the view's samples comes before the resolve, the tonemap after it.
    features.push_back(std::make_unique<MsaaResolve>());
    features.push_back(std::make_unique<Tonemap>(device, scene.environment.exposure, settings.path, gpuScene->pointSampler()));
    if (settings.debugView == DebugView::Tiles) features.push_back(std::make_unique<TileHeatmap>(device, *localLights, settings.path));
}

Renderer::Impl::~Impl() {
    if (deviceLifetime.expired()) {
        // Its work finished when it was destroyed; the RHI handles below may outlive it.
        fmt::print(stderr, "janus renderer: warning: the renderer's rhi::IDevice was destroyed before the renderer; destroy "
                           "the renderer first\n");
        return;
    }
    try {
        device.waitIdle();
    } catch (const std::exception& e) {
        fmt::print(stderr, "janus renderer: warning: waiting for the GPU before teardown failed: {}\n", e.what());
    }
}

void Renderer::Impl::checkSettings() const {
    const rhi::Capabilities& caps = device.capabilities();
    const uint32_t maxSize = caps.limits.maxTextureSize2D;
    if (settings.width == 0 || settings.height == 0 || settings.width > maxSize || settings.height > maxSize)
        throw RendererError(fmt::format("render size {}x{} is not possible on this {} device: width and height must be "
                                        "between 1 and its maximum 2D texture size {}",
                                        settings.width, settings.height, rhi::toString(device.info().backend), maxSize));
    if (!caps.floatRenderTargets)
        throw RendererError(fmt::format("the forward pass renders into RGBA16F, which needs the '{}' capability that this {} "
                                        "device lacks",
                                        rhi::toString(rhi::Capability::FloatRenderTargets), rhi::toString(device.info().backend)));
    requireSampleCount(device, settings.msaaSamples, mainView.colorFormat, mainView.depthFormat, "msaa");
    // Each probe's own count is checked where the probes are made, naming the probe.
    if (settings.probeMsaaSamples != 0)
        requireSampleCount(device, settings.probeMsaaSamples, ReflectionProbes::kCaptureFormat, ReflectionProbes::kCaptureDepthFormat,
                           "probe msaa");
    if (settings.path == FeaturePath::Compute) {
        for (rhi::Capability cap : {rhi::Capability::Compute, rhi::Capability::StorageImages, rhi::Capability::StorageBuffers})
            if (!caps.has(cap))
                throw RendererError(fmt::format("the compute path needs the '{}' capability, which this {} device lacks; render "
                                                "with the fallback path (FeaturePath::Fallback, --path fallback)",
                                                rhi::toString(cap), rhi::toString(device.info().backend)));
    }
}

void Renderer::Impl::createTargets() {
    const uint32_t w = settings.width, h = settings.height;
    hdrTarget = device.createTexture(rhi::TextureDesc{}
                                         .setFormat(mainView.colorFormat)
                                         .setSize(w, h)
                                         .setUsage(rhi::TextureUsage::RenderTarget | rhi::TextureUsage::Sampled)
                                         .setDebugName("hdr radiance"));
    // Sampled: light_cull.comp reads the prepass depth for the tile depth bounds. With
    // multisampling the scene is drawn into multisampled colour and depth, the colour resolved
    // into hdrTarget; multisampled depth is never sampled (tiles then have no depth bounds).
    const uint32_t samples = settings.msaaSamples;
    depthTarget = device.createTexture(rhi::TextureDesc{}
                                           .setFormat(mainView.depthFormat)
                                           .setSize(w, h)
                                           .setUsage(samples > 1 ? rhi::TextureUsage::RenderTarget
                                                                 : rhi::TextureUsage::RenderTarget | rhi::TextureUsage::Sampled)
                                           .setSampleCount(samples)
                                           .setDebugName(samples > 1 ? fmt::format("depth ({} samples)", samples) : "depth"));
    if (samples > 1)
        msaaColorTarget = device.createTexture(rhi::TextureDesc{}
                                                   .setFormat(mainView.colorFormat)
                                                   .setSize(w, h)
                                                   .setUsage(rhi::TextureUsage::RenderTarget)
                                                   .setSampleCount(samples)
                                                   .setDebugName(fmt::format("hdr radiance ({} samples)", samples)));
    rhi::TextureUsage displayUsage = Tonemap::displayUsage(settings.path);
    if (settings.debugView == DebugView::Tiles) displayUsage = displayUsage | TileHeatmap::displayUsage();
    displayImage = device.createTexture(
        rhi::TextureDesc{}.setFormat(rhi::Format::RGBA8_UNORM).setSize(w, h).setUsage(displayUsage).setDebugName("display"));
}

void Renderer::Impl::addView(PassGraph& graph, const SceneView& view, const ViewTarget& hdr, const ViewTarget& depth,
                             const ViewTarget* display) {
    graph.publish(view.name, frame_resources::kHdr, hdr);
    graph.publish(view.name, frame_resources::kDepth, depth);
    if (display) graph.publish(view.name, frame_resources::kDisplay, *display);
    for (const std::unique_ptr<RenderFeature>& feature : features) feature->addPasses(graph, view);
}

// The main view: the frame needs the display image (and the HDR image and depth, which can be
// read back), and the graph keeps what contributes to them.
void Renderer::Impl::buildFrameGraph() {
    const ViewTarget hdr{frameGraph.importResource("hdr"), hdrTarget, {}};
    const ViewTarget depth{frameGraph.importResource("depth"), depthTarget, {}};
    const ViewTarget display{frameGraph.importResource("display"), displayImage, {}};
    if (msaaColorTarget) {
        // The scene shades the samples; MsaaResolve averages them into hdrTarget.
        const ViewTarget samples{frameGraph.importResource("hdr-samples"), msaaColorTarget, {}};
        frameGraph.publish(mainView.name, frame_resources::kHdrResolved, hdr);
        addView(frameGraph, mainView, samples, depth, &display);
    } else {
        addView(frameGraph, mainView, hdr, depth, &display);
    }
    frameGraph.markOutput(display.resource);
    frameGraph.markOutput(hdr.resource);
    frameGraph.markOutput(depth.resource);
    frameGraph.compile(device);
}

FrameReport Renderer::Impl::newReport(uint32_t width, uint32_t height) const {
    FrameReport frame;
    frame.backend = rhi::toString(device.info().backend);
    frame.path = toString(settings.path);
    frame.width = width;
    frame.height = height;
    return frame;
}

FrameReport Renderer::Impl::renderFrame() {
    FrameReport frame = newReport(settings.width, settings.height);
    frame.msaaSamples = settings.msaaSamples;
    frame.alphaToCoverage = mainView.alphaToCoverage;
    frame.views.push_back(ViewReport{mainView.name, mainView.width, mainView.height, mainView.sampleCount});
    // Work done once when the renderer was made (e.g. the sky's filtering) opens the first report.
    for (const std::unique_ptr<RenderFeature>& feature : features)
        for (PassReport& pass : feature->takeStartupReports()) frame.passes.push_back(std::move(pass));
    // Then what features do before the frame (reflection-probe updates), then the frame.
    for (const std::unique_ptr<RenderFeature>& feature : features) feature->beginFrame(frame);
    for (PassReport& pass : frameGraph.execute(device, commandList)) frame.passes.push_back(std::move(pass));
    frameRendered = true;
    frame.lightCulling = localLights->finishFrame();
    takePerformanceMessages(frame);
    return frame;
}

void Renderer::Impl::takePerformanceMessages(FrameReport& frame) {
    for (rhi::DebugMessage& message : device.takePerformanceMessages()) frame.performanceMessages.push_back(std::move(message.text));
}

const Renderer::Impl::CaptureTargets& Renderer::Impl::captureTargets(uint32_t size, uint32_t samples, rhi::Format color) {
    if (samples == 1) color = rhi::Format::Unknown;   // faces render straight into the capture's target
    for (const CaptureTargets& targets : captureTargetSets)
        if (targets.size == size && targets.samples == samples && targets.color == color) return targets;
    CaptureTargets targets{size, samples, color, {}, {}};
    const std::string samplesText = samples > 1 ? fmt::format(", {} samples", samples) : "";
    targets.depth = device.createTexture(rhi::TextureDesc{}
                                             .setFormat(ReflectionProbes::kCaptureDepthFormat)
                                             .setSize(size, size)
                                             .setUsage(rhi::TextureUsage::RenderTarget)
                                             .setSampleCount(samples)
                                             .setDebugName(fmt::format("capture depth {}{}", size, samplesText)));
    if (samples > 1)
        targets.multisampledColor = device.createTexture(rhi::TextureDesc{}
                                                             .setFormat(color)
                                                             .setSize(size, size)
                                                             .setUsage(rhi::TextureUsage::RenderTarget)
                                                             .setSampleCount(samples)
                                                             .setDebugName(fmt::format("capture radiance {}{}", size, samplesText)));
    captureTargetSets.push_back(std::move(targets));
    return captureTargetSets.back();
}

FrameReport Renderer::Impl::renderCubeCapture(const CubeCaptureDesc& capture) {
    if (!capture.target)
        throw RendererError("cube capture: no target texture; give a TextureCube or TextureCubeArray with RenderTarget usage");
    const rhi::TextureDesc& desc = capture.target->desc();
    if (desc.dimension != rhi::TextureDimension::TextureCube && desc.dimension != rhi::TextureDimension::TextureCubeArray)
        throw RendererError(fmt::format("cube capture: target '{}' is a {}, not a cube map or cube array", desc.debugName,
                                        rhi::toString(desc.dimension)));
    const uint32_t cubes = rhi::textureLayerCount(desc) / 6;
    if (capture.cube >= cubes)
        throw RendererError(fmt::format("cube capture: target '{}' holds {} cube(s); cube {} does not exist", desc.debugName, cubes,
                                        capture.cube));
    if (!rhi::any(desc.usage, rhi::TextureUsage::RenderTarget))
        throw RendererError(fmt::format("cube capture: target '{}' needs RenderTarget usage", desc.debugName));
    const rhi::FormatKind kind = rhi::formatInfo(desc.format).kind;
    if (kind != rhi::FormatKind::Float)
        throw RendererError(fmt::format("cube capture: target '{}' has format {}; radiance needs a float colour format such as rgba16f",
                                        desc.debugName, rhi::toString(desc.format)));
    if (capture.mipLevel >= desc.mipLevels)
        throw RendererError(fmt::format("cube capture: target '{}' has {} mip level(s); mip {} does not exist", desc.debugName,
                                        desc.mipLevels, capture.mipLevel));
    if (capture.faces == 0 || capture.faces > 0x3f)
        throw RendererError(fmt::format("cube capture: faces mask {:#x} must name at least one of the six faces (bits 0..5)", capture.faces));
    if (capture.mipLevel > 0) device.require(rhi::Capability::RenderToCubeFaceMip, "cube capture into a mip level other than 0");
    const uint32_t samples = capture.msaaSamples;
    if (!isMsaaSampleCount(samples))
        throw RendererError(fmt::format("cube capture: msaa {} must be 1 (off), 2, 4, 8 or 16 samples per pixel", samples));
    requireSampleCount(device, samples, desc.format, ReflectionProbes::kCaptureDepthFormat,
                       fmt::format("cube capture into '{}': msaa", desc.debugName));
    const uint32_t size = rhi::mipExtent(desc.width, capture.mipLevel);

    PassGraph graph;
    const CaptureTargets& targets = captureTargets(size, samples, desc.format);
    const ViewTarget depth{graph.importResource("capture depth"), targets.depth, {}};
    // With samples every face is shaded into the same multisampled target, and its msaa-resolve
    // pass (msaa/) averages them into the face before the next face clears it.
    std::optional<ViewTarget> multisampled;
    if (samples > 1) multisampled = ViewTarget{graph.importResource("capture samples"), targets.multisampledColor, {}};
    FrameReport frame = newReport(size, size);
    frame.msaaSamples = samples;
    frame.alphaToCoverage = samples > 1 && *settings.alphaToCoverage;
    std::array<SceneView, 6> views = makeCubeFaceViews(capture.position, size, capture.nearPlane, capture.farPlane, capture.viewPrefix);
    for (uint32_t face = 0; face < 6; ++face) {
        if ((capture.faces & (1u << face)) == 0) continue;
        SceneView& view = views[face];
        view.colorFormat = desc.format;
        view.renderingLayers = capture.renderingLayers;
        view.passes.shadows = capture.shadows;
        view.passes.shadowMapSize = capture.shadowMapSize;
        view.passes.lightCulling = false;
        view.passes.tonemap = false;
        view.passes.reflectionProbes = capture.reflectionProbes;
        view.sampleCount = samples;
        view.alphaToCoverage = frame.alphaToCoverage;
        const ViewTarget color{graph.importResource(fmt::format("capture {}", cubeFaceName(face))), capture.target,
                               rhi::TextureSubresource{capture.mipLevel, capture.cube * 6 + face}};
        if (multisampled) {
            graph.publish(view.name, frame_resources::kHdrResolved, color);
            addView(graph, view, *multisampled, depth, nullptr);
        } else {
            addView(graph, view, color, depth, nullptr);
        }
        graph.markOutput(color.resource);
        frame.views.push_back(ViewReport{view.name, size, size, samples});
    }
    graph.compile(device);
    frame.passes = graph.execute(device, commandList);
    takePerformanceMessages(frame);
    return frame;
}

namespace {

bool sameLight(const Light& a, const Light& b) {
    return a.type == b.type && a.color == b.color && a.intensity == b.intensity && a.position == b.position &&
           a.direction == b.direction && a.range == b.range && a.innerConeAngle == b.innerConeAngle &&
           a.outerConeAngle == b.outerConeAngle && a.renderingLayers == b.renderingLayers;
}

}  // namespace

// Updates what reads the lights in place; the frame's plan (its passes, the light array's size)
// stays, so lights that need another plan are refused before anything changes.
void Renderer::Impl::setLights(std::span<const Light> newLights) {
    for (size_t i = 0; i < newLights.size(); ++i)
        if (const char* problem = detail::lightProblem(newLights[i]))
            throw RendererError(fmt::format("setLights: light {} {}", i, problem));
    if (std::equal(newLights.begin(), newLights.end(), lights.begin(), lights.end(), sameLight)) return;   // nothing to relight
    localLights->checkLights(newLights);
    shadows->checkLights(newLights);
    lights.assign(newLights.begin(), newLights.end());
    localLights->setLights(lights);
    shadows->setLights(lights);   // before forward shading, whose frame uniforms hold the map's matrix
    forward->setLights(lights);
    probeGi->setLights(lights);   // relights the volume from scratch before the next frame
}

void Renderer::Impl::requireDevice(const char* what) const {
    if (deviceLifetime.expired())
        throw RendererError(fmt::format("Renderer::{}: the rhi::IDevice this renderer was made with was destroyed; a renderer "
                                        "must not outlive its device (destroy the renderer first)", what));
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

Renderer::Renderer(rhi::IDevice& device, const Scene& scene, const RenderSettings& settings)
    : m_impl(std::make_unique<Impl>(device, scene, settings)) {}
Renderer::~Renderer() = default;
FrameReport Renderer::renderFrame() {
    m_impl->requireDevice("renderFrame()");
    return m_impl->renderFrame();
}
FrameReport Renderer::renderCubeCapture(const CubeCaptureDesc& capture) {
    m_impl->requireDevice("renderCubeCapture()");
    return m_impl->renderCubeCapture(capture);
}
void Renderer::requestProbeUpdate(std::string_view probeName) { m_impl->reflectionProbes->requestUpdate(probeName); }
bool Renderer::probesPending() const { return m_impl->reflectionProbes->pending(); }
bool Renderer::irradiancePending() const { return m_impl->probeGi->relightPending(); }
std::vector<IrradianceProbe> Renderer::readIrradianceProbes() {
    m_impl->requireDevice("readIrradianceProbes()");
    const GiBake& bake = m_impl->probeGi->bake();
    const std::vector<GiProbeSh> stored = m_impl->probeGi->readProbes();
    std::vector<IrradianceProbe> probes(stored.size());
    for (size_t i = 0; i < stored.size(); ++i) {
        probes[i].position = bake.probePositions[i];
        probes[i].sh = stored[i].coefficients;
        probes[i].valid = stored[i].valid;
        probes[i].backFaceFraction = bake.backFaceFraction[i];
    }
    return probes;
}
void Renderer::writeIrradianceProbes(std::span<const IrradianceProbe> probes) {
    m_impl->requireDevice("writeIrradianceProbes()");
    ProbeGi& gi = *m_impl->probeGi;
    if (!gi.active())
        throw RendererError("writeIrradianceProbes(): the scene has no irradiance volume; give it an \"irradianceVolume\" (docs/SCENES.md)");
    const std::vector<glm::vec3>& positions = gi.bake().probePositions;
    if (probes.size() != positions.size())
        throw RendererError(fmt::format("writeIrradianceProbes(): {} probes given, the volume has {}; pass one per probe, in the grid order "
                                        "readIrradianceProbes() gives",
                                        probes.size(), positions.size()));
    std::vector<GiProbeSh> stored(probes.size());
    for (size_t i = 0; i < probes.size(); ++i) {
        const glm::vec3 expected = positions[i], given = probes[i].position;
        if (!(glm::length(given - expected) <= 1e-4f * (1.0f + glm::length(expected))))
            throw RendererError(fmt::format("writeIrradianceProbes(): probe {} is at ({}, {}, {}), the volume's probe {} at ({}, {}, {}); pass the "
                                            "probes in the grid order readIrradianceProbes() gives",
                                            i, given.x, given.y, given.z, i, expected.x, expected.y, expected.z));
        for (size_t k = 0; k < 9; ++k)
            for (int c = 0; c < 3; ++c) {
                const float value = probes[i].sh[k][c];
                if (!std::isfinite(value) || std::abs(value) > 65504.0f)
                    throw RendererError(fmt::format("writeIrradianceProbes(): probe {} coefficient {} channel {} is {}; the volume stores "
                                                    "finite half floats (|value| <= 65504)",
                                                    i, k, c, value));
            }
        stored[i].coefficients = probes[i].sh;
        stored[i].valid = probes[i].valid;
    }
    gi.writeProbes(stored);
}
void Renderer::markIrradianceDirty() { m_impl->probeGi->markDirty(); }
void Renderer::setLights(std::span<const Light> lights) {
    m_impl->requireDevice("setLights()");
    m_impl->setLights(lights);
}

IrradianceBakeSummary bakeIrradianceVolume(rhi::IDevice& device, const Scene& scene, const std::filesystem::path& path) {
    validateScene(scene);
    if (!scene.irradianceVolume)
        throw RendererError("the scene has no irradiance volume to bake; give it an \"irradianceVolume\" (docs/SCENES.md) or a glTF node "
                            "named IrradianceVolume...");
    const auto start = std::chrono::steady_clock::now();
    const GpuScene gpuScene(device, scene);
    const GiBake bake = bakeGiVolume(device, gpuScene, *scene.irradianceVolume);
    writeGiBakeFile(path, bake, *scene.irradianceVolume, giSceneHash(scene));
    IrradianceBakeSummary summary;
    summary.probes = uint32_t(bake.probePositions.size());
    summary.validProbes = uint32_t(std::count(bake.valid.begin(), bake.valid.end(), true));
    const std::vector<glm::vec3> grid = giProbePositions(*scene.irradianceVolume);
    for (size_t p = 0; p < grid.size(); ++p) summary.relocatedProbes += bake.probePositions[p] != grid[p] ? 1u : 0u;
    summary.surfels = bake.surfels.size();
    summary.bricks = uint64_t(std::count_if(bake.bricks.begin(), bake.bricks.end(), [](const GiBrick& b) { return b.holdsLight(); }));
    summary.transfers = bake.transfers.size();
    summary.milliseconds = millisecondsSince(start);
    return summary;
}
ImageRGBA8 Renderer::readDisplayImage() {
    m_impl->requireDevice("readDisplayImage()");
    return m_impl->readDisplayImage();
}
ImageRGBAF Renderer::readHdrImage() {
    m_impl->requireDevice("readHdrImage()");
    return m_impl->readHdrImage();
}
TileLists Renderer::readTileLists() {
    m_impl->requireDevice("readTileLists()");
    m_impl->requireFrame("readTileLists()");
    return m_impl->localLights->readTileLists();
}
std::vector<float> Renderer::readDepth() {
    m_impl->requireDevice("readDepth()");
    m_impl->requireFrame("readDepth()");
    if (m_impl->settings.msaaSamples > 1)
        throw RendererError(fmt::format("readDepth(): the renderer draws with msaa {}, so its depth is multisampled and cannot be read "
                                        "back; read it from a renderer with msaaSamples 1",
                                        m_impl->settings.msaaSamples));
    return readDepth32F(m_impl->device, m_impl->depthTarget);
}

}  // namespace janus::renderer
