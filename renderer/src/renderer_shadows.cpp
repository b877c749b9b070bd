// Renderer shadows: the shadow casters and the main directional light's shadow map
// (shadow_map.h, docs/SHADOWS.md), or the stand-in bound when nothing casts shadows.
#include <memory>
#include <optional>

#include "renderer_impl.h"

namespace janus::renderer {

void Renderer::Impl::createShadows(const Scene& scene) {
    dummyShadowTexture = device.createTexture(rhi::TextureDesc{}
                                                  .setFormat(DirectionalShadowMap::kDepthFormat)
                                                  .setSize(1, 1)
                                                  .setUsage(rhi::TextureUsage::Sampled | rhi::TextureUsage::RenderTarget)
                                                  .setDebugName("no shadow map"));
    dummyShadowSampler = device.createSampler(rhi::SamplerDesc{}
                                                  .setFilter(rhi::Filter::Nearest)
                                                  .setAddress(rhi::AddressMode::ClampToEdge)
                                                  .setCompare(rhi::CompareOp::LessOrEqual));
    if (!lighting.shadows) return;
    const std::optional<size_t> main = mainDirectionalLight(scene, kMaxDirectionalLights);
    if (!main) return;
    const WorldBounds bounds = sceneWorldBounds(scene);
    if (bounds.empty()) return;
    const Material defaultMaterial;
    for (const Instance& instance : scene.instances) {
        const GpuMesh& mesh = meshes[instance.mesh];
        if (mesh.indexCount == 0) continue;
        const Mesh& sceneMesh = scene.meshes[instance.mesh];
        const Material& material = sceneMesh.material >= 0 ? scene.materials[size_t(sceneMesh.material)] : defaultMaterial;
        shadowCasters.push_back(ShadowCaster{mesh.vertices, mesh.indices, mesh.indexCount, instance.world, material.doubleSided});
    }
    if (shadowCasters.empty()) return;
    shadowMap = std::make_unique<DirectionalShadowMap>(device, lighting.shadowMapSize);
    shadowMap->fit(scene.lights[*main].direction, bounds.min, bounds.max);
    shadowMap->setCasters(shadowCasters);
}

void Renderer::Impl::recordShadowMap(rhi::ICommandList& cmd, PassReport& report) { shadowMap->record(cmd, shadowCasters, report.draws); }

}  // namespace janus::renderer
