// Renderer::Impl, private to the renderer: the state of one renderer (its scene uploaded once, the
// frame plan, the GPU resources) and the methods that build and record it. The methods are
// defined by topic:
//   renderer.cpp            construction, the frame plan, renderFrame, readbacks, the public Renderer
//   renderer_settings.cpp   checkSettings, resolveLighting (RenderSettings -> scene quality -> defaults), chooseCulling
//   renderer_resources.cpp  render targets, texture upload (CPU mips), samplers, meshes
//   renderer_lights.cpp     the light array, tile lists (compute culling or the CPU builder), cull stats
//   renderer_shadows.cpp    the main directional light's shadow map
//   renderer_passes.cpp     forward, depth prepass, tonemap, tile heat map; the std140 uniform mirrors
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "janus/renderer/light_grid.h"
#include "janus/renderer/renderer.h"
#include "janus/shaders/shaders.h"
#include "shadow_map.h"

namespace janus::renderer {

constexpr uint32_t kMaxDirectionalLights = 4;   // must match forward_common.glsl

// Lighting defaults (renderer.h, LightingSettings).
constexpr uint32_t kDefaultTileSize = 16;
constexpr uint32_t kDefaultMaxLightsPerTile = 256;
constexpr float kDefaultIntensityCutoff = 0.01f;
// LightCulling::Auto loops fewer local lights than this directly. `janus bench forward` on a quiet
// machine (docs/BENCHMARKS.md) finds a tiled mode faster than naive on all four configurations
// from 8 lights (1.2-1.9x) and about even at 0; below 8 the prepass and culling cost what they save.
constexpr uint32_t kDefaultAutoTiledThreshold = 8;
constexpr uint32_t kDefaultShadowMapSize = 1024;

// std140 mirror of forward_common.glsl's frame block (renderer_passes.cpp).
struct FrameUniforms;

inline double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

inline rhi::ShaderHandle makeShader(rhi::IDevice& device, rhi::ShaderStage stage, const char* name) {
    return device.createShader(rhi::ShaderDesc{}.setStage(stage).setSpirv(shaders::get(name)).setDebugName(name));
}

struct Renderer::Impl {
    struct GpuMesh {
        rhi::BufferHandle vertices;
        rhi::BufferHandle indices;
        uint32_t indexCount = 0;
    };
    struct Draw {
        uint32_t mesh = 0;
        bool doubleSided = false;
        rhi::BindingSetHandle bindings;
    };
    // One entry of the frame plan: a pass the scene needs, how to record it, and its timer. A
    // pass with `cpuWork` runs on the CPU between two submissions: what was recorded before it
    // is executed first, and the passes after it go into a new submission.
    struct PlannedPass {
        std::string name;
        void (Impl::*record)(rhi::ICommandList&, PassReport&) = nullptr;
        void (Impl::*cpuWork)(PassReport&) = nullptr;
        rhi::TimerQueryHandle timer;   // null without Capability::TimestampQueries or for CPU work
    };
    // LightingSettings after RenderSettings -> scene quality -> defaults.
    struct Lighting {
        LightCulling culling = LightCulling::Auto;
        uint32_t tileSize = kDefaultTileSize;
        uint32_t maxLightsPerTile = kDefaultMaxLightsPerTile;
        float intensityCutoff = kDefaultIntensityCutoff;
        uint32_t autoTiledThreshold = kDefaultAutoTiledThreshold;
        bool shadows = true;
        uint32_t shadowMapSize = kDefaultShadowMapSize;
    };

    rhi::IDevice& device;
    RenderSettings settings;
    Lighting lighting;
    LightCulling cullingMode = LightCulling::Naive;   // resolved for this scene (never Auto)
    std::vector<GpuMesh> meshes;
    std::vector<Draw> draws;
    std::vector<rhi::TextureHandle> textures;
    std::vector<rhi::SamplerHandle> textureSamplers;   // per scene texture, shared between equal samplings
    rhi::TextureHandle whiteTexture, flatNormalTexture;
    rhi::SamplerHandle materialSampler;
    rhi::SamplerHandle targetSampler;   // reads the HDR target with texelFetch: filtering never applies
    rhi::BufferHandle frameUniforms, drawUniforms, tonemapUniforms;
    rhi::BindingSetHandle frameBindings, tonemapBindings;
    rhi::TextureHandle hdrTarget, depthTarget, displayImage;
    rhi::PipelineHandle forwardCulled, forwardDoubleSided, tonemapPipeline;
    rhi::PipelineHandle prepassCulled, prepassDoubleSided;
    std::array<float, 4> backgroundRadiance{};
    rhi::CommandListHandle commandList;
    std::vector<PlannedPass> plan;
    bool frameRendered = false;   // the targets hold nothing readable before the first frame

    // Lights.
    uint32_t directionalCount = 0;
    std::vector<PackedLight> localLights;   // docs/LIGHTING.md, "GPU light layout"
    TileGrid tileGrid;                       // camera matrices and tiling shared with the culling
    rhi::BufferHandle localLightBuffer, tileBuffer;       // compute path (storage buffers)
    rhi::TextureHandle localLightTexture, tileTexture;    // fallback path (RGBA32UI / R32UI)
    uint32_t tilesX = 0, tilesY = 0;
    std::vector<uint32_t> cpuTileData;                    // fallback path: what the CPU builder produced
    std::optional<LightCullingReport> cullingReport;
    bool overflowWarned = false;

    // Shadows.
    std::unique_ptr<DirectionalShadowMap> shadowMap;
    std::vector<ShadowCaster> shadowCasters;
    rhi::TextureHandle dummyShadowTexture;   // bound at binding 9 when nothing casts shadows
    rhi::SamplerHandle dummyShadowSampler;

    // Debug view.
    rhi::PipelineHandle heatmapPipeline;
    rhi::BufferHandle heatmapUniforms;
    rhi::BindingSetHandle heatmapBindings;

    // Compute-path culling (light_cull.comp).
    rhi::PipelineHandle cullPipeline;
    rhi::BufferHandle cullUniforms, cullStats;
    rhi::BindingSetHandle cullBindings;

    Impl(rhi::IDevice& d, const Scene& scene, const RenderSettings& s);
    // A frame that threw half-way (e.g. in the CPU step between its submissions) may leave work
    // in flight that uses the resources about to be destroyed: wait for it first.
    ~Impl();

    bool tiled() const { return cullingMode == LightCulling::Tiles2D || cullingMode == LightCulling::TilesDepth; }
    uint32_t tileCount() const { return tilesX * tilesY; }

    // ---- renderer.cpp: the frame plan, renderFrame, readbacks ----
    // The passes this scene needs, in order. Every frame produces HDR radiance and a display
    // image, so forward and tonemap are always there; the rest join only when the scene has
    // what they work on.
    void planFrame();
    FrameReport renderFrame();
    void requireFrame(const char* what) const;
    ImageRGBA8 readDisplayImage();
    ImageRGBAF readHdrImage();
    std::vector<float> readDepth();
    std::vector<float> readDepthTarget();

    // ---- renderer_settings.cpp ----
    void checkSettings() const;
    void resolveLighting(const Scene& scene);
    void chooseCulling();

    // ---- renderer_resources.cpp ----
    void createTargets();
    rhi::TextureHandle createTexture(const std::string& name, uint32_t width, uint32_t height, std::vector<uint8_t> rgba, bool srgb);
    rhi::SamplerHandle createSampler(const TextureSampling& sampling);
    void uploadTextures(const Scene& scene);
    void uploadMeshes(const Scene& scene);

    // ---- renderer_lights.cpp: light array, tile-list builders (light_grid.h, light_cull.comp: docs/LIGHTING.md) ----
    // Point and spot lights into the GPU light array (light_grid.h: skips and warns about lights
    // that light nothing, refuses more than kMaxLocalLights). Directional lights stay in the frame
    // uniforms (frameUniformsFor).
    void packLights(const Scene& scene);
    // The light array and the tile lists in the form the path reads them. Without local lights
    // (or without tiles) a one-element stand-in keeps the bindings valid.
    void createLightArrays();
    // An array of `elements` texels in a texture kDataTextureWidth wide (light_access.glsl).
    rhi::TextureHandle createDataTexture(rhi::Format format, size_t elements, const char* name);
    // Writes `elements` texels of `texelBytes` each; the texture's padding after them reads as zero.
    void writeDataTexture(const rhi::TextureHandle& texture, const void* data, size_t elements, size_t texelBytes);
    // Tile-list building: the compute path's resources (light_cull.comp) or nothing for the CPU
    // builder, which runs between submissions.
    void createCulling();
    void createCullCompute();
    // One workgroup per tile; the stats are atomics, so they start from zero every frame.
    void recordLightCullCompute(rhi::ICommandList& cmd, PassReport& report);
    // Fallback path, between the prepass submission and the forward one: the prepass depth (for
    // TilesDepth) comes back, the multi-threaded CPU builder makes the lists, and they go up as
    // the R32UI tile texture. cpuMs is the builder's time alone.
    void buildTilesOnCpu(PassReport& report);
    void readCullStats(LightCullingReport& report);
    TileLists readTileLists();
    void warnOverflowOnce(const LightCullingReport& report);

    // ---- renderer_shadows.cpp ----
    void createShadows(const Scene& scene);
    void recordShadowMap(rhi::ICommandList& cmd, PassReport& report);

    // ---- renderer_passes.cpp ----
    FrameUniforms frameUniformsFor(const Scene& scene) const;
    void createForward(const Scene& scene);
    void recordMeshes(rhi::ICommandList& cmd, PassReport& report, const rhi::PipelineHandle& culled, const rhi::PipelineHandle& doubleSided);
    void recordDepthPrepass(rhi::ICommandList& cmd, PassReport& report);
    void recordForward(rhi::ICommandList& cmd, PassReport& report);
    void createTonemap(const Scene& scene);
    void recordTonemapCompute(rhi::ICommandList& cmd, PassReport& report);
    void recordTonemapFallback(rhi::ICommandList& cmd, PassReport& report);
    void createHeatmap();
    void recordHeatmap(rhi::ICommandList& cmd, PassReport& report);
};

}  // namespace janus::renderer
