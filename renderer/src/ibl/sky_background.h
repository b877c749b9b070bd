// Sky background feature (internal to the renderer): after forward shading, the sky's radiance
// fills every pixel of a view that no surface covered (a far-plane triangle tested LessOrEqual
// against the view's depth). Only views of a scene with a sky get the "sky" pass.
#pragma once

#include <memory>
#include <vector>

#include "core/render_feature.h"
#include "ibl/image_based_lighting.h"

namespace janus::renderer {

class SkyBackground final : public RenderFeature {
public:
    SkyBackground(rhi::IDevice& device, const ImageBasedLighting& lighting);

    // Adds "sky" for a view with kHdr and kDepth targets when the frame has the sky: reads both
    // and the sky, writes kHdr.
    void addPasses(PassGraph& graph, const SceneView& view) override;

private:
    struct ViewState {
        SceneView view;
        ViewTarget hdr, depth;
        rhi::BufferHandle uniforms;
        rhi::BindingSetHandle bindings;
        rhi::PipelineHandle pipeline;
    };
    void setup(ViewState& state);
    void record(const ViewState& state, rhi::ICommandList& cmd, PassReport& report);

    rhi::IDevice& m_device;
    const ImageBasedLighting& m_lighting;
    rhi::SamplerHandle m_sampler;
    std::vector<std::unique_ptr<ViewState>> m_views;   // by view name, reused when a view renders again
};

}  // namespace janus::renderer
