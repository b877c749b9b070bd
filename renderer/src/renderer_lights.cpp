// Renderer lights: packing point and spot lights into the GPU light array, the light array and
// tile lists as storage buffers (compute path) or data textures (fallback path), and building
// the tile lists each frame: light_cull.comp on the compute path, the CPU builder (light_grid.h)
// between submissions on the fallback path. Also the culling stats, readTileLists and the
// once-per-renderer overflow warning. See docs/LIGHTING.md.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <cstring>

#include <fmt/format.h>

#include "janus/shaders/bindings.h"
#include "renderer_impl.h"

namespace janus::renderer {

// Point and spot lights into the GPU light array (light_grid.h: skips and warns about lights
// that light nothing, refuses more than kMaxLocalLights). Directional lights stay in the frame
// uniforms (frameUniformsFor).
void Renderer::Impl::packLights(const Scene& scene) {
    localLights = packLocalLights(scene, lighting.intensityCutoff).lights;
    const auto directional = std::count_if(scene.lights.begin(), scene.lights.end(),
                                           [](const Light& light) { return light.type == LightType::Directional; });
    directionalCount = uint32_t(std::min<size_t>(size_t(directional), kMaxDirectionalLights));
    if (size_t(directional) > kMaxDirectionalLights)
        fmt::print(stderr, "janus renderer: warning: scene '{}' has {} directional lights; the first {} are shaded\n", scene.name,
                   directional, kMaxDirectionalLights);
    tileGrid = makeTileGrid(scene.camera, settings.width, settings.height, lighting.tileSize, lighting.maxLightsPerTile);
}

// The light array and the tile lists in the form the path reads them. Without local lights
// (or without tiles) a one-element stand-in keeps the bindings valid.
void Renderer::Impl::createLightArrays() {
    const size_t lightWords = std::max<size_t>(localLights.size(), 1) * 4;   // uvec4 words
    const size_t tileWords = tiled() ? size_t(tileCount()) * (1 + lighting.maxLightsPerTile) : 1;   // uints
    if (settings.path == FeaturePath::Compute) {
        localLightBuffer = device.createBuffer(
            rhi::BufferDesc{}.setSize(lightWords * 16).setUsage(rhi::BufferUsage::Storage).setDebugName("local lights"));
        if (!localLights.empty()) device.writeBuffer(localLightBuffer, localLights.data(), localLights.size() * sizeof(PackedLight));
        tileBuffer = device.createBuffer(
            rhi::BufferDesc{}.setSize(tileWords * 4).setUsage(rhi::BufferUsage::Storage).setDebugName("tile light lists"));
    } else {
        localLightTexture = createDataTexture(rhi::Format::RGBA32_UINT, lightWords, "local lights");
        if (!localLights.empty()) writeDataTexture(localLightTexture, localLights.data(), localLights.size() * 4, 16);
        tileTexture = createDataTexture(rhi::Format::R32_UINT, tileWords, "tile light lists");
    }
}

// An array of `elements` texels in a texture kDataTextureWidth wide (light_access.glsl).
rhi::TextureHandle Renderer::Impl::createDataTexture(rhi::Format format, size_t elements, const char* name) {
    const uint32_t width = uint32_t(std::min<size_t>(elements, kDataTextureWidth));
    const size_t height = (elements + kDataTextureWidth - 1) / kDataTextureWidth;
    if (height > device.capabilities().limits.maxTextureSize2D)
        throw RendererError(fmt::format("the {} need a {}x{} texture on the fallback path, more than this device's maximum 2D "
                                        "texture size {}; use larger tiles or a smaller maxLightsPerTile",
                                        name, width, height, device.capabilities().limits.maxTextureSize2D));
    return device.createTexture(
        rhi::TextureDesc{}.setFormat(format).setSize(width, uint32_t(height)).setUsage(rhi::TextureUsage::Sampled).setDebugName(name));
}

// Writes `elements` texels of `texelBytes` each; the texture's padding after them reads as zero.
void Renderer::Impl::writeDataTexture(const rhi::TextureHandle& texture, const void* data, size_t elements, size_t texelBytes) {
    const rhi::TextureDesc& desc = texture->desc();
    std::vector<std::byte> texels(size_t(desc.width) * desc.height * texelBytes);
    std::memcpy(texels.data(), data, elements * texelBytes);
    device.writeTexture(texture, {}, texels.data(), texels.size());
}

// Tile-list building: the compute path's resources (light_cull.comp) or nothing for the CPU
// builder, which runs between submissions.
void Renderer::Impl::createCulling() {
    if (!tiled() || settings.path != FeaturePath::Compute) return;
    createCullCompute();
}

// ---- Tile-list builders (light_grid.h, light_cull.comp: docs/LIGHTING.md) ----
void Renderer::Impl::createCullCompute() {
    const CullUniforms uniforms = makeCullUniforms(tileGrid, uint32_t(localLights.size()), cullingMode);
    cullUniforms = device.createBuffer(
        rhi::BufferDesc{}.setSize(sizeof(uniforms)).setUsage(rhi::BufferUsage::Uniform).setDebugName("cull uniforms"));
    device.writeBuffer(cullUniforms, &uniforms, sizeof(uniforms));
    cullStats = device.createBuffer(rhi::BufferDesc{}.setSize(16).setUsage(rhi::BufferUsage::Storage).setDebugName("cull stats"));
    cullBindings = device.createBindingSet(rhi::BindingSetDesc{}
                                               .add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_CULL_UNIFORMS, cullUniforms))
                                               .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_CULL_DEPTH, depthTarget, targetSampler))
                                               .add(rhi::BindingItem::storageBuffer(JANUS_BINDING_CULL_LIGHTS, localLightBuffer))
                                               .add(rhi::BindingItem::storageBuffer(JANUS_BINDING_CULL_TILE_LISTS, tileBuffer))
                                               .add(rhi::BindingItem::storageBuffer(JANUS_BINDING_CULL_STATS, cullStats)));
    cullPipeline = device.createComputePipeline(rhi::ComputePipelineDesc{}
                                                    .setShader(makeShader(device, rhi::ShaderStage::Compute, "light_cull_comp"))
                                                    .setDebugName("light culling"));
}

// One workgroup per tile; the stats are atomics, so they start from zero every frame.
void Renderer::Impl::recordLightCullCompute(rhi::ICommandList& cmd, PassReport& report) {
    const std::array<uint32_t, 4> zero{};
    cmd.writeBuffer(cullStats, zero.data(), sizeof(zero));
    cmd.setPipeline(cullPipeline);
    cmd.setBindingSet(0, cullBindings);
    cmd.dispatch(tilesX, tilesY);
    ++report.dispatches;
}

// Fallback path, between the prepass submission and the forward one: the prepass depth (for
// TilesDepth) comes back, the multi-threaded CPU builder makes the lists, and they go up as
// the R32UI tile texture. cpuMs is the builder's time alone.
void Renderer::Impl::buildTilesOnCpu(PassReport& report) {
    std::vector<float> depth;
    if (cullingMode == LightCulling::TilesDepth) depth = readDepthTarget();
    TileBuildStats stats;
    const auto start = std::chrono::steady_clock::now();
    const TileLists lists = buildTileListsCpu(tileGrid, localLights, depth, &stats);
    report.cpuMs = millisecondsSince(start);
    cpuTileData = flattenTileData(lists);
    writeDataTexture(tileTexture, cpuTileData.data(), cpuTileData.size(), sizeof(uint32_t));
    cullingReport->listedLights = stats.listedLights;
    cullingReport->overflowTiles = stats.overflowTiles;
    cullingReport->droppedLights = stats.droppedLights;
}

void Renderer::Impl::readCullStats(LightCullingReport& report) {
    const std::vector<std::byte> bytes = device.readBuffer(cullStats);
    std::array<uint32_t, 4> stats{};
    std::memcpy(stats.data(), bytes.data(), std::min(bytes.size(), sizeof(stats)));
    report.overflowTiles = stats[0];
    report.droppedLights = stats[1];
    report.listedLights = stats[2];
}

TileLists Renderer::Impl::readTileLists() {
    requireFrame("readTileLists()");
    if (!tiled())
        throw RendererError(fmt::format("readTileLists(): the last frame built no tile lists (light culling {}{}); tiles exist only "
                                        "with tiles-2d or tiles-depth and point/spot lights",
                                        toString(cullingMode), localLights.empty() ? ", no point or spot lights" : ""));
    std::vector<uint32_t> data;
    if (settings.path == FeaturePath::Compute) {
        const std::vector<std::byte> bytes = device.readBuffer(tileBuffer);
        data.resize(bytes.size() / 4);
        std::memcpy(data.data(), bytes.data(), data.size() * 4);
    } else {
        data = cpuTileData;
    }
    TileLists lists;
    lists.tileSize = lighting.tileSize;
    lists.tilesX = tilesX;
    lists.tilesY = tilesY;
    lists.maxLightsPerTile = lighting.maxLightsPerTile;
    const size_t tiles = tileCount();
    if (data.size() < tiles * (1 + lists.maxLightsPerTile))
        throw RendererError(fmt::format("readTileLists(): the tile data holds {} words, expected {}", data.size(),
                                        tiles * (1 + lists.maxLightsPerTile)));
    lists.counts.assign(data.begin(), data.begin() + tiles);
    lists.indices.assign(data.begin() + tiles, data.begin() + tiles * (1 + lists.maxLightsPerTile));
    return lists;
}

void Renderer::Impl::warnOverflowOnce(const LightCullingReport& report) {
    if (report.overflowTiles == 0 || overflowWarned) return;
    overflowWarned = true;
    fmt::print(stderr, "janus renderer: warning: {} tile(s) had more than maxLightsPerTile = {} lights; {} light reference(s) were "
                       "dropped (highest light indices first), so those tiles miss light. Raise maxLightsPerTile or use smaller "
                       "tiles (reported once per renderer)\n",
               report.overflowTiles, report.maxLightsPerTile, report.droppedLights);
}

}  // namespace janus::renderer
