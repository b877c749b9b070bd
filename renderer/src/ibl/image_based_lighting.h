// Image-based lighting from the scene's sky (internal to the renderer; docs/IBL.md): the
// equirectangular map becomes a cube (EnvironmentMap), GGX-prefiltered mips (GgxPrefilter) and
// SH9 irradiance (ShIrradiance), and a second, sharper cube for the background, once, when the
// renderer is made; forward shading then reads the
// prefiltered cube, the DFG table and the SH through bindings JANUS_BINDING_SKY_*. Without a sky
// the feature makes only 1x1 stand-ins and the forward pass keeps the ambient colour.
#pragma once

#include <filesystem>
#include <memory>
#include <vector>

#include "core/render_feature.h"
#include "ibl/dfg_lut.h"
#include "ibl/environment_map.h"
#include "ibl/ggx_prefilter.h"
#include "ibl/sh_irradiance.h"
#include "janus/renderer/scene.h"

namespace janus::renderer {

// Blackboard name (frame-wide) of the processed sky: the prefiltered cube and SH are ready.
namespace ibl_resources {
inline constexpr const char* kSkyLight = "sky-light";
}  // namespace ibl_resources

// An equirectangular sky file (.hdr Radiance RGBE or .exr) as linear radiance. Throws RendererError
// naming the file when it cannot be read or has another extension.
ImageRGBAF readEnvironmentMap(const std::filesystem::path& path);

class ImageBasedLighting final : public RenderFeature {
public:
    // The sky's cube face size (mip 0 of the prefiltered cube; 8 mips).
    static constexpr uint32_t kSkyFaceSize = 128;
    // The background cube's face size for an equirect `equirectWidth` texels around: a quarter of
    // it (the equirect's texel density along the horizon), at least kSkyFaceSize, at most
    // kMaxBackgroundFaceSize and the device's cube limit (docs/IBL.md, "The background").
    static constexpr uint32_t kMaxBackgroundFaceSize = 1024;
    static uint32_t backgroundFaceSize(uint32_t equirectWidth, uint32_t maxCubeSize);

    // Reads environment.map (.hdr or .exr) when set and processes it on the GPU. Throws
    // RendererError naming the file when it cannot be read or is not a usable sky.
    ImageBasedLighting(rhi::IDevice& device, const Environment& environment, FeaturePath path, rhi::SamplerHandle pointSampler);

    bool active() const { return m_prefilter != nullptr; }

    // Publishes the processed sky (frame-wide, imported: it was made at construction) so views
    // that shade with it declare the read. Nothing without a sky.
    void addPasses(PassGraph& graph, const SceneView& view) override;
    std::vector<PassReport> takeStartupReports() override { return std::move(m_startupReports); }

    // Bindings JANUS_BINDING_SKY_SPECULAR, _DFG and _SKY_SH of the view set (stand-ins without a sky).
    void addViewBindings(rhi::BindingSetDesc& set) const;
    // frame.skyParams: x 1 with a sky, y the prefiltered cube's last mip, z intensity.
    glm::vec4 shadingParams() const;
    // The sky's radiance for the background, with a box-filtered mip chain; null without a sky.
    rhi::TextureHandle backgroundCube() const;
    float intensity() const { return m_intensity; }

private:
    rhi::IDevice& m_device;
    FeaturePath m_path;
    float m_intensity = 1.0f;
    rhi::SamplerHandle m_pointSampler, m_cubeSampler, m_dfgSampler;
    std::unique_ptr<EnvironmentMap> m_environment;
    std::unique_ptr<GgxPrefilter> m_prefilter;
    std::unique_ptr<ShIrradiance> m_sh;
    rhi::TextureHandle m_dfg;
    rhi::TextureHandle m_standInCube, m_standInShTexture;
    rhi::BufferHandle m_standInShBuffer;
    std::vector<PassReport> m_startupReports;
};

}  // namespace janus::renderer
