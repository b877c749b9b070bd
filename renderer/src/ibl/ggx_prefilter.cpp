#include "ibl/ggx_prefilter.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <glm/gtc/packing.hpp>

#include "core/gpu_util.h"
#include "ibl/environment_map.h"
#include "janus/shaders/bindings.h"

namespace janus::renderer {
namespace {

constexpr uint32_t kGroupSize = 8;   // ggx_prefilter.comp local_size

// std140 mirrors of ggx_common.glsl's PrefilterParams and PrefilterSamples, and ggx_bright.glsl's
// BrightParams.
struct PrefilterParams {
    glm::ivec4 params;   // x face, y mip, z size, w sample count
    glm::vec4 lobe;      // bright-texel variant: x alpha^2, y Z, z source face size, w 1 = split this mip
};
struct BrightParams {
    glm::ivec4 params;   // x face (fallback split), y source face size, z top level, w list capacity
    glm::vec4 limits;    // x threshold (times the mean r + g + b), y the alpha marker
};
// The split marks a bright texel with this alpha; the rest's box-filtered alpha then counts them
// exactly in half floats (powers of two; a 2048^2 face's top level still holds 1 texel as 2^-14, a
// normal half).
constexpr float kBrightMarker = 256.0f;
constexpr uint32_t kListGroupX = 64;   // ggx_bright_list.comp local size
constexpr uint64_t kBrightListBlockBytes = 16384;   // ggx_common.glsl PrefilterBrightList: 1024 uvec4

bool isPowerOfTwo(uint32_t v) { return v != 0 && (v & (v - 1)) == 0; }
uint32_t log2u(uint32_t v) {
    uint32_t l = 0;
    while (v > 1) v >>= 1, ++l;
    return l;
}
struct PrefilterSamples {
    glm::vec4 samples[kMaxGgxSamples];
};
static_assert(sizeof(PrefilterSamples) <= 16384, "the minimum uniform block size of GLES 3.0 / GL / Vulkan");

}  // namespace

GgxPrefilter::GgxPrefilter(rhi::IDevice& device, FeaturePath path, GgxPrefilterSettings settings)
    : m_device(device), m_path(path), m_settings(std::move(settings)) {
    const rhi::Capabilities& caps = device.capabilities();
    if (path == FeaturePath::Compute && !(caps.compute && caps.storageImages))
        throw RendererError("GGX prefilter: the compute path needs Capability::Compute and StorageImages");
    if (path == FeaturePath::Fallback && !caps.renderToCubeFaceMip)
        throw RendererError("GGX prefilter: the fallback path needs Capability::RenderToCubeFaceMip");
    if (m_settings.samplesPerMip.empty()) throw RendererError("GGX prefilter: samplesPerMip is empty");
    for (uint32_t n : m_settings.samplesPerMip)
        if (n == 0 || n > kMaxGgxSamples)
            throw RendererError(fmt::format("GGX prefilter: {} samples per mip is outside 1..{}", n, kMaxGgxSamples));
    for (float r : m_settings.roughness)
        if (!(r >= 0.0f && r <= 1.0f)) throw RendererError(fmt::format("GGX prefilter: roughness {} is outside [0, 1]", r));
    if (!std::isfinite(m_settings.lodBias)) throw RendererError("GGX prefilter: the lod bias is not finite");
    if (m_settings.brightTexels > kMaxGgxBrightTexels)
        throw RendererError(fmt::format("GGX prefilter: {} bright texels is above the most, {}", m_settings.brightTexels, kMaxGgxBrightTexels));
    if (!(std::isfinite(m_settings.brightThreshold) && m_settings.brightThreshold >= 1.0f))
        throw RendererError(fmt::format("GGX prefilter: the bright threshold {} is not a finite number >= 1", m_settings.brightThreshold));
    rhi::SamplerDesc sampler;
    sampler.setFilter(rhi::Filter::Linear).setAddress(rhi::AddressMode::ClampToEdge);
    m_sampler = device.createSampler(sampler);
    if (m_settings.brightTexels > 0) {
        rhi::SamplerDesc nearest;
        nearest.setFilter(rhi::Filter::Nearest).setAddress(rhi::AddressMode::ClampToEdge);
        m_nearest = device.createSampler(nearest);
    }
}

float GgxPrefilter::roughnessForMip(uint32_t mip) const {
    if (mip < m_settings.roughness.size() && mip > 0) return m_settings.roughness[mip];
    return ggxRoughnessForMip(mip, m_mipCount);
}

void GgxPrefilter::bindSource(const rhi::TextureHandle& source) {
    const rhi::TextureDesc& desc = source->desc();
    if (desc.dimension != rhi::TextureDimension::TextureCube)
        throw RendererError("GGX prefilter: the source must be a cube map");
    const uint32_t full = rhi::fullMipCount(desc.width, desc.width);
    if (desc.mipLevels != full)
        throw RendererError(fmt::format("GGX prefilter: the source cube needs its full chain ({} mips), it has {}", full, desc.mipLevels));
    const uint32_t mipCount = m_settings.mipCount == 0 ? full : m_settings.mipCount;
    if (mipCount > full)
        throw RendererError(fmt::format("GGX prefilter: {} mips asked for, a {}^2 cube has at most {}", mipCount, desc.width, full));
    const bool reuse = m_target && m_target->desc().width == desc.width && m_target->desc().format == desc.format &&
                       m_mipCount == mipCount && m_source == source;
    if (!reuse) {
        m_pipeline.reset();
        m_source = source;
        m_mipCount = mipCount;
        const rhi::TextureUsage usage =
            rhi::TextureUsage::Sampled | (m_path == FeaturePath::Compute ? rhi::TextureUsage::Storage : rhi::TextureUsage::RenderTarget);
        m_target = m_device.createTexture(rhi::TextureDesc{}
                                              .setDimension(rhi::TextureDimension::TextureCube)
                                              .setFormat(desc.format)
                                              .setSize(desc.width, desc.width)
                                              .setMipLevels(mipCount)
                                              .setUsage(usage)
                                              .setDebugName(m_settings.debugName));
        m_sets.assign(mipCount, GgxSampleSet{});
        for (uint32_t mip = 1; mip < mipCount; ++mip)
            m_sets[mip] = makeGgxSampleSet(roughnessForMip(mip), ggxSamplesForMip(m_settings.samplesPerMip, mip), desc.width,
                                           desc.mipLevels, m_settings.lodBias);
        m_brightSplit = m_settings.brightTexels > 0 && isPowerOfTwo(desc.width);
        m_rest.reset();
        m_brightList.reset();
        m_brightListBuffer.reset();
        if (m_brightSplit) {
            m_rest = m_device.createTexture(rhi::TextureDesc{}
                                                .setDimension(rhi::TextureDimension::TextureCube)
                                                .setFormat(rhi::Format::RGBA16_FLOAT)
                                                .setSize(desc.width, desc.width)
                                                .setMipLevels(desc.mipLevels)
                                                .setUsage(usage)
                                                .setDebugName(m_settings.debugName + " bright-texel rest"));
            m_brightList = m_device.createTexture(rhi::TextureDesc{}
                                                      .setFormat(rhi::Format::RGBA16_FLOAT)
                                                      .setSize(2 * (m_settings.brightTexels + 1), 1)
                                                      .setUsage(usage)
                                                      .setDebugName(m_settings.debugName + " bright-texel list"));
            // The whole block, so the binding covers what the shader declares; the copy fills the front.
            m_brightListBuffer = m_device.createBuffer(rhi::BufferDesc{}
                                                           .setSize(kBrightListBlockBytes)
                                                           .setUsage(rhi::BufferUsage::Uniform)
                                                           .setDebugName(m_settings.debugName + " bright-texel list"));
            const std::vector<std::byte> zeros(kBrightListBlockBytes);
            m_device.writeBuffer(m_brightListBuffer, zeros.data(), zeros.size());
        }
    }
}

void GgxPrefilter::prepare(const rhi::TextureHandle& source) {
    bindSource(source);
    setup();
}

ViewTarget GgxPrefilter::addPasses(PassGraph& graph, const ViewTarget& source) {
    bindSource(source.texture);
    ViewTarget target;
    target.resource = graph.addResource(ibl_resources::kPrefilteredEnvironment);
    target.texture = m_target;
    PassGraph::PassDesc pass;
    pass.name = m_path == FeaturePath::Compute ? "ggx-prefilter-compute" : "ggx-prefilter-fallback";
    pass.reads = {source.resource};
    pass.writes = {target.resource};
    pass.setup = [this] { setup(); };
    pass.record = [this](rhi::ICommandList& cmd, PassReport& report) { record(cmd, report); };
    graph.addPass(std::move(pass));
    graph.publish("", ibl_resources::kPrefilteredEnvironment, target);
    return target;
}

void GgxPrefilter::setup() {
    if (m_pipeline) return;
    m_bindings.clear();
    m_buffers.clear();
    m_splitBindings.clear();
    m_listBindings.reset();
    const bool compute = m_path == FeaturePath::Compute;
    auto computePipeline = [&](const char* shader, const char* name) {
        return m_device.createComputePipeline(
            rhi::ComputePipelineDesc{}.setShader(makeShader(m_device, rhi::ShaderStage::Compute, shader)).setDebugName(name));
    };
    auto graphicsPipeline = [&](const char* shader, const char* name, rhi::Format format = rhi::Format::RGBA16_FLOAT,
                                const char* vertex = "fullscreen_vert") {
        return m_device.createGraphicsPipeline(rhi::GraphicsPipelineDesc{}
                                                   .setShaders(makeShader(m_device, rhi::ShaderStage::Vertex, vertex),
                                                               makeShader(m_device, rhi::ShaderStage::Fragment, shader))
                                                   .addColorFormat(format)
                                                   .setDebugName(name));
    };
    const rhi::Format targetFormat = m_target->desc().format;
    if (m_brightSplit) {
        m_pipeline = compute ? computePipeline("ggx_prefilter_bright_comp", "ggx prefilter (bright texels)")
                             : graphicsPipeline("ggx_prefilter_bright_frag", "ggx prefilter (bright texels)", targetFormat);
        m_splitPipeline = compute ? computePipeline("ggx_bright_split_comp", "ggx bright-texel split")
                                  : graphicsPipeline("ggx_bright_split_frag", "ggx bright-texel split", rhi::Format::RGBA16_FLOAT,
                                                     "ggx_bright_split_vert");
        m_listPipeline = compute ? computePipeline("ggx_bright_list_comp", "ggx bright-texel list")
                                 : graphicsPipeline("ggx_bright_list_frag", "ggx bright-texel list");
        const uint32_t size = m_source->desc().width;
        for (int face = 0; face < (compute ? 1 : 6); ++face) {
            const BrightParams values{glm::ivec4(face, int(size), int(log2u(size)), int(m_settings.brightTexels)),
                                      glm::vec4(m_settings.brightThreshold, kBrightMarker, 0.0f, 0.0f)};
            const rhi::BufferHandle params = makeUniformBuffer(m_device, values, "ggx bright params");
            m_buffers.push_back(params);
            rhi::BindingSetDesc split;
            split.add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_BRIGHT_PARAMS, params))
                .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_BRIGHT_SOURCE, m_source, m_nearest));
            if (compute) split.add(rhi::BindingItem::storageImage(JANUS_BINDING_BRIGHT_TARGET, m_rest, 0));
            m_splitBindings.push_back(m_device.createBindingSet(split));
            if (face == 0) {
                rhi::BindingSetDesc list;
                list.add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_BRIGHT_PARAMS, params))
                    .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_BRIGHT_SOURCE, m_source, m_nearest))
                    .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_BRIGHT_REST, m_rest, m_nearest));
                if (compute) list.add(rhi::BindingItem::storageImage(JANUS_BINDING_BRIGHT_TARGET, m_brightList, 0));
                m_listBindings = m_device.createBindingSet(list);
            }
        }
    } else {
        m_pipeline = compute ? computePipeline("ggx_prefilter_comp", "ggx prefilter")
                             : graphicsPipeline("ggx_prefilter_frag", "ggx prefilter", targetFormat);
    }
    const uint32_t size0 = m_target->desc().width;
    for (uint32_t mip = 1; mip < m_mipCount; ++mip) {
        PrefilterSamples samples{};
        const GgxSampleSet& set = m_sets[mip];
        for (size_t i = 0; i < set.samples.size(); ++i) samples.samples[i] = glm::vec4(set.samples[i].direction, set.samples[i].lod);
        const rhi::BufferHandle sampleBuffer = makeUniformBuffer(m_device, samples, "ggx samples");
        m_buffers.push_back(sampleBuffer);
        const int size = int(std::max(1u, size0 >> mip));
        const int count = int(set.samples.size());
        const double alpha = double(set.roughness) * double(set.roughness);
        // The mirror (one sample at N, alpha below 1e-6) reads the source itself: no split.
        const bool split = m_brightSplit && set.normalization > 0.0;
        const glm::vec4 lobe(float(alpha * alpha), float(set.normalization), float(m_source->desc().width), split ? 1.0f : 0.0f);
        const int faces = compute ? 1 : 6;
        for (int face = 0; face < faces; ++face) {
            const rhi::BufferHandle params =
                makeUniformBuffer(m_device, PrefilterParams{glm::ivec4(face, int(mip), size, count), lobe}, "ggx prefilter params");
            m_buffers.push_back(params);
            rhi::BindingSetDesc bindings;
            bindings.add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_PREFILTER_PARAMS, params))
                .add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_PREFILTER_SAMPLES, sampleBuffer))
                .add(rhi::BindingItem::sampledTexture(JANUS_BINDING_PREFILTER_SOURCE, m_source, m_sampler));
            if (m_brightSplit)
                bindings.add(rhi::BindingItem::sampledTexture(JANUS_BINDING_PREFILTER_REST, m_rest, m_sampler))
                    .add(rhi::BindingItem::uniformBuffer(JANUS_BINDING_PREFILTER_BRIGHT_LIST, m_brightListBuffer));
            if (compute) bindings.add(rhi::BindingItem::storageImage(JANUS_BINDING_PREFILTER_TARGET, m_target, mip));
            m_bindings.push_back(m_device.createBindingSet(bindings));
        }
    }
}

void GgxPrefilter::record(rhi::ICommandList& cmd, PassReport& report) { recordMips(cmd, report, 0, m_mipCount); }

double GgxPrefilter::mipCost(uint32_t mip) const {
    if (mip == 0 || mip >= m_mipCount) return 0.0;
    const double size = std::max(1u, m_target->desc().width >> mip);
    return size * size * 6.0 * double(m_sets[mip].samples.size());
}

void GgxPrefilter::recordMips(rhi::ICommandList& cmd, PassReport& report, uint32_t firstMip, uint32_t endMip) {
    if (!m_pipeline) throw RendererError("GGX prefilter: recordMips() before prepare() or the pass's setup");
    endMip = std::min(endMip, m_mipCount);
    if (firstMip == 0) {
        if (m_source->desc().mipLevels > 1) cmd.generateMips(m_source);
        for (uint32_t face = 0; face < 6; ++face) cmd.copyTexture(m_target, {0, face}, m_source, {0, face});
        if (m_brightSplit) recordBrightSplit(cmd, report);
    }
    const uint32_t size0 = m_target->desc().width;
    for (uint32_t mip = std::max(1u, firstMip); mip < endMip; ++mip) {
        const uint32_t size = std::max(1u, size0 >> mip);
        if (m_path == FeaturePath::Compute) {
            cmd.setPipeline(m_pipeline);
            cmd.setBindingSet(0, m_bindings[mip - 1]);
            const uint32_t groups = (size + kGroupSize - 1) / kGroupSize;
            cmd.dispatch(groups, groups, 6);
            ++report.dispatches;
            continue;
        }
        for (uint32_t face = 0; face < 6; ++face) {
            rhi::Attachment target = rhi::Attachment::clear(m_target, {0, 0, 0, 0}, {mip, face});
            target.loadOp = rhi::LoadOp::DontCare;   // every texel is written
            drawFullscreenTriangle(cmd, target, m_pipeline, m_bindings[(mip - 1) * 6 + face], report);
        }
    }
}

void GgxPrefilter::recordBrightSplit(rhi::ICommandList& cmd, PassReport& report) {
    const uint32_t size = m_source->desc().width;
    // 1. The rest's mip 0: the source without its bright texels (their alpha = the marker).
    if (m_path == FeaturePath::Compute) {
        cmd.setPipeline(m_splitPipeline);
        cmd.setBindingSet(0, m_splitBindings[0]);
        const uint32_t groups = (size + kGroupSize - 1) / kGroupSize;
        cmd.dispatch(groups, groups, 6);
        ++report.dispatches;
    } else {
        for (uint32_t face = 0; face < 6; ++face) {
            rhi::Attachment target = rhi::Attachment::clear(m_rest, {0, 0, 0, 0}, {0, face});
            target.loadOp = rhi::LoadOp::DontCare;   // every texel is written
            drawFullscreenTriangle(cmd, target, m_splitPipeline, m_splitBindings[face], report);
        }
    }
    // 2. Its box-filtered chain: what the samples read, and (alpha) how many bright texels each texel holds.
    if (m_rest->desc().mipLevels > 1) cmd.generateMips(m_rest);
    // 3. The list, found down that count chain.
    if (m_path == FeaturePath::Compute) {
        cmd.setPipeline(m_listPipeline);
        cmd.setBindingSet(0, m_listBindings);
        cmd.dispatch((2 * (m_settings.brightTexels + 1) + kListGroupX - 1) / kListGroupX, 1, 1);
        ++report.dispatches;
    } else {
        rhi::Attachment target = rhi::Attachment::clear(m_brightList, {0, 0, 0, 0}, {0, 0});
        target.loadOp = rhi::LoadOp::DontCare;
        drawFullscreenTriangle(cmd, target, m_listPipeline, m_listBindings, report);
    }
    // 4. Into a uniform block: every prefiltered texel reads all of it (a copy, not a draw).
    cmd.copyTextureToBuffer(m_brightListBuffer, 0, m_brightList, {0, 0});
}

GgxBrightTexels GgxPrefilter::readBrightTexels() const {
    GgxBrightTexels result;
    if (!m_brightSplit || !m_brightList) return result;
    const uint32_t width = m_brightList->desc().width;   // 2 texels per entry, the header first
    const std::vector<std::byte> bytes = m_device.readTexture(m_brightList, {0, 0});
    if (bytes.size() != size_t(width) * 4 * 2)
        throw RendererError(fmt::format("GGX prefilter: the bright-texel list read back as {} bytes", bytes.size()));
    auto value = [&](uint32_t column, uint32_t c) {
        uint16_t half;
        std::memcpy(&half, bytes.data() + (size_t(column) * 4 + c) * 2, 2);
        return glm::unpackHalf1x16(half);
    };
    result.found = uint32_t(value(0, 2) + 0.5f);
    result.overflow = value(0, 1) > 0.5f;
    const uint32_t count = uint32_t(value(0, 0) + 0.5f);
    for (uint32_t k = 0; k < count && 2 * k + 3 < width && !result.overflow; ++k) {
        const uint32_t column = 2 * k + 2;
        if (value(column, 3) < 0.5f) continue;
        GgxBrightTexels::Texel t;
        t.radiance = {value(column, 0), value(column, 1), value(column, 2)};
        t.face = uint32_t(value(column + 1, 0) + 0.5f);
        t.x = uint32_t(value(column + 1, 1) + 0.5f);
        t.y = uint32_t(value(column + 1, 2) + 0.5f);
        result.texels.push_back(t);
    }
    return result;
}

PassReport GgxPrefilter::run(const rhi::TextureHandle& source) {
    PassGraph graph;
    ViewTarget input;
    input.resource = graph.importResource("prefilter source");
    input.texture = source;
    const ViewTarget output = addPasses(graph, input);
    graph.markOutput(output.resource);
    graph.compile(m_device);
    std::vector<PassReport> reports = graph.execute(m_device, m_device.createCommandList());
    return reports.empty() ? PassReport{} : reports.front();
}

FloatCube readCube(rhi::IDevice& device, const rhi::TextureHandle& cube, uint32_t mip) {
    const rhi::TextureDesc& desc = cube->desc();
    FloatCube image;
    image.size = std::max(1u, desc.width >> mip);
    const size_t values = size_t(image.size) * image.size * 4;
    for (uint32_t face = 0; face < 6; ++face) {
        const std::vector<std::byte> bytes = device.readTexture(cube, {mip, face});
        std::vector<float>& out = image.faces[face];
        out.resize(values);
        if (desc.format == rhi::Format::RGBA32_FLOAT && bytes.size() == values * 4) {
            std::memcpy(out.data(), bytes.data(), bytes.size());
        } else if (desc.format == rhi::Format::RGBA16_FLOAT && bytes.size() == values * 2) {
            for (size_t i = 0; i < values; ++i) {
                uint16_t half;
                std::memcpy(&half, bytes.data() + i * 2, 2);
                out[i] = glm::unpackHalf1x16(half);
            }
        } else {
            throw RendererError(fmt::format("readCube: {} bytes for a {}^2 {} face", bytes.size(), image.size, rhi::toString(desc.format)));
        }
    }
    return image;
}

GgxReference::GgxReference(const FloatCube& cube) {
    m_texels.reserve(size_t(cube.size) * cube.size * 6);
    for (uint32_t face = 0; face < 6; ++face)
        for (uint32_t y = 0; y < cube.size; ++y)
            for (uint32_t x = 0; x < cube.size; ++x)
                m_texels.push_back(
                    Texel{cubeTexelDirection(face, x, y, cube.size), cubeTexelSolidAngle(x, y, cube.size), cube.texel(face, x, y)});
}

glm::dvec3 GgxReference::radiance(const glm::dvec3& normal, double roughness, Normalization normalization) const {
    const glm::dvec3 n = glm::normalize(normal);
    const double alpha = roughness * roughness;
    if (alpha < 1e-6) {
        const Texel* nearest = nullptr;
        double best = -2.0;
        for (const Texel& t : m_texels)
            if (double c = glm::dot(t.direction, n); c > best) {
                best = c;
                nearest = &t;
            }
        return nearest ? nearest->radiance : glm::dvec3(0.0);
    }
    glm::dvec3 sum(0.0);
    double weight = 0.0;
    for (const Texel& t : m_texels) {
        const double nDotL = glm::dot(n, t.direction);
        if (nDotL <= 0.0) continue;
        const glm::dvec3 h = glm::normalize(n + t.direction);   // |n + l| > 0 since n.l > 0
        const double w = ggxDistribution(std::max(0.0, glm::dot(n, h)), alpha) * nDotL * t.solidAngle;
        sum += t.radiance * w;
        weight += w;
    }
    if (normalization == Normalization::Exact) weight = ggxLobeNormalization(alpha);
    return weight > 0.0 ? sum / weight : glm::dvec3(0.0);
}

}  // namespace janus::renderer
