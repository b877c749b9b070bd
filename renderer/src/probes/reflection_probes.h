// Reflection probes feature (internal to the renderer; docs/PROBES.md).
//
// Each probe the main view can use is captured with the renderer's own passes (six mirrored
// cube-face views, the reduced pass set: no tile culling, no tonemap, no probes unless the probe
// sees probes (the shown ones, never what it writes); shadows and
// rendering layers as the probe says; with the probe's samples per pixel, resolved face by face)
// into the probe's capture cube, whose mip chain is built and
// GGX-prefiltered (GgxPrefilter: 7 levels, roughness = mip / 6) into the probe's staging cube;
// when the whole update is done the staging mips are copied where shading reads them and the
// probe is listed in the view's probe uniforms. Updates follow the probe's mode (once / every
// frame / on request) and are spread over frames as its time slicing says (probe_update_plan.h),
// so shading never sees faces or mips of different updates.
//
// Where shading reads probes: a cube array of all shown probes (face size: the largest probe's;
// a smaller probe starts at a lower mip, so the roughness -> lod mapping carries each probe's
// first and last mip), or, on devices without cube arrays (GLES 3.0), one cube per probe and at
// most two probes. Probes beyond what the main view can show are left out with a warning,
// farthest from the camera first; left-out probes are never captured.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/render_feature.h"
#include "ibl/ggx_prefilter.h"
#include "janus/renderer/renderer.h"
#include "probes/probe_update_plan.h"

namespace janus::renderer {

namespace probe_resources {
inline constexpr const char* kReflectionProbes = "reflection-probes";   // frame-wide: the shown probes
}  // namespace probe_resources

class ReflectionProbes final : public RenderFeature {
public:
    // Renders the six faces (bit f of `faces`) of a capture: Renderer::Impl::renderCubeCapture.
    using CaptureFunction = std::function<FrameReport(const CubeCaptureDesc&)>;

    static constexpr uint32_t kMaxShownWithCubeArrays = 16;   // probe_access.glsl kMaxShownProbes
    static constexpr uint32_t kMaxShownWithoutCubeArrays = 2;
    static constexpr uint32_t kPrefilteredMips = 7;           // mip 0 + 6 GGX mips (36 draws on the fallback path)
    static constexpr rhi::Format kCaptureFormat = rhi::Format::RGBA16_FLOAT;
    static constexpr rhi::Format kCaptureDepthFormat = rhi::Format::D32_FLOAT;

    // Picks the probes the view at `cameraPosition` shows and makes their textures; a probe's
    // capture takes `msaaSamples` per pixel, or its own (ReflectionProbe::msaaSamples) when 0.
    // Throws RendererError when the path cannot prefilter on this device, or the device does not
    // allow a shown probe's sample count.
    ReflectionProbes(rhi::IDevice& device, const Scene& scene, FeaturePath path, const glm::vec3& cameraPosition,
                     uint32_t msaaSamples, CaptureFunction capture);

    bool active() const { return !m_probes.empty(); }

    // Publishes kReflectionProbes for views that shade with probes (the forward pass reads it).
    void addPasses(PassGraph& graph, const SceneView& view) override;
    // Runs this frame's steps of every probe update that is due, before the frame's graph.
    void beginFrame(FrameReport& frame) override;

    // Bindings JANUS_BINDING_PROBE_CUBES(, _PROBE_CUBE_1) and _REFLECTION_PROBES of the view set:
    // the shown probes for views that want probes, stand-ins (no probe) for the others.
    void addViewBindings(rhi::BindingSetDesc& set, const SceneView& view) const;
    // Whether forward shading must use the two-cube shader variant (forward_textures_cubes_frag).
    bool separateCubes() const { return !m_cubeArrays; }

    // Starts an update of the named probe (all probes when empty) at the next frame, whatever its
    // mode; an update in progress finishes first. Throws RendererError for an unknown name.
    void requestUpdate(std::string_view probeName);
    // True while a probe the main view shows has an update due or under way and was never shown.
    bool pending() const;

private:
    struct Probe {
        ReflectionProbe desc;
        uint32_t slot = 0;             // cube of the array | binding (0 or 1) without cube arrays
        uint32_t baseMip = 0;          // mip of the shown texture that holds this probe's mip 0
        rhi::TextureHandle capture;    // RGBA16F cube, full chain: what the faces are rendered into
        rhi::TextureHandle shownCube;  // without cube arrays: what shading reads
        std::unique_ptr<GgxPrefilter> prefilter;   // staging: its destination
        std::vector<ProbeUpdateStep> plan;
        bool shown = false;            // an update finished: listed in the uniforms
        bool requested = false;
        int step = -1;                 // next step of the update in progress; -1 idle
        uint32_t updates = 0;          // updates started
        ProbeUpdateReport report;      // of the update in progress
    };

    void createShownTextures();
    void runStep(Probe& probe, FrameReport& frame);
    void writeUniforms(rhi::ICommandList& cmd);
    bool due(const Probe& probe) const;

    rhi::IDevice& m_device;
    FeaturePath m_path;
    CaptureFunction m_capture;
    bool m_cubeArrays = false;
    std::vector<Probe> m_probes;       // shown order (blend priority: smallest influence first)
    rhi::TextureHandle m_shownArray;   // with cube arrays
    rhi::BufferHandle m_uniforms, m_standInUniforms;
    rhi::TextureHandle m_standInCube;
    rhi::SamplerHandle m_sampler;
    rhi::CommandListHandle m_commandList;
    std::vector<rhi::TimerQueryHandle> m_timers;
};

}  // namespace janus::renderer
