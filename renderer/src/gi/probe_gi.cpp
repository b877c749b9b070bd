// Probe GI feature (probe_gi.h, docs/GI.md).
#include "gi/probe_gi.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <numeric>

#include <fmt/format.h>
#include <glm/gtc/packing.hpp>

#include "core/gpu_util.h"
#include "forward/frame_uniforms.h"
#include "gi/gi_bake_file.h"
#include "janus/shaders/bindings.h"

namespace janus::renderer {

namespace {

constexpr uint32_t kDataWidth = 1024;   // gi_relight_common.glsl kGiDataWidth
constexpr uint32_t kGroupSize = 64;     // gi_brick_radiance.comp, gi_probe_sh.comp
constexpr uint32_t kShCoefficientsPerDraw = 3;   // gi_probe_sh.frag: colour targets per draw of the fallback SH pass

// std140 mirror of gi_relight_common.glsl's GiRelightParams.

// An RGBA32F data texture 1024 texels wide holding `texels` (padded with zeros).
rhi::TextureHandle makeDataTexture(rhi::IDevice& device, std::vector<glm::vec4> texels, const char* name) {
    const uint32_t rows = std::max<uint32_t>(1, uint32_t((texels.size() + kDataWidth - 1) / kDataWidth));
    texels.resize(size_t(rows) * kDataWidth, glm::vec4(0.0f));
    rhi::TextureHandle texture = device.createTexture(
        rhi::TextureDesc{}.setFormat(rhi::Format::RGBA32_FLOAT).setSize(kDataWidth, rows).setUsage(rhi::TextureUsage::Sampled).setDebugName(name));
    device.writeTexture(texture, {}, texels.data(), texels.size() * sizeof(glm::vec4));
    return texture;
}

// The visibility texture (gi_access.glsl): per probe a tile of (N + 2) x (N + 3) texels, its
// N x N distance moments inside a border that continues the octahedral map across its folds (a
// border texel repeats the interior texel its direction folds onto: an edge's mirror, a corner's
// opposite corner), and below them its position. Tiles fill rows of at most 2048 texels (GLES 3.0's
// smallest maximum texture size).
rhi::TextureHandle makeVisibilityTexture(rhi::IDevice& device, const GiBake& bake) {
    const uint32_t n = kGiVisibilityResolution;
    const uint32_t probes = uint32_t(bake.probePositions.size());
    const uint32_t tileWidth = n + 2, tileHeight = n + 3;
    const uint32_t perRow = std::min(probes, 2048u / tileWidth);
    const uint32_t rows = (probes + perRow - 1) / perRow;
    const uint32_t width = perRow * tileWidth, height = rows * tileHeight;
    std::vector<glm::vec4> texels(size_t(width) * height, glm::vec4(0.0f));
    for (uint32_t p = 0; p < probes; ++p) {
        const glm::vec2* moments = bake.distanceMoments.data() + size_t(p) * n * n;
        const uint32_t x0 = (p % perRow) * tileWidth, y0 = (p / perRow) * tileHeight;
        for (int y = -1; y <= int(n); ++y)
            for (int x = -1; x <= int(n); ++x) {
                // Across a horizontal edge the map continues mirrored in x, across a vertical one
                // mirrored in y; past a corner, at the opposite corner (all four are -z).
                const int cx = std::clamp(x, 0, int(n) - 1), cy = std::clamp(y, 0, int(n) - 1);
                const uint32_t sx = uint32_t(y != cy ? int(n) - 1 - cx : cx);
                const uint32_t sy = uint32_t(x != cx ? int(n) - 1 - cy : cy);
                const glm::vec2 m = moments[sy * n + sx];
                texels[size_t(y0 + uint32_t(y + 1)) * width + x0 + uint32_t(x + 1)] = glm::vec4(m, 0.0f, 0.0f);
            }
        texels[size_t(y0 + n + 2) * width + x0] = glm::vec4(bake.probePositions[p], 1.0f);
    }
    rhi::TextureHandle texture = device.createTexture(
        rhi::TextureDesc{}.setFormat(rhi::Format::RGBA32_FLOAT).setSize(width, height).setUsage(rhi::TextureUsage::Sampled).setDebugName("gi visibility"));
    device.writeTexture(texture, {}, texels.data(), texels.size() * sizeof(glm::vec4));
    return texture;
}

}  // namespace

ProbeGi::ProbeGi(rhi::IDevice& device, const Scene& scene, const GpuScene& gpuScene, const LocalLights& localLights,
                 MainLightShadows& shadows, const ImageBasedLighting& imageBasedLighting, FeaturePath path,
                 const glm::vec3& cameraPosition, const std::filesystem::path& bakeFile)
    : m_device(device), m_localLights(localLights), m_shadows(shadows), m_imageBasedLighting(imageBasedLighting), m_path(path) {
    m_pointSampler = device.createSampler(rhi::SamplerDesc{}.setFilter(rhi::Filter::Nearest).setAddress(rhi::AddressMode::ClampToEdge));
    m_standInUniforms = makeUniformBuffer(device, GiVolumeUniforms{}, "no irradiance volume");   // origin.w 0: off
    {
        const glm::vec4 nothing(0.0f);
        m_standInVisibility = device.createTexture(
            rhi::TextureDesc{}.setFormat(rhi::Format::RGBA32_FLOAT).setSize(1, 1).setUsage(rhi::TextureUsage::Sampled).setDebugName("no gi visibility"));
        device.writeTexture(m_standInVisibility, {}, &nothing, sizeof(nothing));
    }
    if (!scene.irradianceVolume) {
        if (!bakeFile.empty())
            throw GiBakeFileError(fmt::format("{}: RenderSettings::giBakeFile is set but the scene has no irradiance volume for a "
                                              "bake to fill; give the scene the bake was made for, or leave giBakeFile empty",
                                              bakeFile.string()));
        m_standInVolume = device.createTexture(rhi::TextureDesc{}
                                                   .setDimension(rhi::TextureDimension::Texture3D)
                                                   .setFormat(rhi::Format::RGBA16_FLOAT)
                                                   .setSize(1, 1, 9)
                                                   .setUsage(rhi::TextureUsage::Sampled)
                                                   .setDebugName("no irradiance volume"));
        return;
    }
    if (path == FeaturePath::Compute) device.require(rhi::Capability::StorageImages, "the GI relight's compute path");
    m_active = true;
    m_volume = *scene.irradianceVolume;
    m_relightFrame = sceneFrameUniforms(scene);
    m_relightFrame.lightCounts = glm::ivec4(m_relightFrame.lightCounts.x, int(localLights.count()), 0, 0);
    m_relightFrame.skyParams = imageBasedLighting.shadingParams();
    m_bounces = m_volume.bounces;

    // The bake's report: its G-buffer draws and their GPU time, and the whole bake's CPU time
    // (readbacks, surfels, bricks, transfers).
    if (!bakeFile.empty()) {
        m_bake = readGiBakeFile(bakeFile, m_volume, giSceneHash(scene));   // no GPU work: no report entry
    } else {
        const auto start = std::chrono::steady_clock::now();
        PassReport bakeReport;
        bakeReport.name = "gi-bake";
        m_bake = bakeGiVolume(device, gpuScene, m_volume, &bakeReport);
        bakeReport.cpuMs = millisecondsSince(start);
        m_startupReports.push_back(bakeReport);
    }

    m_probeCount = uint32_t(m_bake.probePositions.size());
    m_probesPerStep = m_volume.probesPerFrame == 0 ? m_probeCount : std::min(m_volume.probesPerFrame, m_probeCount);
    // Relight order: nearest the camera first (ties in grid order).
    m_rankToProbe.resize(m_probeCount);
    std::iota(m_rankToProbe.begin(), m_rankToProbe.end(), 0u);
    std::stable_sort(m_rankToProbe.begin(), m_rankToProbe.end(), [&](uint32_t a, uint32_t b) {
        return glm::distance(m_bake.probePositions[a], cameraPosition) < glm::distance(m_bake.probePositions[b], cameraPosition);
    });
    upload();
    m_commandList = device.createCommandList();
}

void ProbeGi::upload() {
    std::vector<glm::vec4> surfels, bricks, transfers, probes;
    surfels.reserve(m_bake.surfels.size() * 4);
    for (const GiSurfel& s : m_bake.surfels) {
        // Four texels a surfel (gi_relight_common.glsl): in their w, the face normal octahedrally
        // and the rendering layers as two 16-bit halves (floats hold both exactly).
        const glm::vec2 face = giOctahedralEncode(s.faceNormal);
        surfels.push_back(glm::vec4(s.position, face.x));
        surfels.push_back(glm::vec4(s.normal, face.y));
        surfels.push_back(glm::vec4(s.albedo, float(s.renderingLayers & 0xFFFFu)));
        surfels.push_back(glm::vec4(s.emission, float(s.renderingLayers >> 16)));
    }
    for (const GiBrick& b : m_bake.bricks) {
        bricks.push_back(glm::vec4(float(b.firstSurfel), float(b.surfelCount), b.sky ? 1.0f : 0.0f, 0.0f));
        bricks.push_back(glm::vec4(b.skyDirection, 0.0f));
    }
    for (const GiTransfer& t : m_bake.transfers) {
        transfers.push_back(glm::vec4(float(t.brick), t.sh[0], t.sh[1], t.sh[2]));
        transfers.push_back(glm::vec4(t.sh[3], t.sh[4], t.sh[5], t.sh[6]));
        transfers.push_back(glm::vec4(t.sh[7], t.sh[8], 0.0f, 0.0f));
    }
    std::vector<uint32_t> rankOf(m_probeCount);
    for (uint32_t r = 0; r < m_probeCount; ++r) rankOf[m_rankToProbe[r]] = r;
    for (uint32_t p = 0; p < m_probeCount; ++p)
        probes.push_back(glm::vec4(float(m_bake.probeFirstTransfer[p]), float(m_bake.probeTransferCount[p]), m_bake.valid[p] ? 1.0f : 0.0f,
                                   float(rankOf[p])));
    for (uint32_t r = 0; r < m_probeCount; ++r) probes.push_back(glm::vec4(float(m_rankToProbe[r]), 0.0f, 0.0f, 0.0f));
    m_surfels = makeDataTexture(m_device, std::move(surfels), "gi surfels");
    m_bricks = makeDataTexture(m_device, std::move(bricks), "gi bricks");
    m_transfers = makeDataTexture(m_device, std::move(transfers), "gi transfers");
    m_probes = makeDataTexture(m_device, std::move(probes), "gi probes");

    const bool compute = m_path == FeaturePath::Compute;
    const uint32_t brickRows = std::max<uint32_t>(1, uint32_t((m_bake.bricks.size() + kDataWidth - 1) / kDataWidth));
    // RGBA32F where the device renders to it (ES 3.0 needs EXT_color_buffer_float), else RGBA16F.
    const bool float32Target = compute || m_device.formatCapabilities(rhi::Format::RGBA32_FLOAT).has(rhi::FormatCapability::RenderTarget);
    m_brickRadiance = m_device.createTexture(rhi::TextureDesc{}
                                                 .setFormat(float32Target ? rhi::Format::RGBA32_FLOAT : rhi::Format::RGBA16_FLOAT)
                                                 .setSize(kDataWidth, brickRows)
                                                 .setUsage(rhi::TextureUsage::Sampled |
                                                           (compute ? rhi::TextureUsage::Storage : rhi::TextureUsage::RenderTarget))
                                                 .setDebugName("gi brick radiance"));
    const glm::uvec3 counts = m_volume.probeCounts;
    m_volumeTexture = m_device.createTexture(rhi::TextureDesc{}
                                                 .setDimension(rhi::TextureDimension::Texture3D)
                                                 .setFormat(rhi::Format::RGBA16_FLOAT)
                                                 .setSize(counts.x, counts.z, counts.y * 9)
                                                 .setUsage(rhi::TextureUsage::Sampled |
                                                           (compute ? rhi::TextureUsage::Storage : rhi::TextureUsage::RenderTarget))
                                                 .setDebugName("irradiance volume"));
    // Zero: every probe invalid (no weight) until its first relight.
    const std::vector<uint16_t> zeros(size_t(counts.x) * counts.z * 4, 0);
    for (uint32_t slice = 0; slice < counts.y * 9; ++slice)
        m_device.writeTexture(m_volumeTexture, {0, slice}, zeros.data(), zeros.size() * sizeof(uint16_t));

    GiVolumeUniforms uniforms;
    const glm::vec3 spacing = giProbeSpacing(m_volume);
    uniforms.origin = glm::vec4(giProbePositions(m_volume)[0], 1.0f);   // the grid's: probe 0 may have moved
    uniforms.spacing = glm::vec4(spacing, m_volume.normalBias);
    const bool visibility = m_volume.visibility && !m_bake.distanceMoments.empty();
    uniforms.counts = glm::ivec4(glm::ivec3(counts), visibility ? int(kGiVisibilityResolution) : 0);
    if (visibility) m_visibility = makeVisibilityTexture(m_device, m_bake);
    m_volumeUniforms = makeUniformBuffer(m_device, uniforms, "irradiance volume");
}

void ProbeGi::addPasses(PassGraph& graph, const SceneView&) {
    if (!m_active || graph.find("", gi_resources::kIrradianceVolume)) return;
    graph.publish("", gi_resources::kIrradianceVolume, ViewTarget{graph.importResource(gi_resources::kIrradianceVolume), m_volumeTexture, {}});
}

void ProbeGi::addViewBindings(rhi::BindingSetDesc& set) const {
    set.add(rhi::BindingItem::sampledTexture(JANUS_BINDING_GI_VOLUME, m_active ? m_volumeTexture : m_standInVolume, m_pointSampler))
        .add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_GI_UNIFORMS, m_active ? m_volumeUniforms : m_standInUniforms))
        .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_GI_VISIBILITY, m_visibility ? m_visibility : m_standInVisibility, m_pointSampler));
}

void ProbeGi::markDirty() {
    if (!m_active) return;
    m_cyclesDone = 0;
    m_nextRank = 0;
}

void ProbeGi::setLights(std::span<const Light> lights) {
    if (!m_active) return;
    const FrameUniforms lit = sceneFrameUniforms(lights, glm::vec3(m_relightFrame.ambientColor));
    std::copy(std::begin(lit.directionalLights), std::end(lit.directionalLights), std::begin(m_relightFrame.directionalLights));
    m_relightFrame.lightCounts.x = lit.lightCounts.x;
    if (m_frameUniforms) {
        const FrameUniforms frame = relightFrameUniforms();
        m_device.writeBuffer(m_frameUniforms, &frame, sizeof(frame));
    }
    m_cyclesDone = 0;
    m_nextRank = 0;
    m_volumeHasLight = false;
}

// The relight lights surfels as forward shading lights surfaces: the scene's directional lights
// (the main one shadowed), every local light (no tiles), the sky.
FrameUniforms ProbeGi::relightFrameUniforms() const {
    FrameUniforms frame = m_relightFrame;
    if (const DirectionalShadowMap* map = m_shadows.map()) {   // made by the relight's shadow-map pass setup
        frame.worldToShadow = map->worldToShadow();
        frame.shadowParams = glm::vec4(1.0f, map->texelSize(), map->normalOffset(), 0.0f);
    }
    return frame;
}

void ProbeGi::setupRelight() {
    if (m_brickPipeline) return;
    const bool compute = m_path == FeaturePath::Compute;
    auto computePipeline = [&](const char* shader, const char* name) {
        return m_device.createComputePipeline(
            rhi::ComputePipelineDesc{}.setShader(makeShader(m_device, rhi::ShaderStage::Compute, shader)).setDebugName(name));
    };
    auto graphicsPipeline = [&](const char* shader, const char* name, rhi::Format format, uint32_t targets) {
        rhi::GraphicsPipelineDesc desc;
        desc.setShaders(makeShader(m_device, rhi::ShaderStage::Vertex, "fullscreen_vert"), makeShader(m_device, rhi::ShaderStage::Fragment, shader))
            .setDebugName(name);
        for (uint32_t i = 0; i < targets; ++i) desc.addColorFormat(format);
        return m_device.createGraphicsPipeline(desc);
    };
    m_brickPipeline = compute ? computePipeline("gi_brick_radiance_comp", "gi brick radiance")
                              : graphicsPipeline("gi_brick_radiance_frag", "gi brick radiance", m_brickRadiance->desc().format, 1);
    m_shPipeline = compute ? computePipeline("gi_probe_sh_comp", "gi probe sh")
                           : graphicsPipeline("gi_probe_sh_frag", "gi probe sh", rhi::Format::RGBA16_FLOAT, kShCoefficientsPerDraw);

    m_frameUniforms = makeUniformBuffer(m_device, relightFrameUniforms(), "gi relight frame");
    m_relightParams = m_device.createBuffer(
        rhi::BufferDesc{}.setSize(sizeof(GiRelightParams)).setUsage(rhi::BufferUsage::Uniform).setDebugName("gi relight params"));

    rhi::BindingSetDesc brick;
    brick.add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_FRAME_UNIFORMS, m_frameUniforms))
        .add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_GI_RELIGHT_PARAMS, m_relightParams))
        .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_GI_SURFELS, m_surfels, m_pointSampler))
        .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_GI_BRICKS, m_bricks, m_pointSampler))
        .add(m_shadows.binding(JANUS_BINDING_SHADOW_MAP));
    m_localLights.addViewBindings(brick);
    m_imageBasedLighting.addViewBindings(brick);
    addViewBindings(brick);
    if (compute) brick.add(rhi::BindingItem::storageImage(JANUS_BINDING_GI_TARGET, m_brickRadiance, 0));
    m_brickBindings = m_device.createBindingSet(brick);

    rhi::BindingSetDesc sh;
    sh.add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_GI_RELIGHT_PARAMS, m_relightParams))
        .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_GI_TRANSFERS, m_transfers, m_pointSampler))
        .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_GI_PROBES, m_probes, m_pointSampler))
        .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_GI_BRICK_RADIANCE, m_brickRadiance, m_pointSampler));
    if (compute) sh.add(rhi::BindingItem::storageImage(JANUS_BINDING_GI_TARGET, m_volumeTexture, 0));
    m_shBindings = m_device.createBindingSet(sh);
}

GiRelightParams ProbeGi::relightParams(bool bounce) const {
    GiRelightParams params;
    params.counts = glm::ivec4(int(m_bake.bricks.size()), int(m_probeCount), bounce ? 1 : 0, m_volume.shOrder == 1 ? 4 : 9);
    params.grid = glm::ivec4(glm::ivec3(m_volume.probeCounts), 0);
    return params;
}

void ProbeGi::recordBrickRadiance(rhi::ICommandList& cmd, PassReport& report, bool bounce) {
    const GiRelightParams params = relightParams(bounce);
    cmd.writeBuffer(m_relightParams, &params, sizeof(params));
    if (m_path == FeaturePath::Compute) {
        cmd.setPipeline(m_brickPipeline);
        cmd.setBindingSet(0, m_brickBindings);
        cmd.dispatch(std::max<uint32_t>(1, uint32_t((m_bake.bricks.size() + kGroupSize - 1) / kGroupSize)), 1, 1);
        ++report.dispatches;
        return;
    }
    rhi::Attachment target = rhi::Attachment::clear(m_brickRadiance, {0, 0, 0, 0});
    target.loadOp = rhi::LoadOp::DontCare;   // every texel is written
    drawFullscreenTriangle(cmd, target, m_brickPipeline, m_brickBindings, report);
}

void ProbeGi::recordProbeSh(rhi::ICommandList& cmd, PassReport& report, uint32_t firstRank, uint32_t count, bool bounce) {
    GiRelightParams params = relightParams(bounce);
    params.schedule = glm::ivec4(int(firstRank), int(count), 0, m_volume.parallelReduction ? 0 : 1);
    if (m_path == FeaturePath::Compute) {
        cmd.writeBuffer(m_relightParams, &params, sizeof(params));
        cmd.setPipeline(m_shPipeline);
        cmd.setBindingSet(0, m_shBindings);
        cmd.dispatch(count, 1, 1);
        ++report.dispatches;
        return;
    }
    // One draw per layer y and group g of three coefficients, into slices y * 9 + 3g + j at once
    // (render passes cost the most on tilers and on llvmpipe; a third of them); fragments of probes
    // not relit now are discarded (Load keeps them).
    constexpr uint32_t kGroups = 9 / kShCoefficientsPerDraw;
    for (uint32_t draw = 0; draw < m_volume.probeCounts.y * kGroups; ++draw) {
        params.schedule.z = int(draw);
        cmd.writeBuffer(m_relightParams, &params, sizeof(params));
        rhi::RenderPassDesc pass;
        for (uint32_t j = 0; j < kShCoefficientsPerDraw; ++j)
            pass.addColor(rhi::Attachment::load(m_volumeTexture, {0, draw * kShCoefficientsPerDraw + j}));
        drawFullscreenTriangle(cmd, pass, m_shPipeline, m_shBindings, report);
    }
}

void ProbeGi::beginFrame(FrameReport& frame) {
    if (!relightPending()) return;
    PassGraph graph;
    SceneView view;
    view.name = "gi relight";
    m_shadows.addPasses(graph, view);
    std::vector<PassGraph::ResourceId> lightInputs;
    if (const ViewTarget* shadowMap = graph.find(view.name, frame_resources::kShadowMap)) lightInputs.push_back(shadowMap->resource);
    const PassGraph::ResourceId volume = graph.importResource(gi_resources::kIrradianceVolume);
    const bool compute = m_path == FeaturePath::Compute;
    const char* suffix = compute ? "-compute" : "-fallback";

    // A step relights m_probesPerStep probes; with every probe per step, all cycles run now.
    const uint32_t cycles = m_probesPerStep >= m_probeCount ? m_bounces - m_cyclesDone : 1;
    for (uint32_t c = 0; c < cycles; ++c) {
        const bool bounce = m_volumeHasLight || c > 0;
        const uint32_t firstRank = m_nextRank;
        const uint32_t count = std::min(m_probesPerStep, m_probeCount - firstRank);
        // Bricks are lit once per cycle, when it starts; the cycle's later frames (K probes per
        // frame) sum their probes from the same brick radiance, so every probe of a cycle sees the
        // same light and a frame costs only its K probes' sums.
        PassGraph::ResourceId brickRadiance;
        if (firstRank == 0) {
            brickRadiance = graph.addResource(fmt::format("gi brick radiance {}", c));
            PassGraph::PassDesc bricks;
            bricks.name = std::string("gi-brick-radiance") + suffix;
            bricks.view = view.name;
            bricks.reads = lightInputs;
            bricks.reads.push_back(volume);
            bricks.writes = {brickRadiance};
            bricks.setup = [this] { setupRelight(); };
            bricks.record = [this, bounce](rhi::ICommandList& cmd, PassReport& report) { recordBrickRadiance(cmd, report, bounce); };
            graph.addPass(std::move(bricks));
        } else {
            brickRadiance = graph.importResource("gi brick radiance");   // this cycle's, from an earlier frame
        }
        PassGraph::PassDesc sh;
        sh.name = std::string("gi-probe-sh") + suffix;
        sh.view = view.name;
        sh.setup = [this] { setupRelight(); };
        sh.reads = {brickRadiance};
        sh.writes = {volume};
        sh.record = [this, firstRank, count, bounce](rhi::ICommandList& cmd, PassReport& report) {
            recordProbeSh(cmd, report, firstRank, count, bounce);
        };
        graph.addPass(std::move(sh));
        m_nextRank = firstRank + count;
        if (m_nextRank >= m_probeCount) {
            m_nextRank = 0;
            ++m_cyclesDone;
            m_volumeHasLight = true;
        }
    }
    graph.markOutput(volume);
    graph.compile(m_device);
    for (PassReport& pass : graph.execute(m_device, m_commandList)) frame.passes.push_back(std::move(pass));
    frame.views.push_back(ViewReport{view.name, 0, 0});
}

std::vector<GiProbeSh> ProbeGi::readProbes() const {
    std::vector<GiProbeSh> result(m_probeCount);
    if (!m_active) return result;
    const glm::uvec3 counts = m_volume.probeCounts;
    std::vector<uint16_t> halves;
    for (uint32_t slice = 0; slice < counts.y * 9; ++slice) {
        const std::vector<std::byte> bytes = m_device.readTexture(m_volumeTexture, {0, slice});
        halves.resize(bytes.size() / 2);
        std::memcpy(halves.data(), bytes.data(), bytes.size());
        const uint32_t y = slice / 9, k = slice % 9;
        for (uint32_t z = 0; z < counts.z; ++z)
            for (uint32_t x = 0; x < counts.x; ++x) {
                const uint16_t* h = halves.data() + (size_t(z) * counts.x + x) * 4;
                GiProbeSh& probe = result[x + counts.x * (y + counts.y * z)];
                probe.coefficients[k] = glm::vec3(glm::unpackHalf1x16(h[0]), glm::unpackHalf1x16(h[1]), glm::unpackHalf1x16(h[2]));
                if (k == 0) probe.valid = glm::unpackHalf1x16(h[3]) > 0.5f;
            }
    }
    return result;
}

void ProbeGi::writeProbes(std::span<const GiProbeSh> probes) {
    if (!m_active) return;
    const glm::uvec3 counts = m_volume.probeCounts;
    std::vector<uint16_t> halves(size_t(counts.x) * counts.z * 4);
    for (uint32_t slice = 0; slice < counts.y * 9; ++slice) {
        const uint32_t y = slice / 9, k = slice % 9;
        for (uint32_t z = 0; z < counts.z; ++z)
            for (uint32_t x = 0; x < counts.x; ++x) {
                const GiProbeSh& probe = probes[x + counts.x * (y + counts.y * z)];
                uint16_t* h = halves.data() + (size_t(z) * counts.x + x) * 4;
                for (int c = 0; c < 3; ++c) h[c] = glm::packHalf1x16(probe.coefficients[k][c]);
                h[3] = glm::packHalf1x16(k == 0 ? (probe.valid ? 1.0f : 0.0f) : 0.0f);
            }
        m_device.writeTexture(m_volumeTexture, {0, slice}, halves.data(), halves.size() * sizeof(uint16_t));
    }
    m_cyclesDone = m_bounces;
    m_nextRank = 0;
    m_volumeHasLight = true;
}

}  // namespace janus::renderer
