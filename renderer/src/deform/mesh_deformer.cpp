#include "deform/mesh_deformer.h"

#include <algorithm>
#include <array>
#include <cstddef>

#include <fmt/format.h>

#include "core/gpu_util.h"
#include "scene/scene_internal.h"
#include "core/pass_graph.h"
#include "janus/shaders/bindings.h"

namespace janus::renderer {
namespace {

constexpr uint32_t kGroupSize = 64;               // deform.comp local_size_x
constexpr uint32_t kTexelsPerVertex = sizeof(Vertex) / 16;
static_assert(sizeof(Vertex) == 80 && kTexelsPerVertex == 5, "deform_points.vert writes a Vertex as five RGBA32F texels");
// Widest texture the fallback path makes: GLES 3.0 promises 2048.
constexpr uint32_t kMaxTextureWidth = 2048;
constexpr uint32_t kJointsPerTextureRow = 256;    // deform_points.vert: 4 texels per matrix, 1024 wide

// std140 mirror of deform_common.glsl's DeformUniforms.
struct DeformUniforms {
    glm::ivec4 counts;   // vertices, morph targets, skinned, 0
    glm::ivec4 target;   // fallback: output width, height
    glm::vec4 morphWeights[kMaxMorphTargets / 4];
};
static_assert(sizeof(DeformUniforms) == 32 + kMaxMorphTargets * 4, "DeformUniforms must match std140");

// What the shaders read for a mesh without skin data or morph targets (bindings cannot be empty).
std::vector<glm::vec4> standIn() { return {glm::vec4(0.0f)}; }

// `texels` RGBA32F texels laid out `width` per row (the last row zero-padded).
rhi::TextureHandle makeTexelTexture(rhi::IDevice& device, std::vector<glm::vec4> texels, uint32_t width, const std::string& name) {
    const uint32_t height = uint32_t((texels.size() + width - 1) / width);
    texels.resize(size_t(width) * height, glm::vec4(0.0f));
    rhi::TextureHandle texture = device.createTexture(rhi::TextureDesc{}
                                                          .setFormat(rhi::Format::RGBA32_FLOAT)
                                                          .setSize(width, height)
                                                          .setUsage(rhi::TextureUsage::Sampled)
                                                          .setDebugName(name));
    device.writeTexture(texture, {}, texels.data(), texels.size() * sizeof(glm::vec4));
    return texture;
}

template <class T>
rhi::BufferHandle makeBuffer(rhi::IDevice& device, const std::vector<T>& data, rhi::BufferUsage usage, const std::string& name) {
    rhi::BufferHandle buffer =
        device.createBuffer(rhi::BufferDesc{}.setSize(data.size() * sizeof(T)).setUsage(usage).setDebugName(name));
    device.writeBuffer(buffer, data.data(), data.size() * sizeof(T));
    return buffer;
}

}  // namespace

bool MeshDeformer::deforms(const Scene& scene, const Instance& instance) { return detail::isDeformed(scene, instance); }

bool MeshDeformer::needed(const Scene& scene) {
    return std::any_of(scene.instances.begin(), scene.instances.end(), [&](const Instance& i) { return deforms(scene, i); });
}

const MeshDeformer::MeshData& MeshDeformer::meshData(const Scene& scene, uint32_t meshIndex) {
    MeshData& data = m_meshes[meshIndex];
    if (data.vertexCount > 0) return data;
    const Mesh& mesh = scene.meshes[meshIndex];
    const bool compute = m_path == FeaturePath::Compute;
    const rhi::BufferUsage usage = compute ? rhi::BufferUsage::Storage : rhi::BufferUsage::Vertex;
    data.vertexCount = uint32_t(mesh.vertices.size());
    data.base = makeBuffer(m_device, mesh.vertices, usage, fmt::format("mesh {} deform base", meshIndex));
    // Joint indices as floats (exact below 2^24; skins have at most kMaxSkinJoints): one vertex
    // layout and one storage layout for both paths.
    std::vector<glm::vec4> skin(size_t(data.vertexCount) * 2, glm::vec4(0.0f));
    for (size_t v = 0; v < mesh.joints.size() && v < data.vertexCount; ++v) {
        skin[v * 2] = glm::vec4(mesh.joints[v]);
        skin[v * 2 + 1] = mesh.weights[v];
    }
    data.skin = makeBuffer(m_device, skin, usage, fmt::format("mesh {} joints and weights", meshIndex));
    std::vector<glm::vec4> displacements;
    displacements.reserve(mesh.morphTargets.size() * data.vertexCount * 3);
    for (const MorphTarget& target : mesh.morphTargets)
        for (size_t v = 0; v < data.vertexCount; ++v) {
            displacements.push_back(glm::vec4(target.positions.empty() ? glm::vec3(0.0f) : target.positions[v], 0.0f));
            displacements.push_back(glm::vec4(target.normals.empty() ? glm::vec3(0.0f) : target.normals[v], 0.0f));
            displacements.push_back(glm::vec4(target.tangents.empty() ? glm::vec3(0.0f) : target.tangents[v], 0.0f));
        }
    if (displacements.empty()) displacements = standIn();
    const std::string name = fmt::format("mesh {} morph displacements", meshIndex);
    if (compute)
        data.morphBuffer = makeBuffer(m_device, displacements, rhi::BufferUsage::Storage, name);
    else
        data.morphTexture = makeTexelTexture(m_device, displacements, std::min<uint32_t>(uint32_t(displacements.size()), kMaxTextureWidth), name);
    return data;
}

MeshDeformer::MeshDeformer(rhi::IDevice& device, const Scene& scene, GpuScene& gpuScene, FeaturePath path)
    : m_device(device), m_path(path), m_meshes(scene.meshes.size()) {
    const bool compute = path == FeaturePath::Compute;
    m_pointSampler = device.createSampler(rhi::SamplerDesc{}.setFilter(rhi::Filter::Nearest).setAddress(rhi::AddressMode::ClampToEdge));
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        if (!deforms(scene, instance)) continue;
        const Mesh& mesh = scene.meshes[instance.mesh];
        const MeshData& meshGpu = meshData(scene, instance.mesh);
        InstanceData data;
        data.instance = i;
        data.mesh = instance.mesh;
        const bool skinned = !mesh.joints.empty() && instance.skin >= 0;

        DeformUniforms uniforms{};
        uniforms.counts = glm::ivec4(int32_t(meshGpu.vertexCount), int32_t(mesh.morphTargets.size()), skinned ? 1 : 0, 0);
        for (size_t t = 0; t < mesh.morphTargets.size(); ++t)
            uniforms.morphWeights[t / 4][int(t % 4)] = t < instance.morphWeights.size() ? instance.morphWeights[t] : 0.0f;

        std::vector<glm::vec4> joints;   // four columns per matrix
        if (skinned)
            for (const glm::mat4& m : instance.jointMatrices)
                for (int c = 0; c < 4; ++c) joints.push_back(m[c]);
        if (joints.empty()) joints = standIn();
        const std::string name = fmt::format("instance {} ('{}')", i, instance.nodeName);
        rhi::BindingSetDesc bindings;
        if (compute) {
            data.jointBuffer = makeBuffer(m_device, joints, rhi::BufferUsage::Storage, name + " joint matrices");
            data.posed = m_device.createBuffer(rhi::BufferDesc{}
                                                   .setSize(uint64_t(meshGpu.vertexCount) * sizeof(Vertex))
                                                   .setUsage(rhi::BufferUsage::Vertex | rhi::BufferUsage::Storage)
                                                   .setDebugName(name + " posed vertices"));
            bindings.add(rhi::BindingItem::storageBuffer(JANUS_BINDING_DEFORM_JOINTS, data.jointBuffer))
                .add(rhi::BindingItem::storageBuffer(JANUS_BINDING_DEFORM_MORPHS, meshGpu.morphBuffer))
                .add(rhi::BindingItem::storageBuffer(JANUS_BINDING_DEFORM_BASE, meshGpu.base))
                .add(rhi::BindingItem::storageBuffer(JANUS_BINDING_DEFORM_SKIN, meshGpu.skin))
                .add(rhi::BindingItem::storageBuffer(JANUS_BINDING_DEFORM_OUTPUT, data.posed));
        } else {
            // Four texels per matrix, kJointsPerTextureRow matrices per row (deform_points.vert).
            const uint32_t jointTexels = uint32_t(joints.size());
            data.jointTexture = makeTexelTexture(m_device, joints, std::min(jointTexels, 4 * kJointsPerTextureRow), name + " joint matrices");
            const uint32_t texels = meshGpu.vertexCount * kTexelsPerVertex;
            const uint32_t width = std::min(texels, kMaxTextureWidth - kMaxTextureWidth % kTexelsPerVertex);
            const uint32_t height = (texels + width - 1) / width;
            uniforms.target = glm::ivec4(int32_t(width), int32_t(height), 0, 0);
            data.target = m_device.createTexture(rhi::TextureDesc{}
                                                     .setFormat(rhi::Format::RGBA32_FLOAT)
                                                     .setSize(width, height)
                                                     .setUsage(rhi::TextureUsage::RenderTarget)
                                                     .setDebugName(name + " posed texels"));
            data.posed = m_device.createBuffer(rhi::BufferDesc{}
                                                   .setSize(uint64_t(width) * height * 16)
                                                   .setUsage(rhi::BufferUsage::Vertex)
                                                   .setDebugName(name + " posed vertices"));
            bindings.add(rhi::BindingItem::sampledTexture(JANUS_BINDING_DEFORM_JOINTS, data.jointTexture, m_pointSampler))
                .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_DEFORM_MORPHS, meshGpu.morphTexture, m_pointSampler));
        }
        data.uniforms = makeUniformBuffer(m_device, uniforms, "deform uniforms");
        bindings.add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_DEFORM_UNIFORMS, data.uniforms));
        data.bindings = m_device.createBindingSet(bindings);
        gpuScene.useInstanceVertices(i, data.posed);
        m_instances.push_back(std::move(data));
    }

    if (compute) {
        m_pipeline = m_device.createComputePipeline(
            rhi::ComputePipelineDesc{}.setShader(makeShader(m_device, rhi::ShaderStage::Compute, "deform_comp")).setDebugName("mesh deform"));
    } else {
        rhi::GraphicsPipelineDesc desc;
        desc.setShaders(makeShader(m_device, rhi::ShaderStage::Vertex, "deform_points_vert"),
                        makeShader(m_device, rhi::ShaderStage::Fragment, "deform_points_frag"))
            .setTopology(rhi::PrimitiveTopology::PointList);
        m_pipeline = m_device.createGraphicsPipeline(
            GpuScene::addVertexLayout(desc)
                .addVertexBuffer({1, 2 * sizeof(glm::vec4), false})
                .addVertexAttribute({6, rhi::VertexFormat::Float4, 1, 0})
                .addVertexAttribute({7, rhi::VertexFormat::Float4, 1, sizeof(glm::vec4)})
                .addColorFormat(rhi::Format::RGBA32_FLOAT)
                .setDebugName("mesh deform points"));
    }

    // Once, now: the pose does not change while the renderer lives (see the header).
    PassGraph graph;
    const PassGraph::ResourceId posed = graph.addResource("posed vertices");
    PassGraph::PassDesc pass;
    pass.name = compute ? "mesh-deform-compute" : "mesh-deform-fallback";
    pass.writes = {posed};
    pass.record = [this](rhi::ICommandList& cmd, PassReport& report) { record(cmd, report); };
    graph.addPass(std::move(pass));
    graph.markOutput(posed);
    graph.compile(m_device);
    m_startupReports = graph.execute(m_device, m_device.createCommandList());
}

void MeshDeformer::record(rhi::ICommandList& cmd, PassReport& report) const {
    for (const InstanceData& data : m_instances) {
        const MeshData& mesh = m_meshes[data.mesh];
        if (m_path == FeaturePath::Compute) {
            cmd.setPipeline(m_pipeline);
            cmd.setBindingSet(0, data.bindings);
            cmd.dispatch((mesh.vertexCount + kGroupSize - 1) / kGroupSize);
            ++report.dispatches;
            continue;
        }
        // Every texel a vertex owns is drawn; the padding after the last vertex stays cleared.
        cmd.beginRenderPass(rhi::RenderPassDesc{}.addColor(rhi::Attachment::clear(data.target, {0, 0, 0, 0})));
        cmd.setPipeline(m_pipeline);
        cmd.setBindingSet(0, data.bindings);
        cmd.setVertexBuffer(0, mesh.base);
        cmd.setVertexBuffer(1, mesh.skin);
        cmd.draw(mesh.vertexCount, kTexelsPerVertex);
        ++report.draws;
        cmd.endRenderPass();
        cmd.copyTextureToBuffer(data.posed, 0, data.target, {});
    }
}

rhi::BufferHandle MeshDeformer::posedVertices(uint32_t instance) const {
    for (const InstanceData& data : m_instances)
        if (data.instance == instance) return data.posed;
    return nullptr;
}

}  // namespace janus::renderer
