// Renderer::Impl, private to the renderer: the composition root. It uploads the scene
// (GpuScene), makes the feature modules the settings call for, gives each view its targets and
// lets the features add their passes to a pass graph (core/pass_graph.h), which culls what no
// output needs and runs the rest. Everything a feature does lives in its folder:
//   core/          pass graph, scene views, the uploaded scene and how meshes are drawn, helpers
//   forward/       lighting settings, local lights + tile lists + culling, forward shading,
//                  transparent (alphaMode BLEND) shading
//   shadows/       the main directional light's shadow map
//   msaa/          averaging a multisampled view's samples before the tonemap
//   tonemap/       HDR -> display image
//   ibl/           the sky: cube, GGX prefilter, SH irradiance, background
//   probes/        reflection probes: capture, time-sliced updates, what shading reads
//   gi/            probe GI: the irradiance volume's bake, relight and what shading reads
//   debug_views/   the tile heat map, the GI probes
//   scene/, io/    loading scenes, reading and writing images
#pragma once

#include <deque>
#include <memory>
#include <span>
#include <vector>

#include "core/gpu_scene.h"
#include "core/pass_graph.h"
#include "core/render_feature.h"
#include "debug_views/gi_probe_view.h"
#include "debug_views/tile_heatmap.h"
#include "forward/forward_shading.h"
#include "forward/lighting_settings.h"
#include "forward/local_lights.h"
#include "forward/transparent_shading.h"
#include "gi/probe_gi.h"
#include "ibl/image_based_lighting.h"
#include "ibl/sky_background.h"
#include "msaa/msaa_resolve.h"
#include "msaa/msaa_settings.h"
#include "msaa/sample_count.h"
#include "janus/renderer/renderer.h"
#include "probes/reflection_probes.h"
#include "shadows/main_light_shadows.h"
#include "tonemap/tonemap.h"

namespace janus::renderer {

struct Renderer::Impl {
    rhi::IDevice& device;
    std::weak_ptr<const void> deviceLifetime;   // device.lifetime(): expired once the device is destroyed
    RenderSettings settings;
    ResolvedLighting lighting;
    SceneView mainView;
    rhi::TextureHandle hdrTarget, depthTarget, displayImage;   // the main view's targets
    rhi::TextureHandle msaaColorTarget;   // with msaaSamples > 1: what the scene is shaded into (depthTarget is multisampled too)

    std::unique_ptr<GpuScene> gpuScene;
    std::unique_ptr<LocalLights> localLights;   // forward/'s light data; also behind readTileLists()
    ReflectionProbes* reflectionProbes = nullptr;   // one of `features`; behind requestProbeUpdate()
    ProbeGi* probeGi = nullptr;                     // one of `features`
    MainLightShadows* shadows = nullptr;            // one of `features`; setLights refits its map
    ForwardShading* forward = nullptr;              // one of `features`; setLights updates its frame uniforms
    std::vector<Light> lights;                      // what the frame is lit with now (setLights compares)
    // The features in the order their passes are added for each view (core/render_feature.h).
    std::vector<std::unique_ptr<RenderFeature>> features;

    PassGraph frameGraph;                   // the main view's frame, compiled once
    rhi::CommandListHandle commandList;
    // What cube captures render into besides their target, per face size and sample count in use:
    // depth, and with samples the multisampled colour (of the target's format) they resolve.
    struct CaptureTargets {
        uint32_t size = 0, samples = 1;
        rhi::Format color = rhi::Format::Unknown;   // Unknown with one sample
        rhi::TextureHandle depth, multisampledColor;
    };
    std::deque<CaptureTargets> captureTargetSets;   // a deque: references to its elements stay valid
    bool frameRendered = false;   // the targets hold nothing readable before the first frame

    Impl(rhi::IDevice& d, const Scene& scene, const RenderSettings& s);
    // A frame that threw half-way (e.g. in the CPU step between its submissions) may leave work
    // in flight that uses the resources about to be destroyed: wait for it first.
    ~Impl();

    void checkSettings() const;
    void createTargets();
    void createFeatures(const Scene& scene);
    // Publishes a view's targets on the graph and lets every feature add its passes for it.
    void addView(PassGraph& graph, const SceneView& view, const ViewTarget& hdr, const ViewTarget& depth, const ViewTarget* display);
    void buildFrameGraph();
    FrameReport newReport(uint32_t width, uint32_t height) const;
    FrameReport renderFrame();
    FrameReport renderCubeCapture(const CubeCaptureDesc& capture);
    // Moves the device's performance messages (collected apart from validation messages) into the report.
    void takePerformanceMessages(FrameReport& frame);
    const CaptureTargets& captureTargets(uint32_t size, uint32_t samples, rhi::Format color);
    void setLights(std::span<const Light> newLights);
    void requireFrame(const char* what) const;
    // Throws RendererError when the device was destroyed (a Renderer must not outlive it).
    void requireDevice(const char* what) const;
    ImageRGBA8 readDisplayImage();
    ImageRGBAF readHdrImage();
};

}  // namespace janus::renderer
