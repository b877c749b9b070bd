// Renderer passes: the forward pass (frame and per-draw uniforms, material bindings, pipelines)
// and the depth prepass that shares its meshes and vertex shader, tonemap (compute or fullscreen
// triangle), and the tile heat map debug view; with the std140 mirrors of the uniform blocks they
// fill.
#include <algorithm>
#include <cstddef>
#include <cstring>
#include <vector>

#include <fmt/format.h>
#include <glm/gtc/matrix_inverse.hpp>

#include "janus/shaders/bindings.h"
#include "renderer_impl.h"

namespace janus::renderer {
namespace {

constexpr uint32_t kTonemapGroupSize = 8;       // tonemap.comp local_size

uint64_t alignUp(uint64_t value, uint64_t alignment) { return alignment ? (value + alignment - 1) / alignment * alignment : value; }

}  // namespace

// std140 mirrors of the blocks in shaders/renderer/forward_common.glsl and tonemap_common.glsl.
// Outside the unnamed namespace: renderer_impl.h declares FrameUniforms (frameUniformsFor returns it).
struct DirectionalLightData {
    glm::vec4 direction;        // w unused
    glm::vec4 colorIntensity;   // w renderingLayers as uint bits
};

struct FrameUniforms {
    glm::mat4 viewProjection;
    glm::mat4 worldToShadow;
    glm::vec4 cameraPosition;
    glm::vec4 ambientColor;
    glm::vec4 shadowParams;
    glm::ivec4 lightCounts;
    glm::ivec4 tileGrid;
    DirectionalLightData directionalLights[kMaxDirectionalLights];
};

struct HeatmapUniforms {
    glm::ivec4 grid;
};

struct DrawUniforms {
    glm::mat4 world;
    glm::mat4 normalMatrix;
    glm::vec4 baseColorFactor;
    glm::vec4 emissiveFactor;
    glm::vec4 materialParams;
    glm::ivec4 flags;
};

struct TonemapUniforms {
    glm::vec4 params;
};

static_assert(sizeof(Vertex) == 48 && offsetof(Vertex, normal) == 12 && offsetof(Vertex, uv) == 24 && offsetof(Vertex, tangent) == 32,
              "the forward pipeline's vertex layout assumes a tightly packed Vertex");
static_assert(sizeof(FrameUniforms) == 208 + 32 * kMaxDirectionalLights, "FrameUniforms must match std140");
static_assert(sizeof(DrawUniforms) == 192, "DrawUniforms must match std140");

FrameUniforms Renderer::Impl::frameUniformsFor(const Scene& scene) const {
    FrameUniforms frame{};
    const Camera& camera = scene.camera;
    frame.viewProjection = tileGrid.viewProjection();   // the same matrices the culling uses
    frame.cameraPosition = glm::vec4(camera.position, 1.0f);
    frame.ambientColor = glm::vec4(scene.environment.ambientColor, 0.0f);
    // The main directional light goes first: the shader shadows directional light 0.
    std::vector<const Light*> directional;
    for (const Light& light : scene.lights)
        if (light.type == LightType::Directional && directional.size() < kMaxDirectionalLights) directional.push_back(&light);
    if (const std::optional<size_t> main = mainDirectionalLight(scene, kMaxDirectionalLights)) {
        auto it = std::find(directional.begin(), directional.end(), &scene.lights[*main]);
        if (it != directional.end()) std::rotate(directional.begin(), it, it + 1);
    }
    for (size_t i = 0; i < directional.size(); ++i) {
        const Light& light = *directional[i];
        const uint32_t layers = light.renderingLayers;
        float layerBits;
        std::memcpy(&layerBits, &layers, sizeof(layerBits));
        frame.directionalLights[i].direction = glm::vec4(glm::normalize(light.direction), 0.0f);
        frame.directionalLights[i].colorIntensity = glm::vec4(light.color * light.intensity, layerBits);
    }
    if (shadowMap) {
        frame.worldToShadow = shadowMap->worldToShadow();
        frame.shadowParams = glm::vec4(1.0f, shadowMap->texelSize(), shadowMap->normalOffset(), 0.0f);
    }
    frame.lightCounts = glm::ivec4(int(directional.size()), int(localLights.size()), tiled() ? 1 : 0, 0);
    frame.tileGrid = glm::ivec4(int(lighting.tileSize), int(tilesX), int(lighting.maxLightsPerTile), int(tileCount()));
    return frame;
}

void Renderer::Impl::createForward(const Scene& scene) {
    const rhi::Capabilities& caps = device.capabilities();
    const FrameUniforms frame = frameUniformsFor(scene);
    frameUniforms = device.createBuffer(
        rhi::BufferDesc{}.setSize(sizeof(FrameUniforms)).setUsage(rhi::BufferUsage::Uniform).setDebugName("frame uniforms"));
    device.writeBuffer(frameUniforms, &frame, sizeof(frame));
    rhi::BindingSetDesc frameSet;
    frameSet.add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_FRAME_UNIFORMS, frameUniforms));
    if (settings.path == FeaturePath::Compute) {
        frameSet.add(rhi::BindingItem::storageBuffer(JANUS_BINDING_LOCAL_LIGHTS, localLightBuffer)).add(rhi::BindingItem::storageBuffer(JANUS_BINDING_TILE_LISTS, tileBuffer));
    } else {
        frameSet.add(rhi::BindingItem::sampledTexture(JANUS_BINDING_LOCAL_LIGHTS, localLightTexture, targetSampler))
            .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_TILE_LISTS, tileTexture, targetSampler));
    }
    frameSet.add(shadowMap ? shadowMap->binding(JANUS_BINDING_SHADOW_MAP) : rhi::BindingItem::sampledTexture(JANUS_BINDING_SHADOW_MAP, dummyShadowTexture, dummyShadowSampler));
    frameBindings = device.createBindingSet(frameSet);
    backgroundRadiance = {scene.environment.ambientColor.r, scene.environment.ambientColor.g, scene.environment.ambientColor.b, 1.0f};

    // One slot per draw in a single uniform buffer; each draw's binding set views its slot.
    const uint64_t stride = alignUp(sizeof(DrawUniforms), std::max<uint32_t>(caps.limits.uniformBufferOffsetAlignment, 16));
    std::vector<std::byte> drawData(std::max<size_t>(scene.instances.size(), 1) * stride);
    drawUniforms = device.createBuffer(
        rhi::BufferDesc{}.setSize(drawData.size()).setUsage(rhi::BufferUsage::Uniform).setDebugName("draw uniforms"));
    const Material defaultMaterial;
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        const Mesh& mesh = scene.meshes[instance.mesh];
        if (meshes[instance.mesh].indexCount == 0) continue;
        const Material& material = mesh.material >= 0 ? scene.materials[size_t(mesh.material)] : defaultMaterial;
        const bool hasTangents = std::any_of(mesh.vertices.begin(), mesh.vertices.end(),
                                             [](const Vertex& v) { return v.tangent != glm::vec4(0.0f); });
        DrawUniforms uniforms{};
        uniforms.world = instance.world;
        uniforms.normalMatrix = glm::inverseTranspose(instance.world);
        uniforms.baseColorFactor = material.baseColorFactor;
        uniforms.emissiveFactor = glm::vec4(material.emissiveFactor, material.alphaCutoff);
        uniforms.materialParams = glm::vec4(material.metallicFactor, material.roughnessFactor, 1.0f, 1.0f);
        // Normal maps need tangents; meshes without them shade with their vertex normals.
        uniforms.flags = glm::ivec4(material.doubleSided ? 1 : 0, hasTangents && material.normalTexture >= 0 ? 1 : 0,
                                    material.alphaMode == AlphaMode::Mask ? 1 : 0, int32_t(instance.renderingLayers));
        std::memcpy(drawData.data() + i * stride, &uniforms, sizeof(uniforms));

        auto texture = [&](uint32_t binding, int32_t index, const rhi::TextureHandle& fallback) {
            return index >= 0 ? rhi::BindingItem::sampledTexture(binding, textures[size_t(index)], textureSamplers[size_t(index)])
                              : rhi::BindingItem::sampledTexture(binding, fallback, materialSampler);
        };
        Draw draw;
        draw.mesh = instance.mesh;
        draw.doubleSided = material.doubleSided;
        draw.bindings = device.createBindingSet(
            rhi::BindingSetDesc{}
                .add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_DRAW_UNIFORMS, drawUniforms, i * stride, sizeof(DrawUniforms)))
                .add(texture(JANUS_BINDING_BASE_COLOR, material.baseColorTexture, whiteTexture))
                .add(texture(JANUS_BINDING_METALLIC_ROUGHNESS, material.metallicRoughnessTexture, whiteTexture))
                .add(texture(JANUS_BINDING_NORMAL, material.normalTexture, flatNormalTexture))
                .add(texture(JANUS_BINDING_OCCLUSION, material.occlusionTexture, whiteTexture))
                .add(texture(JANUS_BINDING_EMISSIVE, material.emissiveTexture, whiteTexture)));
        draws.push_back(std::move(draw));
    }
    device.writeBuffer(drawUniforms, drawData.data(), drawData.size());

    // Fewer pipeline switches: single-sided draws first, then double-sided ones.
    std::stable_sort(draws.begin(), draws.end(), [](const Draw& a, const Draw& b) { return !a.doubleSided && b.doubleSided; });

    const rhi::ShaderHandle vs = makeShader(device, rhi::ShaderStage::Vertex, "forward_vert");
    const rhi::ShaderHandle fs = makeShader(device, rhi::ShaderStage::Fragment,
                                            settings.path == FeaturePath::Compute ? "forward_frag" : "forward_textures_frag");
    const bool hasDoubleSided = std::any_of(draws.begin(), draws.end(), [](const Draw& d) { return d.doubleSided; });
    auto meshPipeline = [&](const rhi::ShaderHandle& fragment, rhi::CullMode cull, rhi::DepthState depth, bool color,
                            const char* name) {
        rhi::GraphicsPipelineDesc desc;
        desc.setShaders(vs, fragment)
            .addVertexBuffer({0, sizeof(Vertex), false})
            .addVertexAttribute({0, rhi::VertexFormat::Float3, 0, offsetof(Vertex, position)})
            .addVertexAttribute({1, rhi::VertexFormat::Float3, 0, offsetof(Vertex, normal)})
            .addVertexAttribute({2, rhi::VertexFormat::Float2, 0, offsetof(Vertex, uv)})
            .addVertexAttribute({3, rhi::VertexFormat::Float4, 0, offsetof(Vertex, tangent)})
            // glTF front faces are counter-clockwise; our projection keeps that as seen in the image.
            .setRaster(rhi::RasterState{cull, rhi::FrontFace::CounterClockwise})
            .setDepth(depth)
            .setDepthFormat(rhi::Format::D32_FLOAT)
            .setDebugName(name);
        if (color) desc.addColorFormat(rhi::Format::RGBA16_FLOAT);
        return device.createGraphicsPipeline(desc);
    };
    // After a depth prepass the forward pass only shades the surfaces the prepass kept
    // (forward.vert's invariant position gives both the same depth bits).
    const rhi::DepthState forwardDepth =
        tiled() ? rhi::DepthState{true, false, rhi::CompareOp::LessOrEqual} : rhi::DepthState{true, true, rhi::CompareOp::Less};
    forwardCulled = meshPipeline(fs, rhi::CullMode::Back, forwardDepth, true, "forward (back-face culled)");
    if (hasDoubleSided) forwardDoubleSided = meshPipeline(fs, rhi::CullMode::None, forwardDepth, true, "forward (double-sided)");
    if (tiled()) {
        const rhi::ShaderHandle prepassFs = makeShader(device, rhi::ShaderStage::Fragment, "depth_prepass_frag");
        const rhi::DepthState prepassDepth{true, true, rhi::CompareOp::Less};
        prepassCulled = meshPipeline(prepassFs, rhi::CullMode::Back, prepassDepth, false, "depth prepass (back-face culled)");
        if (hasDoubleSided)
            prepassDoubleSided = meshPipeline(prepassFs, rhi::CullMode::None, prepassDepth, false, "depth prepass (double-sided)");
    }
}

void Renderer::Impl::recordMeshes(rhi::ICommandList& cmd, PassReport& report, const rhi::PipelineHandle& culled,
                                  const rhi::PipelineHandle& doubleSided) {
    const rhi::IPipeline* bound = nullptr;
    for (const Draw& draw : draws) {
        const rhi::PipelineHandle& pipeline = draw.doubleSided ? doubleSided : culled;
        if (pipeline.get() != bound) {
            cmd.setPipeline(pipeline);
            cmd.setBindingSet(JANUS_SET_VIEW, frameBindings);
            bound = pipeline.get();
        }
        const GpuMesh& mesh = meshes[draw.mesh];
        cmd.setBindingSet(JANUS_SET_DRAW, draw.bindings);
        cmd.setVertexBuffer(0, mesh.vertices);
        cmd.setIndexBuffer(mesh.indices, rhi::IndexType::UInt32);
        cmd.drawIndexed(mesh.indexCount);
        ++report.draws;
    }
}

void Renderer::Impl::recordDepthPrepass(rhi::ICommandList& cmd, PassReport& report) {
    cmd.beginRenderPass(rhi::RenderPassDesc{}.setDepth(rhi::Attachment::clearDepthTo(depthTarget, 1.0f)));
    recordMeshes(cmd, report, prepassCulled, prepassDoubleSided);
    cmd.endRenderPass();
}

void Renderer::Impl::recordForward(rhi::ICommandList& cmd, PassReport& report) {
    cmd.beginRenderPass(rhi::RenderPassDesc{}
                            .addColor(rhi::Attachment::clear(hdrTarget, backgroundRadiance))
                            .setDepth(tiled() ? rhi::Attachment::load(depthTarget) : rhi::Attachment::clearDepthTo(depthTarget, 1.0f)));
    recordMeshes(cmd, report, forwardCulled, forwardDoubleSided);
    cmd.endRenderPass();
}

void Renderer::Impl::createTonemap(const Scene& scene) {
    const TonemapUniforms uniforms{glm::vec4(scene.environment.exposure, 0.0f, 0.0f, 0.0f)};
    tonemapUniforms = device.createBuffer(
        rhi::BufferDesc{}.setSize(sizeof(uniforms)).setUsage(rhi::BufferUsage::Uniform).setDebugName("tonemap uniforms"));
    device.writeBuffer(tonemapUniforms, &uniforms, sizeof(uniforms));
    rhi::BindingSetDesc bindings;
    bindings.add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_TONEMAP_UNIFORMS, tonemapUniforms)).add(rhi::BindingItem::sampledTexture(JANUS_BINDING_TONEMAP_HDR, hdrTarget, targetSampler));
    if (settings.path == FeaturePath::Compute) {
        bindings.add(rhi::BindingItem::storageImage(JANUS_BINDING_TONEMAP_DISPLAY, displayImage));
        tonemapPipeline = device.createComputePipeline(
            rhi::ComputePipelineDesc{}.setShader(makeShader(device, rhi::ShaderStage::Compute, "tonemap_comp")).setDebugName("tonemap"));
    } else {
        tonemapPipeline = device.createGraphicsPipeline(
            rhi::GraphicsPipelineDesc{}
                .setShaders(makeShader(device, rhi::ShaderStage::Vertex, "fullscreen_vert"),
                            makeShader(device, rhi::ShaderStage::Fragment, "tonemap_frag"))
                .addColorFormat(rhi::Format::RGBA8_UNORM)
                .setDebugName("tonemap"));
    }
    tonemapBindings = device.createBindingSet(bindings);
}

void Renderer::Impl::recordTonemapCompute(rhi::ICommandList& cmd, PassReport& report) {
    cmd.setPipeline(tonemapPipeline);
    cmd.setBindingSet(0, tonemapBindings);
    cmd.dispatch((settings.width + kTonemapGroupSize - 1) / kTonemapGroupSize,
                 (settings.height + kTonemapGroupSize - 1) / kTonemapGroupSize);
    ++report.dispatches;
}

void Renderer::Impl::recordTonemapFallback(rhi::ICommandList& cmd, PassReport& report) {
    // Every pixel is written, so the previous contents do not matter.
    rhi::Attachment target = rhi::Attachment::clear(displayImage);
    target.loadOp = rhi::LoadOp::DontCare;
    cmd.beginRenderPass(rhi::RenderPassDesc{}.addColor(target));
    cmd.setPipeline(tonemapPipeline);
    cmd.setBindingSet(0, tonemapBindings);
    cmd.draw(3);
    ++report.draws;
    cmd.endRenderPass();
}

void Renderer::Impl::createHeatmap() {
    if (settings.debugView != DebugView::Tiles) return;
    if (!tiled()) {
        fmt::print(stderr, "janus renderer: warning: no tiles to show: the frame uses {} light culling ({}); the tile debug view "
                           "needs tiles-2d or tiles-depth and point/spot lights\n",
                   toString(cullingMode), localLights.empty() ? "the scene has no point or spot lights" : "no tile lists");
        return;
    }
    const HeatmapUniforms uniforms{glm::ivec4(int(lighting.tileSize), int(tilesX), int(lighting.maxLightsPerTile), int(tileCount()))};
    heatmapUniforms = device.createBuffer(
        rhi::BufferDesc{}.setSize(sizeof(uniforms)).setUsage(rhi::BufferUsage::Uniform).setDebugName("heat map uniforms"));
    device.writeBuffer(heatmapUniforms, &uniforms, sizeof(uniforms));
    rhi::BindingSetDesc bindings;
    bindings.add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_HEATMAP_UNIFORMS, heatmapUniforms));
    if (settings.path == FeaturePath::Compute)
        bindings.add(rhi::BindingItem::storageBuffer(JANUS_BINDING_TILE_LISTS, tileBuffer));
    else
        bindings.add(rhi::BindingItem::sampledTexture(JANUS_BINDING_TILE_LISTS, tileTexture, targetSampler));
    heatmapBindings = device.createBindingSet(bindings);
    heatmapPipeline = device.createGraphicsPipeline(
        rhi::GraphicsPipelineDesc{}
            .setShaders(makeShader(device, rhi::ShaderStage::Vertex, "fullscreen_vert"),
                        makeShader(device, rhi::ShaderStage::Fragment,
                                   settings.path == FeaturePath::Compute ? "tile_heatmap_frag" : "tile_heatmap_textures_frag"))
            .addColorFormat(rhi::Format::RGBA8_UNORM, rhi::BlendAttachment::alpha())
            .setDebugName("tile heat map"));
}

void Renderer::Impl::recordHeatmap(rhi::ICommandList& cmd, PassReport& report) {
    cmd.beginRenderPass(rhi::RenderPassDesc{}.addColor(rhi::Attachment::load(displayImage)));
    cmd.setPipeline(heatmapPipeline);
    cmd.setBindingSet(0, heatmapBindings);
    cmd.draw(3);
    ++report.draws;
    cmd.endRenderPass();
}

}  // namespace janus::renderer
