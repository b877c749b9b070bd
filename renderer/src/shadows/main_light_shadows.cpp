#include "shadows/main_light_shadows.h"

#include <algorithm>
#include <tuple>
#include <utility>

#include <fmt/format.h>

#include "core/gpu_util.h"
#include "forward/frame_uniforms.h"
#include "janus/renderer/renderer.h"
#include "janus/shaders/bindings.h"

namespace janus::renderer {

MainLightShadows::MainLightShadows(rhi::IDevice& device, const Scene& scene, const GpuScene& gpuScene, bool enabled, uint32_t mapSize,
                                   uint32_t shadedDirectionalLights)
    : m_device(device), m_gpuScene(gpuScene), m_mapSize(mapSize), m_shadedDirectionalLights(shadedDirectionalLights) {
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
    m_bounds = sceneWorldBounds(scene);
    if (m_bounds.empty()) return;
    // The casters are gathered even without a main light, so setLights can tell whether a light
    // that appears later would need the pass (checkLights).
    const std::optional<size_t> main = mainDirectionalLight(scene, shadedDirectionalLights);
    m_hasMainLight = main.has_value();
    if (main) m_lightDirection = scene.lights[*main].direction;
    const Material defaultMaterial;
    std::vector<std::pair<uint32_t, ShadowCaster>> gathered;   // (mesh, caster)
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        const GpuScene::Mesh& mesh = gpuScene.meshes()[instance.mesh];
        if (mesh.indexCount == 0) continue;
        const Mesh& sceneMesh = scene.meshes[instance.mesh];
        const Material& material = sceneMesh.material >= 0 ? scene.materials[size_t(sceneMesh.material)] : defaultMaterial;
        // Blended (transparent) surfaces cast no shadow (docs/LIGHTING.md, "Transparent surfaces").
        if (material.alphaMode == AlphaMode::Blend) continue;
        // Points and lines have no area to cast a shadow with.
        if (sceneMesh.topology != MeshTopology::Triangles) continue;
        if (material.alphaMode == AlphaMode::Mask) continue;   // drawn with their alpha test (m_maskedDraws)
        // Posed vertices for skinned and morphed instances (MeshDeformer).
        gathered.emplace_back(instance.mesh, ShadowCaster{gpuScene.instanceVertices(i), mesh.indices, mesh.indexCount, instance.world,
                                                          material.doubleSided});
    }
    // A depth-only map with a LessOrEqual test holds the nearest depth whatever the draw order, so
    // the casters are drawn grouped: by pipeline (culling, winding), then mesh, each bound once.
    auto key = [](const std::pair<uint32_t, ShadowCaster>& c) {
        return std::tuple(c.second.doubleSided, glm::determinant(glm::mat3(c.second.world)) < 0.0f, c.first);
    };
    std::stable_sort(gathered.begin(), gathered.end(), [&](const auto& a, const auto& b) { return key(a) < key(b); });
    for (auto& [meshIndex, caster] : gathered) m_casters.push_back(std::move(caster));
    const std::vector<GpuScene::Draw>& draws = gpuScene.draws();
    for (uint32_t d = 0; d < draws.size(); ++d) {
        const Mesh& sceneMesh = scene.meshes[draws[d].mesh];
        const Material& material = sceneMesh.material >= 0 ? scene.materials[size_t(sceneMesh.material)] : defaultMaterial;
        if (material.alphaMode == AlphaMode::Mask && sceneMesh.topology == MeshTopology::Triangles &&
            gpuScene.meshes()[draws[d].mesh].indexCount > 0)
            m_maskedDraws.push_back(d);
    }
}

void MainLightShadows::checkLights(std::span<const Light> lights) const {
    if (active() || !hasCasters() || !mainDirectionalLight(lights, m_shadedDirectionalLights)) return;
    throw RendererError("setLights: the new lights have a directional light that gives light, but this renderer was made without "
                        "one, so its frame has no shadow-map pass; create a new Renderer for a scene with these lights");
}

void MainLightShadows::setLights(std::span<const Light> lights) {
    if (!active()) return;
    const std::optional<size_t> main = mainDirectionalLight(lights, m_shadedDirectionalLights);
    if (!main) return;
    m_lightDirection = lights[*main].direction;
    // Maps already made are refitted in place: binding sets that hold them stay valid, and the
    // next shadow-map pass uploads the new light view-projection.
    for (auto& [size, map] : m_maps) map->fit(m_lightDirection, m_bounds.min, m_bounds.max);
}

DirectionalShadowMap& MainLightShadows::createMap(uint32_t size) {
    std::unique_ptr<DirectionalShadowMap>& map = m_maps[size];
    if (!map) {
        map = std::make_unique<DirectionalShadowMap>(m_device, size);
        map->fit(m_lightDirection, m_bounds.min, m_bounds.max);
        map->setCasters(m_casters);
        if (!m_maskedDraws.empty()) {
            if (!m_maskedPipelines.culled)
                m_maskedPipelines = m_gpuScene.createMeshPipelines(
                    makeShader(m_device, rhi::ShaderStage::Vertex, "forward_vert"),
                    makeShader(m_device, rhi::ShaderStage::Fragment, "depth_prepass_frag"), rhi::DepthState{true, true, rhi::CompareOp::LessOrEqual},
                    rhi::Format::Unknown, DirectionalShadowMap::kDepthFormat, false, "shadow (alpha-masked casters)",
                    DirectionalShadowMap::depthBias());
            MaskedView& view = m_maskedViews[size];
            view.frameUniforms = m_device.createBuffer(
                rhi::BufferDesc{}.setSize(sizeof(FrameUniforms)).setUsage(rhi::BufferUsage::Uniform).setDebugName("shadow masked casters view"));
            view.bindings = m_device.createBindingSet(
                rhi::BindingSetDesc{}.add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_FRAME_UNIFORMS, view.frameUniforms)));
        }
    }
    return *map;
}

void MainLightShadows::recordMap(rhi::ICommandList& cmd, uint32_t size, PassReport& report) {
    DirectionalShadowMap& map = *m_maps.at(size);
    if (m_maskedDraws.empty()) {
        map.record(cmd, m_casters, report.draws);
        return;
    }
    // The light's view-projection as the masked casters' view. The map is recorded only when
    // out of date (made, or refitted to another view-projection), so each recording uploads it.
    MaskedView& view = m_maskedViews.at(size);
    FrameUniforms frame{};
    frame.viewProjection = map.lightViewProjection();
    cmd.writeBuffer(view.frameUniforms, &frame, sizeof(frame));
    map.record(cmd, m_casters, report.draws,
               [&](rhi::ICommandList& pass) { m_gpuScene.drawSelected(pass, m_maskedDraws, m_maskedPipelines, view.bindings, report); });
}

const DirectionalShadowMap* MainLightShadows::map(uint32_t size) const {
    auto it = m_maps.find(size == 0 ? m_mapSize : size);
    return it == m_maps.end() ? nullptr : it->second.get();
}

void MainLightShadows::addPasses(PassGraph& graph, const SceneView& view) {
    if (!active()) return;
    const uint32_t size = view.passes.shadowMapSize == 0 ? m_mapSize : view.passes.shadowMapSize;
    const bool shared = size == m_mapSize;
    // One pass per size and graph; a non-default size is found by the views that asked for it.
    const std::string sizeKey = fmt::format("{}@{}", frame_resources::kShadowMap, size);
    const ViewTarget* existing = graph.find("", sizeKey);
    if (!existing) {
        const PassGraph::ResourceId shadowMap = graph.addResource(shared ? std::string(frame_resources::kShadowMap) : sizeKey);
        PassGraph::PassDesc pass;
        pass.name = "shadow-map";
        pass.writes = {shadowMap};
        pass.setup = [this, size] { createMap(size); };
        pass.record = [this, size](rhi::ICommandList& cmd, PassReport& report) { recordMap(cmd, size, report); };
        // Left out while the map already holds this scene under this light: nothing in a scene
        // moves once it is loaded, and setLights refits. A static scene draws its map once (in the
        // first graph of its first frame that reads it: the GI relight's, a probe capture's or
        // the frame's), and captures reuse the frame's.
        pass.skip = [this, size] {
            auto it = m_maps.find(size);
            return it != m_maps.end() && it->second->upToDate();
        };
        graph.addPass(std::move(pass));
        graph.publish("", sizeKey, ViewTarget{shadowMap, nullptr, {}});
        if (shared) graph.publish("", frame_resources::kShadowMap, ViewTarget{shadowMap, nullptr, {}});
        existing = graph.find("", sizeKey);
    }
    if (!shared) graph.publish(view.name, frame_resources::kShadowMap, *existing);
}

rhi::BindingItem MainLightShadows::binding(uint32_t slot) const {
    const DirectionalShadowMap* shared = map();
    return shared ? shared->binding(slot) : rhi::BindingItem::sampledTexture(slot, m_standInTexture, m_standInSampler);
}

}  // namespace janus::renderer
