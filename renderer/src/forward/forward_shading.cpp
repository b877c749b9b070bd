// Forward shading: per-view frame uniforms and bindings, the depth prepass and the forward pass.
// GGX + height-correlated Smith + Schlick + Lambert in shaders/renderer/forward.frag.
#include "forward/forward_shading.h"

#include <algorithm>
#include <cstring>

#include <fmt/format.h>

#include "core/gpu_util.h"
#include "janus/shaders/bindings.h"

namespace janus::renderer {

namespace {

// forward.frag's variants: lights in storage buffers (compute path) or textures (fallback), and
// reflection probes in a cube array or, without cube arrays, two cubes.
const char* forwardShaderName(FeaturePath path, bool probeCubes) {
    if (path == FeaturePath::Compute) return probeCubes ? "forward_cubes_frag" : "forward_frag";
    return probeCubes ? "forward_textures_cubes_frag" : "forward_textures_frag";
}

}  // namespace

FrameUniforms sceneFrameUniforms(const Scene& scene) { return sceneFrameUniforms(scene.lights, scene.environment.ambientColor); }

FrameUniforms sceneFrameUniforms(std::span<const Light> lights, const glm::vec3& ambientColor) {
    FrameUniforms uniforms{};
    uniforms.ambientColor = glm::vec4(ambientColor, 0.0f);
    // The main directional light goes first: the shader shadows directional light 0.
    std::vector<const Light*> directional;
    for (const Light& light : lights)
        if (light.type == LightType::Directional && directional.size() < kMaxDirectionalLights) directional.push_back(&light);
    if (const std::optional<size_t> main = mainDirectionalLight(lights, kMaxDirectionalLights)) {
        auto it = std::find(directional.begin(), directional.end(), &lights[*main]);
        if (it != directional.end()) std::rotate(directional.begin(), it, it + 1);
    }
    for (size_t i = 0; i < directional.size(); ++i) {
        const Light& light = *directional[i];
        const uint32_t layers = light.renderingLayers;
        float layerBits;
        std::memcpy(&layerBits, &layers, sizeof(layerBits));
        uniforms.directionalLights[i].direction = glm::vec4(glm::normalize(light.direction), 0.0f);
        uniforms.directionalLights[i].colorIntensity = glm::vec4(light.color * light.intensity, layerBits);
    }
    uniforms.lightCounts.x = int(directional.size());
    return uniforms;
}

ForwardShading::ForwardShading(rhi::IDevice& device, const Scene& scene, const GpuScene& gpuScene, LocalLights& localLights,
                               MainLightShadows& shadows, const ImageBasedLighting& imageBasedLighting,
                               const ReflectionProbes& reflectionProbes, const ProbeGi& probeGi, FeaturePath path)
    : m_device(device),
      m_gpuScene(gpuScene),
      m_localLights(localLights),
      m_shadows(shadows),
      m_imageBasedLighting(imageBasedLighting),
      m_reflectionProbes(reflectionProbes),
      m_probeGi(probeGi),
      m_path(path) {
    const glm::vec3 ambient = scene.environment.ambientColor;
    m_background = {ambient.r, ambient.g, ambient.b, 1.0f};
    m_sceneUniforms = sceneFrameUniforms(scene);

    m_vertexShader = makeShader(device, rhi::ShaderStage::Vertex, "forward_vert");
    m_forwardShader = makeShader(device, rhi::ShaderStage::Fragment, forwardShaderName(path, reflectionProbes.separateCubes()));
}

void ForwardShading::addPasses(PassGraph& graph, const SceneView& view) {
    const ViewTarget* colorTarget = graph.find(view.name, frame_resources::kHdr);
    const ViewTarget* depthTarget = graph.find(view.name, frame_resources::kDepth);
    if (!colorTarget || !depthTarget)
        throw RendererError(fmt::format("forward shading: view '{}' has no '{}' and '{}' targets", view.name, frame_resources::kHdr,
                                        frame_resources::kDepth));
    const ViewTarget color = *colorTarget, depth = *depthTarget;
    std::optional<PassGraph::ResourceId> shadowMap;
    if (const ViewTarget* shadows = graph.find(view.name, frame_resources::kShadowMap)) shadowMap = shadows->resource;
    // A view rendered again (each cube capture re-adds its faces) reuses its state, so repeated
    // captures do not accumulate uniform buffers; the graph that referred to it is gone by then.
    auto it = std::find_if(m_views.begin(), m_views.end(), [&](const auto& s) { return s->view.name == view.name; });
    if (it == m_views.end()) it = m_views.insert(m_views.end(), std::make_unique<ViewState>());
    ViewState& state = **it;
    state = ViewState{};
    state.view = view;
    state.tiled = m_localLights.tiledFor(view);
    state.shadowed = view.passes.shadows && shadowMap.has_value();
    state.color = color;
    state.depth = depth;

    std::optional<PassGraph::ResourceId> tileLists;
    if (state.tiled) {
        PassGraph::PassDesc prepass;
        prepass.name = "depth-prepass";
        prepass.view = view.name;
        prepass.writes = {depth.resource};
        prepass.setup = [this, &state] { pipelines(MeshPass::Prepass, state); };
        prepass.record = [this, &state](rhi::ICommandList& cmd, PassReport& report) { recordPrepass(state, cmd, report); };
        graph.addPass(std::move(prepass));
        tileLists = m_localLights.addCullingPass(graph, depth.resource, depth.texture);
        graph.publish(view.name, frame_resources::kTileLists, ViewTarget{*tileLists, nullptr, {}});
    }

    if (state.tiled) state.lightingInputs.push_back(*tileLists);
    if (state.shadowed) state.lightingInputs.push_back(*shadowMap);
    if (const ViewTarget* sky = graph.find(view.name, ibl_resources::kSkyLight)) state.lightingInputs.push_back(sky->resource);
    if (view.passes.reflectionProbes)
        if (const ViewTarget* probes = graph.find(view.name, probe_resources::kReflectionProbes))
            state.lightingInputs.push_back(probes->resource);
    if (const ViewTarget* volume = graph.find(view.name, gi_resources::kIrradianceVolume)) state.lightingInputs.push_back(volume->resource);

    PassGraph::PassDesc forward;
    forward.name = "forward";
    forward.view = view.name;
    if (state.tiled) forward.reads = {depth.resource};
    forward.reads.insert(forward.reads.end(), state.lightingInputs.begin(), state.lightingInputs.end());
    forward.writes = {color.resource, depth.resource};
    forward.setup = [this, &state] { setupView(state); };
    forward.record = [this, &state](rhi::ICommandList& cmd, PassReport& report) { recordForward(state, cmd, report); };
    graph.addPass(std::move(forward));
}

const ForwardShading::ViewState& ForwardShading::stateOf(const std::string& viewName) const {
    auto it = std::find_if(m_views.begin(), m_views.end(), [&](const auto& s) { return s->view.name == viewName; });
    if (it == m_views.end())
        throw RendererError(fmt::format("forward shading: view '{}' has no forward pass; add the forward shading feature before the "
                                        "features that shade with it",
                                        viewName));
    return **it;
}

const std::vector<PassGraph::ResourceId>& ForwardShading::lightingInputs(const std::string& viewName) const {
    return stateOf(viewName).lightingInputs;
}

const rhi::BindingSetHandle& ForwardShading::viewBindings(const std::string& viewName) const {
    const ViewState& state = stateOf(viewName);
    if (!state.bindings)
        throw RendererError(fmt::format("forward shading: view '{}' is not set up yet (its forward pass was culled or not compiled)",
                                        viewName));
    return state.bindings;
}

FrameUniforms ForwardShading::viewFrameUniforms(const ViewState& state) const {
    const SceneView& view = state.view;
    FrameUniforms frame = m_sceneUniforms;
    frame.viewProjection = view.viewProjection();   // for the tiled view, the matrices the culling uses
    frame.cameraPosition = view.homogeneousCamera();   // orthographic: every surface sees the camera in one direction
    if (const DirectionalShadowMap* map = state.shadowed ? m_shadows.map(view.passes.shadowMapSize) : nullptr) {
        frame.worldToShadow = map->worldToShadow();
        frame.shadowParams = glm::vec4(1.0f, map->texelSize(), map->normalOffset(), 0.0f);
    }
    const ResolvedLighting& lighting = m_localLights.lighting();
    frame.lightCounts = glm::ivec4(frame.lightCounts.x, int(m_localLights.count()), state.tiled ? 1 : 0, view.alphaToCoverage ? 1 : 0);
    frame.tileGrid = glm::ivec4(int(lighting.tileSize), state.tiled ? int(m_localLights.tilesX()) : 0, int(lighting.maxLightsPerTile),
                                state.tiled ? int(m_localLights.tileCount()) : 0);
    frame.skyParams = m_imageBasedLighting.shadingParams();
    // forward.frag's debug outputs: 1 the volume's light, 2 the main light's shadow-map visibility.
    frame.skyParams.w = view.debugView == DebugView::Gi || view.debugView == DebugView::GiLight ? 1.0f
                        : view.debugView == DebugView::Shadow                                  ? 2.0f
                                                                                                : 0.0f;
    return frame;
}

void ForwardShading::setLights(std::span<const Light> lights) {
    m_sceneUniforms = sceneFrameUniforms(lights, glm::vec3(m_sceneUniforms.ambientColor));
    // Views set up already keep their buffers (their binding sets hold them): new contents only.
    // A cube capture's views are set up again at each capture anyway.
    for (const std::unique_ptr<ViewState>& state : m_views)
        if (state->frameUniforms) {
            const FrameUniforms frame = viewFrameUniforms(*state);
            m_device.writeBuffer(state->frameUniforms, &frame, sizeof(frame));
        }
}

void ForwardShading::setupView(ViewState& state) {
    const SceneView& view = state.view;
    const DirectionalShadowMap* map = state.shadowed ? m_shadows.map(view.passes.shadowMapSize) : nullptr;
    state.frameUniforms = makeUniformBuffer(m_device, viewFrameUniforms(state), fmt::format("frame uniforms ({})", view.name).c_str());

    rhi::BindingSetDesc set;
    set.add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_FRAME_UNIFORMS, state.frameUniforms));
    m_localLights.addViewBindings(set);
    set.add(map ? map->binding(JANUS_BINDING_SHADOW_MAP) : m_shadows.binding(JANUS_BINDING_SHADOW_MAP));
    m_imageBasedLighting.addViewBindings(set);
    m_reflectionProbes.addViewBindings(set, view);
    m_probeGi.addViewBindings(set);
    state.bindings = m_device.createBindingSet(set);
    pipelines(MeshPass::Forward, state);
    maskedPipelines(MeshPass::Forward, state);
}

const GpuScene::MeshPipelines& ForwardShading::pipelines(MeshPass pass, const ViewState& state) {
    const PipelineKey key{pass, state.tiled, state.view.colorFormat, state.view.depthFormat, state.view.mirrored,
                          state.view.sampleCount};
    auto it = m_pipelines.find(key);
    if (it != m_pipelines.end()) return it->second;
    GpuScene::MeshPipelines made;
    if (pass == MeshPass::ForwardMaskedCoverage) {
        // Not in the prepass, so they test and write depth here, LessOrEqual as forward without a
        // prepass; their coverage comes from forward.frag's alpha (lightCounts.w).
        made = m_gpuScene.createMeshPipelines(m_vertexShader, m_forwardShader, rhi::DepthState{true, true, rhi::CompareOp::LessOrEqual},
                                              state.view.colorFormat, state.view.depthFormat, state.view.mirrored,
                                              "forward (alpha to coverage)", {}, state.view.sampleCount, true);
    } else if (pass == MeshPass::Prepass) {
        if (!m_prepassShader) m_prepassShader = makeShader(m_device, rhi::ShaderStage::Fragment, "depth_prepass_frag");
        made = m_gpuScene.createMeshPipelines(m_vertexShader, m_prepassShader, rhi::DepthState{true, true, rhi::CompareOp::Less},
                                              rhi::Format::Unknown, state.view.depthFormat, state.view.mirrored, "depth prepass", {},
                                              state.view.sampleCount);
    } else {
        // After a depth prepass the forward pass only shades the surfaces the prepass kept
        // (forward.vert's invariant position gives both the same depth bits). Without one it
        // also tests LessOrEqual, so an exact depth tie (coplanar surfaces, or two surfaces
        // meeting in an edge through a pixel centre) goes to the later instance in both frames:
        // with Less the earlier one won here and the later one after a prepass.
        const rhi::DepthState depth = state.tiled ? rhi::DepthState{true, false, rhi::CompareOp::LessOrEqual}
                                                  : rhi::DepthState{true, true, rhi::CompareOp::LessOrEqual};
        made = m_gpuScene.createMeshPipelines(m_vertexShader, m_forwardShader, depth, state.view.colorFormat, state.view.depthFormat,
                                              state.view.mirrored, "forward", {}, state.view.sampleCount);
    }
    return m_pipelines.emplace(key, std::move(made)).first->second;
}

const GpuScene::MeshPipelines* ForwardShading::maskedPipelines(MeshPass pass, const ViewState& state) {
    static const GpuScene::MeshPipelines kNone;
    if (!state.view.alphaToCoverage) return nullptr;
    if (pass == MeshPass::Prepass) return &kNone;
    return m_gpuScene.hasMaskedDraws() ? &pipelines(MeshPass::ForwardMaskedCoverage, state) : nullptr;
}

void ForwardShading::recordPrepass(const ViewState& state, rhi::ICommandList& cmd, PassReport& report) {
    cmd.beginRenderPass(
        rhi::RenderPassDesc{}.setDepth(rhi::Attachment::clearDepthTo(state.depth.texture, 1.0f, state.depth.subresource)));
    m_gpuScene.drawMeshes(cmd, state.view, pipelines(MeshPass::Prepass, state), state.bindings, report,
                          maskedPipelines(MeshPass::Prepass, state));
    cmd.endRenderPass();
}

void ForwardShading::recordForward(const ViewState& state, rhi::ICommandList& cmd, PassReport& report) {
    cmd.beginRenderPass(rhi::RenderPassDesc{}
                            .addColor(rhi::Attachment::clear(state.color.texture, m_background, state.color.subresource))
                            .setDepth(state.tiled ? rhi::Attachment::load(state.depth.texture, state.depth.subresource)
                                                  : rhi::Attachment::clearDepthTo(state.depth.texture, 1.0f, state.depth.subresource)));
    m_gpuScene.drawMeshes(cmd, state.view, pipelines(MeshPass::Forward, state), state.bindings, report,
                          maskedPipelines(MeshPass::Forward, state));
    cmd.endRenderPass();
}

}  // namespace janus::renderer
