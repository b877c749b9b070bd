// Local lights: packing point and spot lights into the GPU light array, the light array and tile
// lists as storage buffers (compute path) or data textures (fallback path), and the pass that
// builds the tile lists each frame. See docs/LIGHTING.md.
#include "forward/local_lights.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include <fmt/format.h>

#include "core/gpu_util.h"
#include "janus/shaders/bindings.h"

namespace janus::renderer {

namespace {

size_t directionalLightCount(std::span<const Light> lights) {
    return size_t(std::count_if(lights.begin(), lights.end(), [](const Light& light) { return light.type == LightType::Directional; }));
}

}  // namespace

LocalLights::LocalLights(rhi::IDevice& device, const Scene& scene, const ResolvedLighting& lighting, FeaturePath path,
                         const SceneView& tiledView, rhi::SamplerHandle pointSampler)
    : m_device(device), m_lighting(lighting), m_path(path), m_tiledViewName(tiledView.name), m_pointSampler(std::move(pointSampler)) {
    // Point and spot lights into the GPU light array; directional lights stay in the frame
    // uniforms (forward_shading.cpp).
    m_lights = packLocalLights(scene, m_lighting.intensityCutoff).lights;
    const size_t directional = directionalLightCount(scene.lights);
    m_directionalCount = uint32_t(std::min<size_t>(directional, kMaxDirectionalLights));
    if (directional > kMaxDirectionalLights)
        fmt::print(stderr, "janus renderer: warning: scene '{}' has {} directional lights; the first {} are shaded\n", scene.name,
                   directional, kMaxDirectionalLights);
    m_grid = makeTileGrid(tiledView, m_lighting.tileSize, m_lighting.maxLightsPerTile);
    // Blended surfaces are not in the prepass depth but read the same tile lists.
    m_grid.rangeFromNearPlane = std::any_of(scene.instances.begin(), scene.instances.end(), [&](const Instance& instance) {
        const Mesh& mesh = scene.meshes[instance.mesh];
        return !mesh.indices.empty() && mesh.material >= 0 && scene.materials[size_t(mesh.material)].alphaMode == AlphaMode::Blend;
    });

    // The culling mode this scene renders with.
    m_mode = m_lighting.culling;
    // Tile depth bounds come from a single-sampled depth prepass; a multisampled view's samples
    // may see surfaces no pixel centre of their tile sees, so it is culled without depth bounds.
    const bool multisampled = tiledView.sampleCount > 1;
    if (multisampled && m_mode == LightCulling::TilesDepth)
        throw RendererError(fmt::format("light culling tiles-depth takes its depth bounds from single-sampled depth, which a view with "
                                        "msaa {} does not have; use tiles-2d, naive or auto (which picks tiles-2d with msaa)",
                                        tiledView.sampleCount));
    if (m_mode == LightCulling::Auto) {
        // Infinite ranges (cut-off 0) can only be looped directly.
        const bool tiledPossible = m_lighting.intensityCutoff > 0.0f;
        const LightCulling tiledMode = multisampled ? LightCulling::Tiles2D : LightCulling::TilesDepth;
        m_mode = tiledPossible && m_lights.size() >= m_lighting.autoTiledThreshold ? tiledMode : LightCulling::Naive;
    }
    // No local lights: nothing to cull, no prepass.
    if (m_lights.empty()) m_mode = LightCulling::Naive;
    if (tiled()) {
        m_tilesX = m_grid.tilesX();
        m_tilesY = m_grid.tilesY();
        if (m_lighting.maxLightsPerTile == kAutoMaxLightsPerTile) {
            m_autoMaxLightsPerTile = true;
            m_lighting.maxLightsPerTile = autoMaxLightsPerTile(m_lights.size(), tileCount(), largestCapThatFits());
        }
        m_grid.maxLightsPerTile = m_lighting.maxLightsPerTile;
        checkTileStorageFits();
    }
    if (!m_lights.empty()) {
        LightCullingReport report;
        report.mode = m_mode;
        report.builder = tiled() ? (m_path == FeaturePath::Compute ? "compute" : "cpu") : "";
        report.directionalLights = m_directionalCount;
        report.localLights = uint32_t(m_lights.size());
        if (tiled()) {
            report.tileSize = m_lighting.tileSize;
            report.tilesX = m_tilesX;
            report.tilesY = m_tilesY;
            report.maxLightsPerTile = m_lighting.maxLightsPerTile;
            report.maxLightsPerTileAuto = m_autoMaxLightsPerTile;
        }
        m_report = report;
    }

    // The light array and the tile lists in the form the path reads them. Without local lights
    // (or without tiles) a one-element stand-in keeps the bindings valid.
    const size_t lightWords = std::max<size_t>(m_lights.size(), 1) * 4;   // uvec4 words
    if (m_path == FeaturePath::Compute)
        m_lightBuffer = m_device.createBuffer(
            rhi::BufferDesc{}.setSize(lightWords * 16).setUsage(rhi::BufferUsage::Storage).setDebugName("local lights"));
    else
        m_lightTexture = createDataTexture(rhi::Format::RGBA32_UINT, lightWords, "local lights");
    uploadLights();
    // The full tile lists are made only when the culling pass is kept (createTileStorage).
    if (!tiled()) createTileStorage(1);
}

void LocalLights::uploadLights() {
    if (m_lights.empty()) return;
    if (m_path == FeaturePath::Compute)
        m_device.writeBuffer(m_lightBuffer, m_lights.data(), m_lights.size() * sizeof(PackedLight));
    else
        writeDataTexture(m_lightTexture, m_lights.data(), m_lights.size() * 4, 16);
}

void LocalLights::checkLights(std::span<const Light> lights) const {
    const size_t lit = packLocalLights(lights, m_lighting.intensityCutoff).lights.size();
    if (lit <= m_lights.size()) return;
    throw RendererError(fmt::format("setLights: {} point/spot lights light something, but this renderer was made for at most {}: its "
                                    "light array, culling mode and passes are planned for that many; give at most {} (dim the others to "
                                    "intensity 0), or create a new Renderer for a scene with these lights",
                                    lit, m_lights.size(), m_lights.size()));
}

void LocalLights::setLights(std::span<const Light> lights) {
    std::vector<PackedLight> packed = packLocalLights(lights, m_lighting.intensityCutoff).lights;
    // Placeholders keep the array's size, so the culling mode and the light count the passes
    // were set up with stay true. Radiance 0 and layer mask 0 make their contribution exactly 0
    // (x + 0 == x), so the image is the one a renderer made with only the lit lights shows.
    PackedLight dark;
    dark.radiance = glm::vec3(0.0f);
    dark.renderingLayers = 0u;
    dark.invRangeSq = 1.0f / (kMinLightRadius * kMinLightRadius);   // the smallest sphere packing makes: in almost no tile
    packed.resize(m_lights.size(), dark);
    m_lights = std::move(packed);
    m_directionalCount = uint32_t(std::min<size_t>(directionalLightCount(lights), kMaxDirectionalLights));
    if (m_report) m_report->directionalLights = m_directionalCount;
    uploadLights();
}

uint32_t LocalLights::largestCapThatFits() const {
    const rhi::Limits& limits = m_device.capabilities().limits;
    const uint64_t words = m_path == FeaturePath::Compute
                               ? (limits.maxStorageBufferRange != 0 ? limits.maxStorageBufferRange / 4 : UINT64_MAX)
                               : uint64_t(limits.maxTextureSize2D) * kDataTextureWidth;
    const uint64_t perTile = words / std::max<uint64_t>(tileCount(), 1);
    return uint32_t(std::min<uint64_t>(perTile > 0 ? perTile - 1 : 0, kMaxLightsPerTileLimit));
}

void LocalLights::checkTileStorageFits() const {
    // Checked when the renderer is made, before any resource: the tile lists (a count and
    // maxLightsPerTile entries per tile, 32 bits each) must fit one storage buffer binding on the
    // compute path and one data texture on the fallback path.
    if (m_lighting.maxLightsPerTile <= largestCapThatFits()) return;
    const size_t words = size_t(tileCount()) * (1 + m_lighting.maxLightsPerTile);
    const rhi::Limits& limits = m_device.capabilities().limits;
    const char* advice = "use larger tiles or a smaller maxLightsPerTile (janus: --tile-size, --max-lights-per-tile)";
    if (m_path == FeaturePath::Compute)
        throw RendererError(fmt::format("the tile light lists ({}x{} tiles of {} px, up to {} lights each) need a {}-byte storage "
                                        "buffer on the compute path, more than this device's largest storage buffer range ({}); {}",
                                        m_tilesX, m_tilesY, m_lighting.tileSize, m_lighting.maxLightsPerTile, uint64_t(words) * 4,
                                        limits.maxStorageBufferRange, advice));
    throw RendererError(fmt::format("the tile light lists ({}x{} tiles of {} px, up to {} lights each) need a {}x{} texture on "
                                    "the fallback path, more than this device's maximum 2D texture size {}; {}",
                                    m_tilesX, m_tilesY, m_lighting.tileSize, m_lighting.maxLightsPerTile,
                                    std::min<size_t>(words, kDataTextureWidth), (words + kDataTextureWidth - 1) / kDataTextureWidth,
                                    limits.maxTextureSize2D, advice));
}

void LocalLights::createTileStorage(size_t words) {
    if (m_tileBuffer || m_tileTexture) return;
    if (m_path == FeaturePath::Compute)
        m_tileBuffer = m_device.createBuffer(
            rhi::BufferDesc{}.setSize(words * 4).setUsage(rhi::BufferUsage::Storage).setDebugName("tile light lists"));
    else
        m_tileTexture = createDataTexture(rhi::Format::R32_UINT, words, "tile light lists");
}

rhi::TextureHandle LocalLights::createDataTexture(rhi::Format format, size_t elements, const char* name) {
    const uint32_t width = uint32_t(std::min<size_t>(elements, kDataTextureWidth));
    const size_t height = (elements + kDataTextureWidth - 1) / kDataTextureWidth;
    if (height > m_device.capabilities().limits.maxTextureSize2D)
        throw RendererError(fmt::format("the {} need a {}x{} texture on the fallback path, more than this device's maximum 2D "
                                        "texture size {}; use larger tiles or a smaller maxLightsPerTile (janus: --tile-size, --max-lights-per-tile)",
                                        name, width, height, m_device.capabilities().limits.maxTextureSize2D));
    return m_device.createTexture(
        rhi::TextureDesc{}.setFormat(format).setSize(width, uint32_t(height)).setUsage(rhi::TextureUsage::Sampled).setDebugName(name));
}

void LocalLights::writeDataTexture(const rhi::TextureHandle& texture, const void* data, size_t elements, size_t texelBytes) {
    const rhi::TextureDesc& desc = texture->desc();
    std::vector<std::byte> texels(size_t(desc.width) * desc.height * texelBytes);
    std::memcpy(texels.data(), data, elements * texelBytes);
    m_device.writeTexture(texture, {}, texels.data(), texels.size());
}

PassGraph::ResourceId LocalLights::addCullingPass(PassGraph& graph, PassGraph::ResourceId depth, rhi::TextureHandle depthTexture) {
    const PassGraph::ResourceId tileLists =
        graph.addResource("tile-lists", [this] { createTileStorage(size_t(tileCount()) * (1 + m_lighting.maxLightsPerTile)); });
    // Tiles2D reads no depth; a multisampled depth cannot be bound, so a stand-in fills the binding.
    if (depthTexture->desc().sampleCount > 1) {
        if (m_mode == LightCulling::TilesDepth)
            throw RendererError("light culling: tiles-depth cannot read a multisampled depth target");
        depthTexture = m_device.createTexture(rhi::TextureDesc{}
                                                  .setFormat(depthTexture->desc().format)
                                                  .setSize(1, 1)
                                                  .setUsage(rhi::TextureUsage::Sampled)
                                                  .setDebugName("cull depth (unused without depth bounds)"));
    }
    m_depthTexture = std::move(depthTexture);
    PassGraph::PassDesc pass;
    pass.view = m_tiledViewName;
    pass.reads = {depth};
    pass.writes = {tileLists};
    if (m_path == FeaturePath::Compute) {
        pass.name = "light-cull-compute";
        pass.setup = [this] { createCullCompute(); };
        pass.record = [this](rhi::ICommandList& cmd, PassReport& report) { recordCullCompute(cmd, report); };
    } else {
        pass.name = "light-cull-cpu";
        pass.run = [this](PassReport& report) { buildTilesOnCpu(report); };
    }
    graph.addPass(std::move(pass));
    return tileLists;
}

void LocalLights::addViewBindings(rhi::BindingSetDesc& set) const {
    if (m_path == FeaturePath::Compute)
        set.add(rhi::BindingItem::storageBuffer(JANUS_BINDING_LOCAL_LIGHTS, m_lightBuffer));
    else
        set.add(rhi::BindingItem::sampledTexture(JANUS_BINDING_LOCAL_LIGHTS, m_lightTexture, m_pointSampler));
    set.add(tileListBinding());
}

rhi::BindingItem LocalLights::tileListBinding() const {
    return m_path == FeaturePath::Compute ? rhi::BindingItem::storageBuffer(JANUS_BINDING_TILE_LISTS, m_tileBuffer)
                                          : rhi::BindingItem::sampledTexture(JANUS_BINDING_TILE_LISTS, m_tileTexture, m_pointSampler);
}

void LocalLights::createCullCompute() {
    const CullUniforms uniforms = makeCullUniforms(m_grid, uint32_t(m_lights.size()), m_mode);
    m_cullUniforms = m_device.createBuffer(
        rhi::BufferDesc{}.setSize(sizeof(uniforms)).setUsage(rhi::BufferUsage::Uniform).setDebugName("cull uniforms"));
    m_device.writeBuffer(m_cullUniforms, &uniforms, sizeof(uniforms));
    m_cullStats = m_device.createBuffer(rhi::BufferDesc{}.setSize(16).setUsage(rhi::BufferUsage::Storage).setDebugName("cull stats"));
    m_cullBindings = m_device.createBindingSet(rhi::BindingSetDesc{}
                                               .add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_CULL_UNIFORMS, m_cullUniforms))
                                               .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_CULL_DEPTH, m_depthTexture, m_pointSampler))
                                               .add(rhi::BindingItem::storageBuffer(JANUS_BINDING_CULL_LIGHTS, m_lightBuffer))
                                               .add(rhi::BindingItem::storageBuffer(JANUS_BINDING_CULL_TILE_LISTS, m_tileBuffer))
                                               .add(rhi::BindingItem::storageBuffer(JANUS_BINDING_CULL_STATS, m_cullStats)));
    m_cullPipeline = m_device.createComputePipeline(rhi::ComputePipelineDesc{}
                                                    .setShader(makeShader(m_device, rhi::ShaderStage::Compute, "light_cull_comp"))
                                                    .setDebugName("light culling"));
}

void LocalLights::recordCullCompute(rhi::ICommandList& cmd, PassReport& report) {
    const std::array<uint32_t, 4> zero{};
    cmd.writeBuffer(m_cullStats, zero.data(), sizeof(zero));
    cmd.setPipeline(m_cullPipeline);
    cmd.setBindingSet(0, m_cullBindings);
    cmd.dispatch(m_tilesX, m_tilesY);
    ++report.dispatches;
    m_culledThisFrame = true;
}

void LocalLights::buildTilesOnCpu(PassReport& report) {
    std::vector<float> depth;
    if (m_mode == LightCulling::TilesDepth) depth = readDepth32F(m_device, m_depthTexture);
    TileBuildStats stats;
    const auto start = std::chrono::steady_clock::now();
    const TileLists lists = buildTileListsCpu(m_grid, m_lights, depth, &stats);
    report.cpuMs = millisecondsSince(start);
    m_cpuTileData = flattenTileData(lists);
    writeDataTexture(m_tileTexture, m_cpuTileData.data(), m_cpuTileData.size(), sizeof(uint32_t));
    m_report->listedLights = stats.listedLights;
    m_report->overflowTiles = stats.overflowTiles;
    m_report->droppedLights = stats.droppedLights;
    m_report->densestTileLights = stats.densestTileLights;
    m_culledThisFrame = true;
}

std::optional<LightCullingReport> LocalLights::finishFrame() {
    if (m_report && m_culledThisFrame && m_path == FeaturePath::Compute) {
        const std::vector<std::byte> bytes = m_device.readBuffer(m_cullStats);
        std::array<uint32_t, 4> stats{};
        std::memcpy(stats.data(), bytes.data(), std::min(bytes.size(), sizeof(stats)));
        m_report->overflowTiles = stats[0];
        m_report->droppedLights = stats[1];
        m_report->listedLights = stats[2];
        m_report->densestTileLights = stats[3];
    }
    m_culledThisFrame = false;
    if (m_report && m_report->overflowTiles != 0 && !m_overflowWarned) {
        m_overflowWarned = true;
        const uint32_t densest = m_report->densestTileLights;
        const std::string advice =
            densest <= kMaxLightsPerTileLimit
                ? fmt::format("set maxLightsPerTile to {} or more (janus: --max-lights-per-tile; scene file: quality.maxLightsPerTile) or "
                              "use smaller tiles",
                              densest)
                : fmt::format("that is more than maxLightsPerTile can be ({}): use smaller tiles, or fewer lights or shorter ranges there",
                              kMaxLightsPerTileLimit);
        // An automatic cap below the light count: which limit held it there.
        const uint32_t cap = m_lighting.maxLightsPerTile;
        const std::string why =
            !m_autoMaxLightsPerTile        ? std::string()
            : cap == kMaxLightsPerTileLimit ? fmt::format(" (automatic, held at the largest cap, {})", kMaxLightsPerTileLimit)
            : cap == largestCapThatFits()
                ? fmt::format(" (automatic, held at {} by what this device holds for {} tiles of {} px)", cap, tileCount(),
                              m_lighting.tileSize)
                : fmt::format(" (automatic, held at {} by the {} MiB budget for the lists of {} tiles of {} px)", cap,
                              kAutoTileListBudgetBytes >> 20, tileCount(), m_lighting.tileSize);
        fmt::print(stderr, "janus renderer: warning: {} tile(s) had more than maxLightsPerTile = {} lights{}; {} light reference(s) were "
                           "dropped (highest light indices first), so those tiles miss light. The densest tile met {} lights: {} "
                           "(reported once per renderer)\n",
                   m_report->overflowTiles, m_report->maxLightsPerTile, why, m_report->droppedLights, densest, advice);
    }
    return m_report;
}

TileLists LocalLights::readTileLists() {
    if (!tiled())
        throw RendererError(fmt::format("readTileLists(): the last frame built no tile lists (light culling {}{}); tiles exist only "
                                        "with tiles-2d or tiles-depth and point/spot lights",
                                        toString(m_mode), m_lights.empty() ? ", no point or spot lights" : ""));
    std::vector<uint32_t> data;
    if (m_path == FeaturePath::Compute) {
        const std::vector<std::byte> bytes = m_device.readBuffer(m_tileBuffer);
        data.resize(bytes.size() / 4);
        std::memcpy(data.data(), bytes.data(), data.size() * 4);
    } else {
        data = m_cpuTileData;
    }
    TileLists lists;
    lists.tileSize = m_lighting.tileSize;
    lists.tilesX = m_tilesX;
    lists.tilesY = m_tilesY;
    lists.maxLightsPerTile = m_lighting.maxLightsPerTile;
    const size_t tiles = tileCount();
    if (data.size() < tiles * (1 + lists.maxLightsPerTile))
        throw RendererError(fmt::format("readTileLists(): the tile data holds {} words, expected {}", data.size(),
                                        tiles * (1 + lists.maxLightsPerTile)));
    lists.counts.assign(data.begin(), data.begin() + tiles);
    lists.indices.assign(data.begin() + tiles, data.begin() + tiles * (1 + lists.maxLightsPerTile));
    return lists;
}

}  // namespace janus::renderer
