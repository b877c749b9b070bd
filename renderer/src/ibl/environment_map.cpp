#include "ibl/environment_map.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/gtc/packing.hpp>

#include "core/gpu_util.h"
#include "janus/shaders/bindings.h"

namespace janus::renderer {
namespace {

constexpr uint32_t kGroupSize = 8;   // equirect_to_cube.comp local_size
constexpr double kPi = 3.14159265358979323846;

// std140 mirror of equirect_common.glsl's EquirectParams.
struct EquirectParams {
    glm::ivec4 params;   // x face, y face size
};

}  // namespace

glm::dvec2 equirectUv(const glm::dvec3& d) {
    return {0.5 + std::atan2(d.x, -d.z) / (2.0 * kPi), std::acos(std::clamp(d.y, -1.0, 1.0)) / kPi};
}

glm::dvec3 equirectDirection(const glm::dvec2& uv) {
    const double phi = (uv.x - 0.5) * 2.0 * kPi, theta = uv.y * kPi;
    return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}


EnvironmentMap::EnvironmentMap(rhi::IDevice& device, const ImageRGBAF& equirect, uint32_t faceSize, FeaturePath path)
    : m_device(device), m_path(path) {
    if (equirect.width == 0 || equirect.height == 0 || equirect.pixels.size() != size_t(equirect.width) * equirect.height * 4)
        throw RendererError(fmt::format("environment map: the equirect image is empty or malformed ({}x{}, {} floats)", equirect.width,
                                        equirect.height, equirect.pixels.size()));
    const rhi::Capabilities& caps = device.capabilities();
    requireFaceSize(faceSize, "face size");
    if (equirect.width > caps.limits.maxTextureSize2D || equirect.height > caps.limits.maxTextureSize2D)
        throw RendererError(fmt::format("environment map: the equirect image {}x{} exceeds the device's 2D limit {}", equirect.width,
                                        equirect.height, caps.limits.maxTextureSize2D));
    if (path == FeaturePath::Compute && !(caps.compute && caps.storageImages))
        throw RendererError("environment map: the compute path needs Capability::Compute and StorageImages");
    if (path == FeaturePath::Fallback && !caps.renderToCubeFaceMip)
        throw RendererError("environment map: the fallback path needs Capability::RenderToCubeFaceMip");

    // RGBA32F keeps every value of the file; devices that cannot filter it get RGBA16F (clamped).
    const bool float32 = device.formatCapabilities(rhi::Format::RGBA32_FLOAT).has(rhi::FormatCapability::Filterable);
    const size_t count = equirect.pixels.size();
    m_equirect = device.createTexture(rhi::TextureDesc{}
                                          .setFormat(float32 ? rhi::Format::RGBA32_FLOAT : rhi::Format::RGBA16_FLOAT)
                                          .setSize(equirect.width, equirect.height)
                                          .setUsage(rhi::TextureUsage::Sampled)
                                          .setDebugName("environment equirect"));
    if (float32) {
        device.writeTexture(m_equirect, {}, equirect.pixels.data(), count * sizeof(float));
    } else {
        std::vector<uint16_t> halves(count);
        for (size_t i = 0; i < count; ++i) halves[i] = glm::packHalf1x16(std::clamp(equirect.pixels[i], 0.0f, 65504.0f));
        device.writeTexture(m_equirect, {}, halves.data(), count * sizeof(uint16_t));
    }
    m_lighting.faceSize = faceSize;
    m_lighting.cube = createCube(faceSize, "environment cube");
    rhi::SamplerDesc sampler;
    sampler.setFilter(rhi::Filter::Linear);
    sampler.addressU = rhi::AddressMode::Repeat;   // wraps around the horizon
    sampler.addressV = sampler.addressW = rhi::AddressMode::ClampToEdge;
    m_sampler = device.createSampler(sampler);
}

void EnvironmentMap::requireFaceSize(uint32_t faceSize, const char* what) const {
    const uint32_t most = m_device.capabilities().limits.maxTextureSizeCube;
    if (faceSize == 0 || faceSize > most) throw RendererError(fmt::format("environment map: {} {} is outside 1..{}", what, faceSize, most));
}

rhi::TextureHandle EnvironmentMap::createCube(uint32_t faceSize, const char* debugName) const {
    const rhi::TextureUsage usage = rhi::TextureUsage::Sampled |
                                    (m_path == FeaturePath::Compute ? rhi::TextureUsage::Storage : rhi::TextureUsage::RenderTarget);
    return m_device.createTexture(rhi::TextureDesc{}
                                      .setDimension(rhi::TextureDimension::TextureCube)
                                      .setFormat(rhi::Format::RGBA16_FLOAT)
                                      .setSize(faceSize, faceSize)
                                      .setMipLevels(0)
                                      .setUsage(usage)
                                      .setDebugName(debugName));
}

ViewTarget EnvironmentMap::addPasses(PassGraph& graph) {
    ViewTarget target;
    target.resource = graph.addResource(ibl_resources::kEnvironment);
    target.texture = m_lighting.cube;
    PassGraph::PassDesc pass;
    pass.name = m_path == FeaturePath::Compute ? "equirect-to-cube-compute" : "equirect-to-cube-fallback";
    pass.writes = {target.resource};
    pass.setup = [this] { setup(m_lighting); };
    pass.record = [this](rhi::ICommandList& cmd, PassReport& report) { record(m_lighting, cmd, report); };
    graph.addPass(std::move(pass));
    graph.publish("", ibl_resources::kEnvironment, target);
    return target;
}

ViewTarget EnvironmentMap::addBackgroundPasses(PassGraph& graph, uint32_t faceSize) {
    if (m_background.cube) throw RendererError("environment map: the background cube was added already");
    requireFaceSize(faceSize, "background face size");
    m_background.faceSize = faceSize;
    m_background.cube = createCube(faceSize, "sky background cube");
    ViewTarget target;
    target.resource = graph.addResource("sky background");
    target.texture = m_background.cube;
    PassGraph::PassDesc pass;
    pass.name = m_path == FeaturePath::Compute ? "background-cube-compute" : "background-cube-fallback";
    pass.writes = {target.resource};
    pass.setup = [this] { setup(m_background); };
    pass.record = [this](rhi::ICommandList& cmd, PassReport& report) {
        record(m_background, cmd, report);
        // A box-filtered chain: the background samples it by the pixel's footprint, so an image
        // smaller than the sky averages it instead of aliasing it.
        if (m_background.cube->desc().mipLevels > 1) cmd.generateMips(m_background.cube);
    };
    graph.addPass(std::move(pass));
    return target;
}

void EnvironmentMap::setup(Conversion& conversion) {
    if (!conversion.bindings.empty()) return;
    if (m_path == FeaturePath::Compute) {
        if (!m_pipeline)
            m_pipeline = m_device.createComputePipeline(rhi::ComputePipelineDesc{}
                                                            .setShader(makeShader(m_device, rhi::ShaderStage::Compute, "equirect_to_cube_comp"))
                                                            .setDebugName("equirect to cube"));
        const rhi::BufferHandle params =
            makeUniformBuffer(m_device, EquirectParams{glm::ivec4(0, int(conversion.faceSize), 0, 0)}, "equirect params");
        conversion.bindings.push_back(m_device.createBindingSet(
            rhi::BindingSetDesc{}
                .add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_EQUIRECT_PARAMS, params))
                .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_EQUIRECT_SOURCE, m_equirect, m_sampler))
                .add(rhi::BindingItem::storageImage(JANUS_BINDING_EQUIRECT_CUBE, conversion.cube, 0))));
        return;
    }
    if (!m_pipeline)
        m_pipeline = m_device.createGraphicsPipeline(rhi::GraphicsPipelineDesc{}
                                                         .setShaders(makeShader(m_device, rhi::ShaderStage::Vertex, "fullscreen_vert"),
                                                                     makeShader(m_device, rhi::ShaderStage::Fragment, "equirect_to_cube_frag"))
                                                         .addColorFormat(rhi::Format::RGBA16_FLOAT)
                                                         .setDebugName("equirect to cube"));
    for (int face = 0; face < 6; ++face) {
        const rhi::BufferHandle params =
            makeUniformBuffer(m_device, EquirectParams{glm::ivec4(face, int(conversion.faceSize), 0, 0)}, "equirect params");
        conversion.bindings.push_back(m_device.createBindingSet(
            rhi::BindingSetDesc{}
                .add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_EQUIRECT_PARAMS, params))
                .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_EQUIRECT_SOURCE, m_equirect, m_sampler))));
    }
}

void EnvironmentMap::record(const Conversion& conversion, rhi::ICommandList& cmd, PassReport& report) {
    if (m_path == FeaturePath::Compute) {
        cmd.setPipeline(m_pipeline);
        cmd.setBindingSet(0, conversion.bindings[0]);
        const uint32_t groups = (conversion.faceSize + kGroupSize - 1) / kGroupSize;
        cmd.dispatch(groups, groups, 6);
        ++report.dispatches;
        return;
    }
    for (uint32_t face = 0; face < 6; ++face) {
        rhi::Attachment target = rhi::Attachment::clear(conversion.cube, {0, 0, 0, 0}, {0, face});
        target.loadOp = rhi::LoadOp::DontCare;   // every texel is written
        drawFullscreenTriangle(cmd, target, m_pipeline, conversion.bindings[face], report);
    }
}

PassReport EnvironmentMap::convert() {
    PassGraph graph;
    const ViewTarget target = addPasses(graph);
    graph.markOutput(target.resource);
    graph.compile(m_device);
    std::vector<PassReport> reports = graph.execute(m_device, m_device.createCommandList());
    return reports.empty() ? PassReport{} : reports.front();
}

}  // namespace janus::renderer
