// Directional shadow map: orthographic fit, depth-only pass, compare sampler. See docs/SHADOWS.md.
#include "shadow_map.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "core/gpu_util.h"
#include "janus/renderer/renderer.h"
#include "scene/scene_internal.h"
#include "janus/renderer/scene.h"
#include "janus/renderer/settings.h"
#include "janus/shaders/bindings.h"

namespace janus::renderer {
namespace {

// Texels kept free on each side of the fitted bounds: one for the snap, one for the PCF kernel.
constexpr float kBorderTexels = 2.0f;

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

WorldBounds sceneWorldBounds(const Scene& scene) {
    // Per mesh once: the local box, whose 8 transformed corners bound each instance.
    std::vector<WorldBounds> local(scene.meshes.size());
    for (size_t m = 0; m < scene.meshes.size(); ++m)
        for (const Vertex& v : scene.meshes[m].vertices) {
            local[m].min = glm::min(local[m].min, v.position);
            local[m].max = glm::max(local[m].max, v.position);
        }
    WorldBounds bounds;
    for (const Instance& instance : scene.instances) {
        if (instance.mesh >= local.size() || local[instance.mesh].empty()) continue;
        if (detail::isDeformed(scene, instance)) {   // where the pose puts it, not its bind pose
            if (const std::optional<Box> box = detail::instanceBounds(scene, instance)) {
                bounds.min = glm::min(bounds.min, box->min);
                bounds.max = glm::max(bounds.max, box->max);
            }
            continue;
        }
        const WorldBounds& box = local[instance.mesh];
        for (int corner = 0; corner < 8; ++corner) {
            const glm::vec3 p((corner & 1) ? box.max.x : box.min.x, (corner & 2) ? box.max.y : box.min.y,
                              (corner & 4) ? box.max.z : box.min.z);
            const glm::vec3 w = glm::vec3(instance.world * glm::vec4(p, 1.0f));
            bounds.min = glm::min(bounds.min, w);
            bounds.max = glm::max(bounds.max, w);
        }
    }
    return bounds;
}

std::optional<size_t> mainDirectionalLight(const Scene& scene, uint32_t shadedDirectionalLights) {
    return mainDirectionalLight(std::span<const Light>(scene.lights), shadedDirectionalLights);
}

std::optional<size_t> mainDirectionalLight(std::span<const Light> lights, uint32_t shadedDirectionalLights) {
    std::optional<size_t> main;
    float brightest = 0.0f;
    uint32_t seen = 0;
    for (size_t i = 0; i < lights.size() && seen < shadedDirectionalLights; ++i) {
        const Light& light = lights[i];
        if (light.type != LightType::Directional) continue;
        ++seen;
        const float brightness = std::max({light.color.r, light.color.g, light.color.b}) * light.intensity;
        if (brightness > brightest) {
            brightest = brightness;
            main = i;
        }
    }
    return main;
}

DirectionalShadowMap::DirectionalShadowMap(rhi::IDevice& device, uint32_t size) : m_device(device), m_size(size) {
    const uint32_t maxSize = device.capabilities().limits.maxTextureSize2D;
    if (size < kMinSize || size > maxSize)
        throw RendererError(fmt::format("shadow map size {} is not possible on this {} device: it must be between {} and the "
                                        "maximum 2D texture size {}",
                                        size, rhi::toString(device.info().backend), kMinSize, maxSize));
    static_assert(sizeof(Vertex) == 80 && offsetof(Vertex, position) == 0, "the shadow pass reads positions from renderer Vertex");

    m_depth = device.createTexture(rhi::TextureDesc{}
                                       .setFormat(kDepthFormat)
                                       .setSize(size, size)
                                       .setUsage(rhi::TextureUsage::RenderTarget | rhi::TextureUsage::Sampled)
                                       .setDebugName("directional shadow map"));
    // Linear filtering on a compare sampler filters the four comparison results (hardware 2x2
    // PCF); clamp-to-edge keeps taps just outside the map on the border texels.
    rhi::SamplerDesc sampler;
    sampler.setFilter(rhi::Filter::Linear).setAddress(rhi::AddressMode::ClampToEdge).setLodRange(0.0f, 0.0f);
    sampler.mipFilter = rhi::Filter::Nearest;
    sampler.setCompare(rhi::CompareOp::LessOrEqual);
    m_compareSampler = device.createSampler(sampler);

    m_passUniforms = device.createBuffer(
        rhi::BufferDesc{}.setSize(sizeof(glm::mat4)).setUsage(rhi::BufferUsage::Uniform).setDebugName("shadow pass uniforms"));
    m_passBindings = device.createBindingSet(rhi::BindingSetDesc{}.add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_SHADOW_PASS, m_passUniforms)));
    m_casterStride = alignUp(sizeof(glm::mat4), std::max<uint32_t>(device.capabilities().limits.uniformBufferOffsetAlignment, 16));

    const rhi::ShaderHandle vs = makeShader(device, rhi::ShaderStage::Vertex, "shadow_vert");
    const rhi::ShaderHandle fs = makeShader(device, rhi::ShaderStage::Fragment, "shadow_frag");
    auto pipeline = [&](rhi::CullMode cull, bool mirroredCaster, const char* name) {
        rhi::RasterState raster = depthBias();
        raster.cullMode = cull;
        // The light's projection has the same handedness and y flip as the camera's, so glTF
        // counter-clockwise front faces stay counter-clockwise as seen in the map (clockwise for
        // a mirrored caster).
        raster.frontFace = mirroredCaster ? rhi::FrontFace::Clockwise : rhi::FrontFace::CounterClockwise;
        return device.createGraphicsPipeline(rhi::GraphicsPipelineDesc{}
                                                 .setShaders(vs, fs)
                                                 .addDynamicUniformBuffer(1, JANUS_BINDING_SHADOW_CASTER)
                                                 .addVertexBuffer({0, sizeof(Vertex), false})
                                                 .addVertexAttribute({0, rhi::VertexFormat::Float3, 0, offsetof(Vertex, position)})
                                                 .setRaster(raster)
                                                 .setDepth(rhi::DepthState{true, true, rhi::CompareOp::LessOrEqual})
                                                 .setDepthFormat(kDepthFormat)
                                                 .setDebugName(name));
    };
    m_culledPipeline = pipeline(rhi::CullMode::Back, false, "shadow (back-face culled)");
    m_doubleSidedPipeline = pipeline(rhi::CullMode::None, false, "shadow (double-sided)");
    m_culledMirroredPipeline = pipeline(rhi::CullMode::Back, true, "shadow (back-face culled, mirrored casters)");
}

void DirectionalShadowMap::fit(const glm::vec3& lightDirection, const glm::vec3& sceneMin, const glm::vec3& sceneMax) {
    if (!finite(lightDirection) || !(glm::length(glm::dvec3(lightDirection)) > 1e-30))
        throw RendererError(fmt::format("shadow map: the light direction ({}, {}, {}) is zero or not finite", lightDirection.x,
                                        lightDirection.y, lightDirection.z));
    if (!finite(sceneMin) || !finite(sceneMax))
        throw RendererError("shadow map: the scene bounds are not finite");
    // Doubles: light space is anchored at the world origin (below), so a scene far from it would
    // lose the snap and the border to float rounding. The result is rounded to float once.
    const glm::dvec3 direction = glm::normalize(glm::dvec3(lightDirection));
    const glm::dvec3 center = (glm::dvec3(sceneMin) + glm::dvec3(sceneMax)) * 0.5;
    // An inverted (empty) box collapses to its centre.
    const glm::dvec3 lo = glm::min(glm::dvec3(sceneMin), center), hi = glm::max(glm::dvec3(sceneMax), center);

    // Any up vector not parallel to the light; which one only rotates the map. The view is a pure
    // rotation about the world origin, so light space (and the texel grid snapped in it below)
    // does not move with the bounds.
    const glm::dvec3 up = std::abs(direction.y) > 0.99 ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(0.0, 1.0, 0.0);
    const glm::dmat4 view = glm::lookAt(glm::dvec3(0.0), direction, up);

    glm::dvec3 viewMin(INFINITY), viewMax(-INFINITY);
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 p((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z);
        const glm::dvec3 v = glm::dvec3(view * glm::dvec4(p, 1.0));
        viewMin = glm::min(viewMin, v);
        viewMax = glm::max(viewMax, v);
    }

    // Square texels: the larger of the two extents, plus the border. A floor relative to the
    // scene's size and distance keeps a point (or edge-on flat) scene from giving a zero-sized
    // projection, and keeps a texel above the float precision of the world positions.
    const double scale = std::max({glm::length(hi - lo), glm::length(center), 1.0});
    const double rawExtent = std::max({viewMax.x - viewMin.x, viewMax.y - viewMin.y, scale * 1e-4});
    const double texel = rawExtent / (double(m_size) - 2.0 * kBorderTexels);
    const double extent = texel * double(m_size);
    // Snapping the window's corner to whole texels of light space keeps the texel grid fixed to
    // the world while the bounds move, so shadow edges do not crawl.
    const double left = std::floor(((viewMin.x + viewMax.x) * 0.5 - extent * 0.5) / texel) * texel;
    const double bottom = std::floor(((viewMin.y + viewMax.y) * 0.5 - extent * 0.5) / texel) * texel;

    // View space looks down -Z: the nearest corner has the largest z. A little depth margin keeps
    // geometry lying on the bounds from being clipped by float error.
    const double depthMargin = std::max((viewMax.z - viewMin.z) * 1e-3, scale * 1e-5);
    const double nearPlane = -viewMax.z - depthMargin, farPlane = -viewMin.z + depthMargin;
    glm::dmat4 projection = glm::orthoRH_ZO(left, left + extent, bottom, bottom + extent, nearPlane, farPlane);
    // Vulkan convention, as for the camera: light-space up lands on NDC y = -1, row 0.
    projection[1][1] *= -1.0;
    projection[3][1] *= -1.0;

    const glm::mat4 lightViewProjection(projection * view);
    if (!m_fitted || lightViewProjection != m_lightViewProjection) m_upToDate = false;
    m_lightViewProjection = lightViewProjection;
    m_lightDirection = glm::vec3(direction);
    m_texelWorldSize = float(texel);
    m_fitted = true;
    m_passUniformsDirty = true;
}

glm::mat4 DirectionalShadowMap::worldToShadow() const {
    // Clip (x, y in [-1, 1], z in [0, 1]) -> (u, v, depth). NDC y = -1 is row 0 and v = 0 is
    // row 0, so v follows y without a flip.
    glm::mat4 clipToTexture(1.0f);
    clipToTexture[0][0] = 0.5f;
    clipToTexture[1][1] = 0.5f;
    clipToTexture[3][0] = 0.5f;
    clipToTexture[3][1] = 0.5f;
    return clipToTexture * m_lightViewProjection;
}

void DirectionalShadowMap::setCasters(std::span<const ShadowCaster> casters) {
    const size_t slots = std::max<size_t>(casters.size(), 1);
    m_casterUniforms = m_device.createBuffer(rhi::BufferDesc{}
                                                 .setSize(slots * m_casterStride)
                                                 .setUsage(rhi::BufferUsage::Uniform)
                                                 .setDebugName("shadow caster uniforms"));
    std::vector<std::byte> data(slots * m_casterStride);
    m_casterWorlds.clear();
    for (size_t i = 0; i < casters.size(); ++i) {
        std::memcpy(data.data() + i * m_casterStride, &casters[i].world, sizeof(glm::mat4));
        m_casterWorlds.push_back(casters[i].world);
    }
    m_casterBindings = m_device.createBindingSet(rhi::BindingSetDesc{}.add(
        rhi::BindingItem::uniformBuffer(JANUS_BINDING_SHADOW_CASTER, m_casterUniforms, 0, sizeof(glm::mat4)).setDynamicOffset()));
    m_casterSlots = casters.size();
    m_device.writeBuffer(m_casterUniforms, data.data(), data.size());
    m_upToDate = false;
}

void DirectionalShadowMap::uploadPassUniforms(rhi::ICommandList& cmd) {
    if (!m_passUniformsDirty) return;
    cmd.writeBuffer(m_passUniforms, &m_lightViewProjection, sizeof(glm::mat4));
    m_passUniformsDirty = false;
}

rhi::RasterState DirectionalShadowMap::depthBias() {
    rhi::RasterState raster;
    raster.depthBiasEnable = true;
    raster.depthBiasConstant = kDepthBiasConstant;
    raster.depthBiasSlope = kDepthBiasSlope;
    return raster;
}

void DirectionalShadowMap::record(rhi::ICommandList& cmd, std::span<const ShadowCaster> casters, uint32_t& drawCount,
                                  const std::function<void(rhi::ICommandList&)>& drawInPass) {
    if (!m_fitted) throw RendererError("DirectionalShadowMap::record() was called before fit(); fit the map to the scene first");
    if (casters.size() > m_casterSlots) setCasters(casters);
    uploadPassUniforms(cmd);
    // Moved casters: one copy of the changed slot range, recorded before the pass.
    size_t firstChanged = casters.size(), lastChanged = 0;
    for (size_t i = 0; i < casters.size(); ++i) {
        if (std::memcmp(&casters[i].world, &m_casterWorlds[i], sizeof(glm::mat4)) == 0) continue;
        m_casterWorlds[i] = casters[i].world;
        firstChanged = std::min(firstChanged, i);
        lastChanged = i;
    }
    if (firstChanged < casters.size()) {
        std::vector<std::byte> data((lastChanged - firstChanged + 1) * m_casterStride);
        for (size_t i = firstChanged; i <= lastChanged; ++i)
            std::memcpy(data.data() + (i - firstChanged) * m_casterStride, &m_casterWorlds[i], sizeof(glm::mat4));
        cmd.writeBuffer(m_casterUniforms, data.data(), data.size(), firstChanged * m_casterStride);
    }

    cmd.beginRenderPass(rhi::RenderPassDesc{}.setDepth(rhi::Attachment::clearDepthTo(m_depth, 1.0f)));
    const rhi::IPipeline* bound = nullptr;
    const rhi::IBuffer* boundVertices = nullptr;
    const rhi::IBuffer* boundIndices = nullptr;
    for (size_t i = 0; i < casters.size(); ++i) {
        const ShadowCaster& caster = casters[i];
        if (caster.indexCount == 0 || !caster.vertices || !caster.indices) continue;
        const bool mirrored = glm::determinant(glm::mat3(caster.world)) < 0.0f;
        const rhi::PipelineHandle& pipeline =
            caster.doubleSided ? m_doubleSidedPipeline : (mirrored ? m_culledMirroredPipeline : m_culledPipeline);
        if (pipeline.get() != bound) {
            cmd.setPipeline(pipeline);
            cmd.setBindingSet(0, m_passBindings);
            bound = pipeline.get();
            boundVertices = boundIndices = nullptr;
        }
        const uint32_t slot = uint32_t(i * m_casterStride);
        cmd.setBindingSet(1, m_casterBindings, std::span(&slot, 1));
        // Casters of one mesh follow each other (MainLightShadows groups them): its buffers stay bound.
        if (caster.vertices.get() != boundVertices) {
            cmd.setVertexBuffer(0, caster.vertices);
            boundVertices = caster.vertices.get();
        }
        if (caster.indices.get() != boundIndices) {
            cmd.setIndexBuffer(caster.indices, rhi::IndexType::UInt32);
            boundIndices = caster.indices.get();
        }
        cmd.drawIndexed(caster.indexCount);
        ++drawCount;
    }
    if (drawInPass) drawInPass(cmd);
    cmd.endRenderPass();
    m_upToDate = true;
}

rhi::BindingItem DirectionalShadowMap::binding(uint32_t slot) const {
    return rhi::BindingItem::sampledTexture(slot, m_depth, m_compareSampler);
}

}  // namespace janus::renderer
