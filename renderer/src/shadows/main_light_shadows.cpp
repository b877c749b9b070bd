#include "shadows/main_light_shadows.h"

namespace janus::renderer {

MainLightShadows::MainLightShadows(rhi::IDevice& device, const Scene& scene, const GpuScene& gpuScene, bool enabled, uint32_t mapSize,
                                   uint32_t shadedDirectionalLights)
    : m_device(device), m_mapSize(mapSize) {
    m_standInTexture = device.createTexture(rhi::TextureDesc{}
                                                .setFormat(DirectionalShadowMap::kDepthFormat)
                                                .setSize(1, 1)
                                                .setUsage(rhi::TextureUsage::Sampled | rhi::TextureUsage::RenderTarget)
                                                .setDebugName("no shadow map"));
    m_standInSampler = device.createSampler(rhi::SamplerDesc{}
                                                .setFilter(rhi::Filter::Nearest)
                                                .setAddress(rhi::AddressMode::ClampToEdge)
                                                .setCompare(rhi::CompareOp::LessOrEqual));
    if (!enabled) return;
    const std::optional<size_t> main = mainDirectionalLight(scene, shadedDirectionalLights);
    if (!main) return;
    m_bounds = sceneWorldBounds(scene);
    if (m_bounds.empty()) return;
    m_lightDirection = scene.lights[*main].direction;
    const Material defaultMaterial;
    for (const Instance& instance : scene.instances) {
        const GpuScene::Mesh& mesh = gpuScene.meshes()[instance.mesh];
        if (mesh.indexCount == 0) continue;
        const Mesh& sceneMesh = scene.meshes[instance.mesh];
        const Material& material = sceneMesh.material >= 0 ? scene.materials[size_t(sceneMesh.material)] : defaultMaterial;
        // Blended (transparent) surfaces cast no shadow (docs/LIGHTING.md, "Transparent surfaces").
        if (material.alphaMode == AlphaMode::Blend) continue;
        m_casters.push_back(ShadowCaster{mesh.vertices, mesh.indices, mesh.indexCount, instance.world, material.doubleSided});
    }
}

void MainLightShadows::createMap() {
    if (m_map) return;
    m_map = std::make_unique<DirectionalShadowMap>(m_device, m_mapSize);
    m_map->fit(m_lightDirection, m_bounds.min, m_bounds.max);
    m_map->setCasters(m_casters);
}

void MainLightShadows::addPasses(PassGraph& graph, const SceneView&) {
    if (!active() || graph.find("", frame_resources::kShadowMap)) return;
    const PassGraph::ResourceId shadowMap = graph.addResource(frame_resources::kShadowMap);
    PassGraph::PassDesc pass;
    pass.name = "shadow-map";
    pass.writes = {shadowMap};
    pass.setup = [this] { createMap(); };
    pass.record = [this](rhi::ICommandList& cmd, PassReport& report) { m_map->record(cmd, m_casters, report.draws); };
    graph.addPass(std::move(pass));
    graph.publish("", frame_resources::kShadowMap, ViewTarget{shadowMap, nullptr, {}});
}

rhi::BindingItem MainLightShadows::binding(uint32_t slot) const {
    return m_map ? m_map->binding(slot) : rhi::BindingItem::sampledTexture(slot, m_standInTexture, m_standInSampler);
}

}  // namespace janus::renderer
