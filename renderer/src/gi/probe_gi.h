// Probe GI feature (internal to the renderer; docs/GI.md): the scene's irradiance volume.
//
// At construction the volume is baked (gi_bake.h: G-buffer cubes -> surfels -> bricks and SH
// transfers) and uploaded as data textures. A relight (before a frame, on its own submission)
// runs, per cycle:
//   shadow-map            the main light's map (the relight's direct light is shadowed)
//   gi-brick-radiance-*   every brick's outgoing radiance (compute: one dispatch | fallback: one draw)
//   gi-probe-sh-*         the relit probes' SH9 irradiance / pi into the volume texture
//                         (compute: one workgroup per probe, shared-memory reduction | fallback:
//                         one draw per layer of probes into three volume slices, a fragment gather)
// `bounces` cycles make the light bounce that many times: a cycle after the first adds the last
// cycle's irradiance at each surfel. With probesPerFrame = 0 a relight runs all its cycles in one
// frame; otherwise each frame relights the next probesPerFrame probes in camera-distance order, and
// a cycle takes ceil(P / K) frames. When the cycles are done the volume is left alone until
// markDirty() (lights changed). Forward shading reads the volume (gi_access.glsl) for every view.
#pragma once

#include <array>
#include <filesystem>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "core/gpu_scene.h"
#include "core/render_feature.h"
#include "forward/frame_uniforms.h"
#include "forward/local_lights.h"
#include "gi/gi_bake.h"
#include "ibl/image_based_lighting.h"
#include "shadows/main_light_shadows.h"

namespace janus::renderer {

namespace gi_resources {
inline constexpr const char* kIrradianceVolume = "irradiance-volume";   // frame-wide: the probes' SH
}  // namespace gi_resources

// std140 mirror of gi_relight_common.glsl's relight parameters.
struct GiRelightParams {
    glm::ivec4 counts{0};
    glm::ivec4 schedule{0};
    glm::ivec4 grid{1};
};

// std140 mirror of gi_access.glsl's GiVolumeUniforms.
struct GiVolumeUniforms {
    glm::vec4 origin{0.0f};
    glm::vec4 spacing{1.0f};
    glm::ivec4 counts{1};
};

// One probe's stored SH (irradiance / pi, basis order of spherical_harmonics.h) and validity.
struct GiProbeSh {
    std::array<glm::vec3, 9> coefficients{};
    bool valid = false;
};

class ProbeGi final : public RenderFeature {
public:
    // Bakes the scene's volume, or reads it from `bakeFile` when one is given (nothing without a
    // volume). Throws RendererError when the path cannot relight on this device or the file does
    // not fit the scene (gi_bake_file.h).
    ProbeGi(rhi::IDevice& device, const Scene& scene, const GpuScene& gpuScene, const LocalLights& localLights,
            MainLightShadows& shadows, const ImageBasedLighting& imageBasedLighting, FeaturePath path, const glm::vec3& cameraPosition,
            const std::filesystem::path& bakeFile = {});

    bool active() const { return m_active; }
    // Publishes kIrradianceVolume (frame-wide, imported) so forward passes declare the read.
    void addPasses(PassGraph& graph, const SceneView& view) override;
    std::vector<PassReport> takeStartupReports() override { return std::move(m_startupReports); }
    // This frame's relight step, when one is due.
    void beginFrame(FrameReport& frame) override;
    // JANUS_BINDING_GI_VOLUME, _GI_UNIFORMS and _GI_VISIBILITY of a view set (stand-ins, "off",
    // without a volume).
    void addViewBindings(rhi::BindingSetDesc& set) const;

    // The lights changed: relight (all cycles again, starting from what the volume holds).
    void markDirty();
    // Renderer::setLights: the relight's directional lights (the local lights are LocalLights',
    // the shadow MainLightShadows'), and a relight from scratch, as at construction: the old
    // lights' bounced light must not feed the new lights' bounces.
    void setLights(std::span<const Light> lights);
    // True while the volume has relight cycles to run.
    bool relightPending() const { return m_active && m_cyclesDone < m_bounces; }
    // The bake, and what the volume holds now (waits for the GPU), grid order.
    const GiBake& bake() const { return m_bake; }
    std::vector<GiProbeSh> readProbes() const;
    // Stores `probes` (grid order, one per probe: the caller checks) in the volume and ends a
    // relight in progress: the volume holds exactly them until the next relight.
    void writeProbes(std::span<const GiProbeSh> probes);

private:
    void upload();
    void setupRelight();
    GiRelightParams relightParams(bool bounce) const;   // counts and grid; the schedule is the SH pass's
    FrameUniforms relightFrameUniforms() const;
    void recordBrickRadiance(rhi::ICommandList& cmd, PassReport& report, bool bounce);
    void recordProbeSh(rhi::ICommandList& cmd, PassReport& report, uint32_t firstRank, uint32_t count, bool bounce);

    rhi::IDevice& m_device;
    const LocalLights& m_localLights;
    MainLightShadows& m_shadows;
    const ImageBasedLighting& m_imageBasedLighting;
    FeaturePath m_path;
    bool m_active = false;
    IrradianceVolume m_volume;
    GiBake m_bake;
    uint32_t m_bounces = 1;
    uint32_t m_probeCount = 0, m_probesPerStep = 0;
    uint32_t m_cyclesDone = 0, m_nextRank = 0;
    bool m_volumeHasLight = false;   // a cycle finished: further bounces can read it
    std::vector<uint32_t> m_rankToProbe;

    rhi::TextureHandle m_volumeTexture, m_standInVolume;
    rhi::TextureHandle m_visibility, m_standInVisibility;   // null m_visibility: no visibility test
    rhi::BufferHandle m_volumeUniforms, m_standInUniforms;
    rhi::TextureHandle m_surfels, m_bricks, m_transfers, m_probes, m_brickRadiance;
    FrameUniforms m_relightFrame{};   // the scene's lights; the shadow is filled in at setup
    rhi::BufferHandle m_frameUniforms, m_relightParams;
    rhi::SamplerHandle m_pointSampler;
    rhi::PipelineHandle m_brickPipeline, m_shPipeline;
    rhi::BindingSetHandle m_brickBindings, m_shBindings;
    rhi::CommandListHandle m_commandList;
    std::vector<PassReport> m_startupReports;
};

}  // namespace janus::renderer
