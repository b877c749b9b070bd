// Debug view "gi" (internal to the renderer; docs/GI.md): the irradiance volume's probes as
// small spheres over the view's HDR image, each shaded with its own SH irradiance / pi at the
// sphere's normal, invalid probes in flat kInvalidProbeColor and in front of everything (they are
// inside geometry). forward.frag shows the volume's light on the surfaces in the same view.
#pragma once

#include <glm/glm.hpp>

#include "core/pass_graph.h"
#include "core/render_feature.h"
#include "gi/probe_gi.h"

namespace janus::renderer {

class GiProbeView final : public RenderFeature {
public:
    static inline const glm::vec3 kInvalidProbeColor{1.0f, 0.0f, 1.0f};   // gi_probe_view.frag
    static constexpr float kRadiusOfSpacing = 0.1f;                    // sphere radius / smallest probe spacing

    GiProbeView(rhi::IDevice& device, const IrradianceVolume& volume, const ProbeGi& probeGi);

    // For a view with DebugView::Gi, when the scene has a volume: adds "gi-probes" (after the
    // view's surfaces, before the tonemap), which reads and writes the view's kHdr and kDepth and
    // reads the irradiance volume. Adds nothing otherwise.
    void addPasses(PassGraph& graph, const SceneView& view) override;

private:
    void setup();
    void record(rhi::ICommandList& cmd, PassReport& report);

    rhi::IDevice& m_device;
    const ProbeGi& m_probeGi;
    float m_radius = 0.0f;
    uint32_t m_probeCount = 0;
    SceneView m_view;
    ViewTarget m_color, m_depth;
    rhi::BufferHandle m_uniforms;
    rhi::BindingSetHandle m_bindings;
    rhi::PipelineHandle m_pipeline;
};

}  // namespace janus::renderer
