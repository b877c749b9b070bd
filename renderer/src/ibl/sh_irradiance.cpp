#include "ibl/sh_irradiance.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include <fmt/format.h>

#include "core/gpu_util.h"
#include "ibl/spherical_harmonics.h"
#include "janus/shaders/bindings.h"

namespace janus::renderer {
namespace {

constexpr uint32_t kTile = 16;          // sh_project.comp local size (x and y)
constexpr uint32_t kFacesTimesCoefficients = 6 * kShCoefficientCount;   // sh_gather.frag target width

// std140 mirror of sh_common.glsl's ShUniforms.
struct ShUniforms {
    glm::uvec4 params;   // x face size, y partial groups
};

}  // namespace

ShIrradiance::ShIrradiance(rhi::IDevice& device, FeaturePath path) : m_device(device), m_path(path) {}

const char* ShIrradiance::passName(FeaturePath path) {
    return path == FeaturePath::Compute ? "sh-irradiance-compute" : "sh-irradiance-fallback";
}

void ShIrradiance::addPass(PassGraph& graph, PassGraph::ResourceId cubeResource, rhi::TextureHandle cube, uint32_t mip,
                           PassGraph::ResourceId shResource, const std::string& view) {
    PassGraph::PassDesc pass;
    pass.name = passName(m_path);
    pass.view = view;
    pass.reads = {cubeResource};
    pass.writes = {shResource};
    pass.setup = [this, cube = std::move(cube), mip] { prepare(cube, mip); };
    pass.record = [this](rhi::ICommandList& cmd, PassReport& report) { record(cmd, report); };
    graph.addPass(std::move(pass));
}

void ShIrradiance::prepare(const rhi::TextureHandle& cube, uint32_t mip) {
    if (!cube) throw RendererError("SH irradiance: no cube map");
    const rhi::TextureDesc& desc = cube->desc();
    if (desc.dimension != rhi::TextureDimension::TextureCube)
        throw RendererError(fmt::format("SH irradiance: '{}' is a {}, not a cube map", desc.debugName, rhi::toString(desc.dimension)));
    if (!rhi::any(desc.usage, rhi::TextureUsage::Sampled))
        throw RendererError(fmt::format("SH irradiance: cube map '{}' needs TextureUsage::Sampled", desc.debugName));
    if (desc.format != rhi::Format::RGBA16_FLOAT && desc.format != rhi::Format::RGBA32_FLOAT)
        throw RendererError(fmt::format("SH irradiance: cube map '{}' must be RGBA16F or RGBA32F", desc.debugName));
    if (mip >= desc.mipLevels)
        throw RendererError(fmt::format("SH irradiance: cube map '{}' has {} mips, mip {} asked for", desc.debugName, desc.mipLevels, mip));
    const rhi::Capabilities& caps = m_device.capabilities();
    if (m_path == FeaturePath::Compute && !(caps.compute && caps.storageBuffers))
        throw RendererError("SH irradiance: the compute path needs Compute and StorageBuffers; use the fallback path");
    if (m_path == FeaturePath::Fallback && !caps.floatRenderTargets)
        throw RendererError("SH irradiance: the fallback path needs FloatRenderTargets (RGBA32F attachments)");

    m_cube = cube;
    m_mip = mip;
    m_size = std::max(1u, desc.width >> mip);
    m_tiles = (m_size + kTile - 1) / kTile;
    const uint32_t groups = m_tiles * m_tiles * 6;

    m_nearest = m_device.createSampler(rhi::SamplerDesc{}.setFilter(rhi::Filter::Nearest).setAddress(rhi::AddressMode::ClampToEdge));
    m_uniforms = makeUniformBuffer(m_device, ShUniforms{glm::uvec4(m_size, groups, 0, 0)}, "sh uniforms");

    // Exact texel solid angles (double, then float), the same for every face.
    std::vector<float> solidAngles(size_t(m_size) * m_size);
    for (uint32_t y = 0; y < m_size; ++y)
        for (uint32_t x = 0; x < m_size; ++x) solidAngles[size_t(y) * m_size + x] = float(cubeTexelSolidAngle(x, y, m_size));
    m_solidAngles = m_device.createTexture(rhi::TextureDesc{}
                                               .setFormat(rhi::Format::R32_FLOAT)
                                               .setSize(m_size, m_size)
                                               .setUsage(rhi::TextureUsage::Sampled)
                                               .setDebugName("sh solid angles"));
    m_device.writeTexture(m_solidAngles, {}, solidAngles.data(), solidAngles.size() * sizeof(float));

    const rhi::BindingItem cubeItem = rhi::BindingItem::sampledTexture(JANUS_BINDING_SH_CUBE, m_cube, m_nearest).setMips(mip, 1);
    const rhi::BindingItem solidAngleItem = rhi::BindingItem::sampledTexture(JANUS_BINDING_SH_SOLID_ANGLES, m_solidAngles, m_nearest);
    const rhi::BindingItem uniformItem = rhi::BindingItem::uniformBuffer(JANUS_BINDING_SH_UNIFORMS, m_uniforms);

    if (m_path == FeaturePath::Compute) {
        m_partials = m_device.createBuffer(rhi::BufferDesc{}
                                               .setSize(uint64_t(groups) * kShCoefficientCount * sizeof(glm::vec4))
                                               .setUsage(rhi::BufferUsage::Storage)
                                               .setDebugName("sh partials"));
        m_coefficients = m_device.createBuffer(rhi::BufferDesc{}
                                                   .setSize(kShCoefficientCount * sizeof(glm::vec4))
                                                   .setUsage(rhi::BufferUsage::Storage | rhi::BufferUsage::Uniform)
                                                   .setDebugName("sh coefficients"));
        m_projectPipeline = m_device.createComputePipeline(
            rhi::ComputePipelineDesc{}.setShader(makeShader(m_device, rhi::ShaderStage::Compute, "sh_project_comp")).setDebugName("sh project"));
        m_reducePipeline = m_device.createComputePipeline(
            rhi::ComputePipelineDesc{}.setShader(makeShader(m_device, rhi::ShaderStage::Compute, "sh_reduce_comp")).setDebugName("sh reduce"));
        m_projectBindings = m_device.createBindingSet(rhi::BindingSetDesc{}.add(uniformItem).add(cubeItem).add(solidAngleItem).add(
            rhi::BindingItem::storageBuffer(JANUS_BINDING_SH_PARTIALS, m_partials)));
        m_reduceBindings = m_device.createBindingSet(rhi::BindingSetDesc{}
                                                         .add(uniformItem)
                                                         .add(rhi::BindingItem::storageBuffer(JANUS_BINDING_SH_PARTIALS, m_partials))
                                                         .add(rhi::BindingItem::storageBuffer(JANUS_BINDING_SH_COEFFICIENTS, m_coefficients)));
        return;
    }
    const rhi::TextureUsage targetUsage = rhi::TextureUsage::RenderTarget | rhi::TextureUsage::Sampled;
    m_rowSums = m_device.createTexture(rhi::TextureDesc{}
                                           .setFormat(rhi::Format::RGBA32_FLOAT)
                                           .setSize(kFacesTimesCoefficients, m_size)
                                           .setUsage(targetUsage)
                                           .setDebugName("sh row sums"));
    m_coefficientTexture = m_device.createTexture(rhi::TextureDesc{}
                                                      .setFormat(rhi::Format::RGBA32_FLOAT)
                                                      .setSize(kShCoefficientCount, 1)
                                                      .setUsage(targetUsage)
                                                      .setDebugName("sh coefficients"));
    const rhi::ShaderHandle vertex = makeShader(m_device, rhi::ShaderStage::Vertex, "fullscreen_vert");
    m_gatherPipeline = m_device.createGraphicsPipeline(rhi::GraphicsPipelineDesc{}
                                                           .setShaders(vertex, makeShader(m_device, rhi::ShaderStage::Fragment, "sh_gather_frag"))
                                                           .addColorFormat(rhi::Format::RGBA32_FLOAT)
                                                           .setDebugName("sh gather"));
    m_finalPipeline = m_device.createGraphicsPipeline(rhi::GraphicsPipelineDesc{}
                                                          .setShaders(vertex, makeShader(m_device, rhi::ShaderStage::Fragment, "sh_gather_final_frag"))
                                                          .addColorFormat(rhi::Format::RGBA32_FLOAT)
                                                          .setDebugName("sh gather final"));
    m_gatherBindings = m_device.createBindingSet(rhi::BindingSetDesc{}.add(uniformItem).add(cubeItem).add(solidAngleItem));
    m_finalBindings = m_device.createBindingSet(
        rhi::BindingSetDesc{}.add(uniformItem).add(rhi::BindingItem::sampledTexture(JANUS_BINDING_SH_PARTIALS, m_rowSums, m_nearest)));
}

void ShIrradiance::record(rhi::ICommandList& cmd, PassReport& report) {
    if (!m_cube) throw RendererError("SH irradiance: record() before prepare()");
    if (m_path == FeaturePath::Compute) {
        cmd.setPipeline(m_projectPipeline);
        cmd.setBindingSet(0, m_projectBindings);
        cmd.dispatch(m_tiles, m_tiles, 6);
        cmd.setPipeline(m_reducePipeline);
        cmd.setBindingSet(0, m_reduceBindings);
        cmd.dispatch(kShCoefficientCount);
        report.dispatches += 2;
        return;
    }
    // Every pixel of both targets is written, so their previous contents do not matter.
    rhi::Attachment rows = rhi::Attachment::clear(m_rowSums);
    rows.loadOp = rhi::LoadOp::DontCare;
    drawFullscreenTriangle(cmd, rows, m_gatherPipeline, m_gatherBindings, report);
    rhi::Attachment coefficients = rhi::Attachment::clear(m_coefficientTexture);
    coefficients.loadOp = rhi::LoadOp::DontCare;
    drawFullscreenTriangle(cmd, coefficients, m_finalPipeline, m_finalBindings, report);
}

void ShIrradiance::run(const rhi::TextureHandle& cube, uint32_t mip) {
    prepare(cube, mip);
    rhi::CommandListHandle cmd = m_device.createCommandList();
    PassReport report;
    cmd->begin();
    record(*cmd, report);
    cmd->end();
    m_device.execute(cmd);
}

std::array<glm::vec3, 9> ShIrradiance::readCoefficients() {
    if (!m_cube) throw RendererError("SH irradiance: readCoefficients() before prepare()");
    const std::vector<std::byte> bytes = m_path == FeaturePath::Compute ? m_device.readBuffer(m_coefficients)
                                                                        : m_device.readTexture(m_coefficientTexture, {});
    if (bytes.size() != kShCoefficientCount * sizeof(glm::vec4))
        throw RendererError(fmt::format("SH irradiance: readback returned {} bytes, expected {}", bytes.size(), kShCoefficientCount * sizeof(glm::vec4)));
    std::array<glm::vec4, 9> texels;
    std::memcpy(texels.data(), bytes.data(), bytes.size());
    std::array<glm::vec3, 9> out;
    for (uint32_t i = 0; i < 9; ++i) out[i] = glm::vec3(texels[i]);
    return out;
}

}  // namespace janus::renderer
