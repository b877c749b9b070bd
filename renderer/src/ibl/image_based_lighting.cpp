#include "ibl/image_based_lighting.h"

#include <algorithm>
#include <cctype>

#include <fmt/format.h>

#include "janus/renderer/image.h"
#include "janus/shaders/bindings.h"

namespace janus::renderer {
namespace {

// One DFG table per process: it depends on nothing but the BRDF (docs/IBL.md).
const DfgTable& sharedDfgTable() {
    static const DfgTable table = computeDfgTable();
    return table;
}

}  // namespace

ImageRGBAF readEnvironmentMap(const std::filesystem::path& path) {
    const std::string extension = lowerCaseExtension(path);
    try {
        if (extension == ".hdr") return readRadianceHDR(path);
        if (extension == ".exr") return readEXR(path);
    } catch (const std::exception& e) {
        throw RendererError(fmt::format("environment map {}: {}", path.string(), e.what()));
    }
    throw RendererError(fmt::format("environment map {}: unsupported file type '{}'; use an equirectangular .hdr or .exr",
                                    path.string(), extension));
}

ImageBasedLighting::ImageBasedLighting(rhi::IDevice& device, const Environment& environment, FeaturePath path,
                                       rhi::SamplerHandle pointSampler)
    : m_device(device), m_path(path), m_intensity(environment.intensity), m_pointSampler(std::move(pointSampler)) {
    m_cubeSampler = device.createSampler(rhi::SamplerDesc{}.setFilter(rhi::Filter::Linear).setAddress(rhi::AddressMode::ClampToEdge));
    m_dfgSampler = device.createSampler(
        rhi::SamplerDesc{}.setFilter(rhi::Filter::Linear).setAddress(rhi::AddressMode::ClampToEdge).setLodRange(0.0f, 0.0f));
    if (environment.map.empty() && !environment.image) {
        // Stand-ins keep the view bindings valid; frame.skyParams.x = 0 keeps them unread.
        m_standInCube = device.createTexture(rhi::TextureDesc{}
                                                 .setDimension(rhi::TextureDimension::TextureCube)
                                                 .setFormat(rhi::Format::RGBA16_FLOAT)
                                                 .setUsage(rhi::TextureUsage::Sampled)
                                                 .setDebugName("no sky"));
        m_dfg = device.createTexture(rhi::TextureDesc{}.setFormat(rhi::Format::RGBA16_FLOAT).setUsage(rhi::TextureUsage::Sampled).setDebugName("no DFG table"));
        if (path == FeaturePath::Compute)
            m_standInShBuffer = device.createBuffer(
                rhi::BufferDesc{}.setSize(9 * 16).setUsage(rhi::BufferUsage::Storage).setDebugName("no sky SH"));
        else
            m_standInShTexture = device.createTexture(
                rhi::TextureDesc{}.setFormat(rhi::Format::RGBA32_FLOAT).setSize(9, 1).setUsage(rhi::TextureUsage::Sampled).setDebugName("no sky SH"));
        return;
    }

    const ImageRGBAF sky = environment.map.empty() ? *environment.image : readEnvironmentMap(environment.map);
    m_environment = std::make_unique<EnvironmentMap>(device, sky, kSkyFaceSize, path);
    // Skies have suns: their brightest texels are summed exactly, not sampled (docs/IBL.md, "Bright texels").
    GgxPrefilterSettings prefilterSettings;
    prefilterSettings.brightTexels = kDefaultGgxBrightTexels;
    m_prefilter = std::make_unique<GgxPrefilter>(device, path, prefilterSettings);
    m_sh = std::make_unique<ShIrradiance>(device, path);
    // Once, now: the sky does not change while the renderer lives. The passes are reported in the
    // first frame's report (takeStartupReports).
    PassGraph graph;
    const ViewTarget cube = m_environment->addPasses(graph);
    const ViewTarget prefiltered = m_prefilter->addPasses(graph, cube);
    const PassGraph::ResourceId sh = graph.addResource("sky SH");
    m_sh->addPass(graph, cube.resource, m_environment->cube(), 0, sh);
    const ViewTarget background =
        m_environment->addBackgroundPasses(graph, backgroundFaceSize(sky.width, device.capabilities().limits.maxTextureSizeCube));
    graph.markOutput(prefiltered.resource);
    graph.markOutput(sh);
    graph.markOutput(background.resource);
    graph.compile(device);
    m_startupReports = graph.execute(device, device.createCommandList());
    m_dfg = uploadDfgTable(device, sharedDfgTable());
}

void ImageBasedLighting::addPasses(PassGraph& graph, const SceneView&) {
    if (!active() || graph.find("", ibl_resources::kSkyLight)) return;
    const PassGraph::ResourceId sky = graph.importResource(ibl_resources::kSkyLight);
    graph.publish("", ibl_resources::kSkyLight, ViewTarget{sky, m_prefilter->prefiltered(), {}});
}

void ImageBasedLighting::addViewBindings(rhi::BindingSetDesc& set) const {
    set.add(rhi::BindingItem::sampledTexture(JANUS_BINDING_SKY_SPECULAR, active() ? m_prefilter->prefiltered() : m_standInCube, m_cubeSampler));
    set.add(rhi::BindingItem::sampledTexture(JANUS_BINDING_DFG, m_dfg, m_dfgSampler));
    if (m_path == FeaturePath::Compute)
        set.add(rhi::BindingItem::storageBuffer(JANUS_BINDING_SKY_SH, active() ? m_sh->coefficientBuffer() : m_standInShBuffer));
    else
        set.add(rhi::BindingItem::sampledTexture(JANUS_BINDING_SKY_SH, active() ? m_sh->coefficientTexture() : m_standInShTexture,
                                                 m_pointSampler));
}

glm::vec4 ImageBasedLighting::shadingParams() const {
    if (!active()) return glm::vec4(0.0f);
    return glm::vec4(1.0f, float(m_prefilter->mipCount() - 1), m_intensity, 0.0f);
}

rhi::TextureHandle ImageBasedLighting::backgroundCube() const { return active() ? m_environment->background() : nullptr; }

uint32_t ImageBasedLighting::backgroundFaceSize(uint32_t equirectWidth, uint32_t maxCubeSize) {
    return std::max(kSkyFaceSize, std::min({equirectWidth / 4, kMaxBackgroundFaceSize, maxCubeSize}));
}

}  // namespace janus::renderer
