// Tonemap feature (internal to the renderer): exposure -> ACES fitted -> sRGB encode -> round to
// 8 bits, HDR radiance into the RGBA8 display image. Compute path: 8x8 groups writing a storage
// image (tonemap.comp); fallback: a fullscreen triangle into the image as an attachment
// (tonemap.frag). Both include shaders/renderer/tonemap_common.glsl and are bit-identical.
#pragma once

#include "core/pass_graph.h"
#include "janus/renderer/settings.h"

namespace janus::renderer {

class Tonemap {
public:
    Tonemap(rhi::IDevice& device, float exposure, FeaturePath path, rhi::SamplerHandle pointSampler);

    // The usage the display image needs for this path.
    static rhi::TextureUsage displayUsage(FeaturePath path);

    // Adds "tonemap-compute" | "tonemap-fallback": reads `hdr`, writes `display` (same size).
    void addPass(PassGraph& graph, const std::string& view, const ViewTarget& hdr, const ViewTarget& display);

private:
    void setup();
    void record(rhi::ICommandList& cmd, PassReport& report);

    rhi::IDevice& m_device;
    float m_exposure = 1.0f;
    FeaturePath m_path;
    rhi::SamplerHandle m_pointSampler;
    ViewTarget m_hdr, m_display;
    rhi::BufferHandle m_uniforms;
    rhi::BindingSetHandle m_bindings;
    rhi::PipelineHandle m_pipeline;
};

}  // namespace janus::renderer
