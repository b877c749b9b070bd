#include "core/gpu_scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <tuple>
#include <utility>

#include <fmt/format.h>
#include <glm/gtc/matrix_inverse.hpp>

#include "core/gpu_util.h"
#include "core/parallel.h"
#include "scene/scene_internal.h"
#include "core/texture_fit.h"
#include "core/texture_mips.h"
#include "janus/shaders/bindings.h"

namespace janus::renderer {
namespace {

// std140 mirror of forward_common.glsl's DrawUniforms block.
struct DrawUniforms {
    glm::mat4 world;
    glm::mat4 normalMatrix;
    glm::vec4 baseColorFactor;
    glm::vec4 emissiveFactor;
    glm::vec4 materialParams;
    glm::ivec4 flags;
    glm::vec4 dielectricSpecular;   // rgb F0, w F90 of the non-metal part
    glm::ivec4 shading;             // x 1 = unlit, y the instance's index (the GI bake's G-buffer)
    // Per material texture (kTexture* in forward_common.glsl) two rows of its KHR_texture_transform
    // matrix; the first row's w is the UV set it reads (0 or 1).
    glm::vec4 textureTransforms[10];
};
static_assert(sizeof(DrawUniforms) == 384, "DrawUniforms must match std140");

// The two rows of `transform`'s 3x3 matrix that matter (the third is 0 0 1), for textureTransforms.
void packTextureTransform(const TextureTransform& transform, glm::vec4* rows) {
    const glm::mat3 m = transform.matrix();   // column-major: m[column][row]
    rows[0] = glm::vec4(m[0][0], m[1][0], m[2][0], float(transform.texCoord));
    rows[1] = glm::vec4(m[0][1], m[1][1], m[2][1], 0.0f);
}

// The matrix that carries normals: the inverse transpose, or, for a world matrix that squashes an
// axis to zero (no inverse: Inf/NaN), its cofactor matrix, which is the inverse transpose times
// the determinant wherever that exists and stays finite where it does not (shading normalises).
glm::mat4 normalMatrixOf(const glm::mat4& world) {
    const glm::mat4 inverseTranspose = glm::inverseTranspose(world);
    bool finite = true;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) finite = finite && std::isfinite(inverseTranspose[c][r]);
    if (finite && glm::determinant(glm::mat3(world)) != 0.0f) return inverseTranspose;
    const glm::mat3 m(world);
    glm::mat3 cofactor;
    cofactor[0] = glm::cross(m[1], m[2]);
    cofactor[1] = glm::cross(m[2], m[0]);
    cofactor[2] = glm::cross(m[0], m[1]);
    return glm::mat4(cofactor);
}
static_assert(sizeof(Vertex) == 80 && offsetof(Vertex, normal) == 12 && offsetof(Vertex, uv) == 24 && offsetof(Vertex, tangent) == 32 &&
                  offsetof(Vertex, uv1) == 48 && offsetof(Vertex, color) == 56,
              "the mesh pipelines' vertex layout assumes a tightly packed Vertex");

}  // namespace

GpuScene::GpuScene(rhi::IDevice& device, const Scene& scene) : m_device(device) {
    uploadTextures(scene);
    uploadMeshes(scene);
    createDraws(scene);
}

rhi::TextureHandle GpuScene::createTexture(const std::string& name, uint32_t width, uint32_t height, std::span<const uint8_t> rgba,
                                                 bool srgb, const std::vector<std::vector<uint8_t>>& mipsBelow) {
    rhi::TextureHandle texture = m_device.createTexture(rhi::TextureDesc{}
                                                          .setFormat(srgb ? rhi::Format::RGBA8_SRGB : rhi::Format::RGBA8_UNORM)
                                                          .setSize(width, height)
                                                          .setMipLevels(uint32_t(mipsBelow.size()) + 1)
                                                          .setUsage(rhi::TextureUsage::Sampled)
                                                          .setDebugName(name));
    m_device.writeTexture(texture, rhi::TextureSubresource{0, 0}, rgba.data(), rgba.size());
    for (size_t level = 0; level < mipsBelow.size(); ++level)
        m_device.writeTexture(texture, rhi::TextureSubresource{uint32_t(level) + 1, 0}, mipsBelow[level].data(), mipsBelow[level].size());
    return texture;
}

rhi::SamplerHandle GpuScene::createSampler(const TextureSampling& sampling) {
    auto address = [](TextureWrap wrap) {
        switch (wrap) {
            case TextureWrap::ClampToEdge: return rhi::AddressMode::ClampToEdge;
            case TextureWrap::MirroredRepeat: return rhi::AddressMode::MirroredRepeat;
            default: return rhi::AddressMode::Repeat;
        }
    };
    rhi::SamplerDesc desc;
    desc.magFilter = sampling.nearestMagnification ? rhi::Filter::Nearest : rhi::Filter::Linear;
    desc.minFilter = sampling.nearestMinification ? rhi::Filter::Nearest : rhi::Filter::Linear;
    desc.mipFilter = sampling.nearestMip ? rhi::Filter::Nearest : rhi::Filter::Linear;
    desc.addressU = address(sampling.wrapU);
    desc.addressV = address(sampling.wrapV);
    if (!sampling.mipmapped) desc.setLodRange(0.0f, 0.0f);   // glTF NEAREST / LINEAR minification: mip 0 only
    return m_device.createSampler(desc);
}

void GpuScene::uploadTextures(const Scene& scene) {
    constexpr std::array<uint8_t, 4> kWhite{255, 255, 255, 255}, kFlatNormal{128, 128, 255, 255};
    m_whiteTexture = createTexture("default white", 1, 1, kWhite, false, {});
    m_flatNormalTexture = createTexture("default normal", 1, 1, kFlatNormal, false, {});
    m_materialSampler = m_device.createSampler(rhi::SamplerDesc{});
    std::vector<std::pair<TextureSampling, rhi::SamplerHandle>> samplers{{TextureSampling{}, m_materialSampler}};
    const uint32_t maxSide = m_device.capabilities().limits.maxTextureSize2D;
    // The CPU's share of each texture (fitting it to the device, its mip chain) on every core; the
    // uploads then go to the device in the scene's order.
    struct Prepared {
        std::optional<TextureImage> fitted;   // larger than the device holds: downscaled rather than refused (docs/SCENES.md)
        std::vector<std::vector<uint8_t>> mipsBelow;
    };
    std::vector<Prepared> prepared(scene.textures.size());
    parallelFor(prepared.size(), parallelThreads(0, prepared.size()), [&](size_t i) {
        const TextureImage& image = scene.textures[i];
        Prepared& p = prepared[i];
        if (maxSide > 0 && (image.width > maxSide || image.height > maxSide)) p.fitted = fitTextureToSize(image, maxSide);
        const TextureImage& source = p.fitted ? *p.fitted : image;
        p.mipsBelow = mipChainBelow(source.rgba, source.width, source.height, source.srgb);
    });
    for (size_t i = 0; i < scene.textures.size(); ++i) {
        const TextureImage& image = scene.textures[i];
        Prepared& p = prepared[i];
        if (p.fitted)
            fmt::print(stderr,
                       "janus: warning: texture '{}' is {}x{}, larger than the device's largest 2D texture ({}); uploading it "
                       "downscaled to {}x{}\n",
                       image.name, image.width, image.height, maxSide, p.fitted->width, p.fitted->height);
        const TextureImage& source = p.fitted ? *p.fitted : image;
        m_textures.push_back(createTexture(source.name, source.width, source.height, source.rgba, source.srgb, p.mipsBelow));
        p = Prepared{};   // uploaded: its memory goes now rather than with the rest
        auto it = std::find_if(samplers.begin(), samplers.end(), [&](const auto& s) { return s.first == image.sampling; });
        if (it == samplers.end()) it = samplers.insert(samplers.end(), {image.sampling, createSampler(image.sampling)});
        m_textureSamplers.push_back(it->second);
    }
    m_pointSampler = m_device.createSampler(rhi::SamplerDesc{}.setFilter(rhi::Filter::Nearest).setAddress(rhi::AddressMode::ClampToEdge));
}

void GpuScene::uploadMeshes(const Scene& scene) {
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const renderer::Mesh& mesh = scene.meshes[m];
        Mesh gpu;
        gpu.indexCount = uint32_t(mesh.indices.size());
        if (!mesh.vertices.empty() && !mesh.indices.empty()) {
            const uint64_t vertexBytes = mesh.vertices.size() * sizeof(Vertex);
            const uint64_t indexBytes = mesh.indices.size() * sizeof(uint32_t);
            gpu.vertices = m_device.createBuffer(
                rhi::BufferDesc{}.setSize(vertexBytes).setUsage(rhi::BufferUsage::Vertex).setDebugName(fmt::format("mesh {} vertices", m)));
            gpu.indices = m_device.createBuffer(
                rhi::BufferDesc{}.setSize(indexBytes).setUsage(rhi::BufferUsage::Index).setDebugName(fmt::format("mesh {} indices", m)));
            m_device.writeBuffer(gpu.vertices, mesh.vertices.data(), vertexBytes);
            m_device.writeBuffer(gpu.indices, mesh.indices.data(), indexBytes);
        }
        m_meshes.push_back(std::move(gpu));
    }
}

void GpuScene::useInstanceVertices(uint32_t instance, rhi::BufferHandle vertices) {
    for (std::vector<Draw>* draws : {&m_draws, &m_blendedDraws})
        for (Draw& draw : *draws)
            if (draw.instance == instance) draw.vertices = vertices;
    m_instanceVertices.at(instance) = std::move(vertices);
}

const rhi::BufferHandle& GpuScene::instanceVertices(uint32_t instance) const { return m_instanceVertices.at(instance); }

void GpuScene::createDraws(const Scene& scene) {
    for (const Instance& instance : scene.instances) m_instanceVertices.push_back(m_meshes[instance.mesh].vertices);
    // One slot per draw in a single uniform buffer; one binding set shows a slot at a time, moved
    // to a draw's slot by the offset given with each bind (dynamic offsets: no set per draw).
    const uint64_t stride =
        alignUp(sizeof(DrawUniforms), std::max<uint32_t>(m_device.capabilities().limits.uniformBufferOffsetAlignment, 16));
    std::vector<std::byte> drawData(std::max<size_t>(scene.instances.size(), 1) * stride);
    m_drawUniforms = m_device.createBuffer(
        rhi::BufferDesc{}.setSize(drawData.size()).setUsage(rhi::BufferUsage::Uniform).setDebugName("draw uniforms"));
    const Material defaultMaterial;
    // Material sets by scene material index (the last: meshes without a material), made for the
    // materials some draw uses.
    std::vector<uint32_t> materialSet(scene.materials.size() + 1, UINT32_MAX);
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        const renderer::Mesh& mesh = scene.meshes[instance.mesh];
        if (m_meshes[instance.mesh].indexCount == 0) continue;
        const Material& material = mesh.material >= 0 ? scene.materials[size_t(mesh.material)] : defaultMaterial;
        const bool hasTangents = std::any_of(mesh.vertices.begin(), mesh.vertices.end(),
                                             [](const Vertex& v) { return v.tangent != glm::vec4(0.0f); });
        DrawUniforms uniforms{};
        uniforms.world = instance.world;
        uniforms.normalMatrix = normalMatrixOf(instance.world);
        uniforms.baseColorFactor = material.baseColorFactor;
        uniforms.emissiveFactor = glm::vec4(material.emissiveFactor * material.emissiveStrength, material.alphaCutoff);
        uniforms.dielectricSpecular = glm::vec4(material.dielectricF0(), material.dielectricF90());
        uniforms.shading = glm::ivec4(material.unlit || mesh.unlit ? 1 : 0, int32_t(std::min<size_t>(i, INT32_MAX)), 0, 0);
        uniforms.materialParams = glm::vec4(material.metallicFactor, material.roughnessFactor, material.normalScale, material.occlusionStrength);
        // Normal maps need tangents; meshes without them shade with their vertex normals.
        // flags.z is the alpha mode as forward.frag reads it: 0 opaque, 1 mask, 2 blend.
        const int32_t alphaMode = material.alphaMode == AlphaMode::Mask ? 1 : material.alphaMode == AlphaMode::Blend ? 2 : 0;
        uniforms.flags = glm::ivec4(material.doubleSided ? 1 : 0, hasTangents && material.normalTexture >= 0 ? 1 : 0, alphaMode,
                                    int32_t(instance.renderingLayers));
        const auto slots = material.textureSlots();   // in kTexture* order
        for (size_t t = 0; t < slots.size(); ++t) packTextureTransform(*slots[t].transform, &uniforms.textureTransforms[t * 2]);
        std::memcpy(drawData.data() + i * stride, &uniforms, sizeof(uniforms));

        auto texture = [&](uint32_t binding, int32_t index, const rhi::TextureHandle& fallback) {
            return index >= 0 ? rhi::BindingItem::sampledTexture(binding, m_textures[size_t(index)], m_textureSamplers[size_t(index)])
                              : rhi::BindingItem::sampledTexture(binding, fallback, m_materialSampler);
        };
        Draw draw;
        draw.mesh = instance.mesh;
        draw.instance = uint32_t(i);
        draw.doubleSided = material.doubleSided;
        draw.mirrored = glm::determinant(glm::mat3(instance.world)) < 0.0f;
        draw.blended = material.alphaMode == AlphaMode::Blend;
        draw.masked = material.alphaMode == AlphaMode::Mask;
        draw.topology = mesh.topology;
        draw.vertices = m_meshes[instance.mesh].vertices;
        draw.renderingLayers = instance.renderingLayers;
        draw.world = instance.world;
        // The centre of the world-space box around the transformed local box is the transformed
        // centre of the local box.
        glm::vec3 localMin(std::numeric_limits<float>::max()), localMax(-std::numeric_limits<float>::max());
        for (const Vertex& v : mesh.vertices) {
            localMin = glm::min(localMin, v.position);
            localMax = glm::max(localMax, v.position);
        }
        draw.boundsCenter = glm::vec3(instance.world * glm::vec4((localMin + localMax) * 0.5f, 1.0f));
        // Skinned and morphed instances: the centre of their posed box.
        if (detail::isDeformed(scene, instance))
            if (const std::optional<Box> box = detail::instanceBounds(scene, instance)) draw.boundsCenter = box->center();
        draw.uniformsOffset = uint32_t(i * stride);
        uint32_t& set = materialSet[mesh.material >= 0 ? size_t(mesh.material) : scene.materials.size()];
        if (set == UINT32_MAX) {
            set = uint32_t(m_materialBindings.size());
            m_materialBindings.push_back(m_device.createBindingSet(
                rhi::BindingSetDesc{}
                    .add(texture(JANUS_BINDING_BASE_COLOR, material.baseColorTexture, m_whiteTexture))
                    .add(texture(JANUS_BINDING_METALLIC_ROUGHNESS, material.metallicRoughnessTexture, m_whiteTexture))
                    .add(texture(JANUS_BINDING_NORMAL, material.normalTexture, m_flatNormalTexture))
                    .add(texture(JANUS_BINDING_OCCLUSION, material.occlusionTexture, m_whiteTexture))
                    .add(texture(JANUS_BINDING_EMISSIVE, material.emissiveTexture, m_whiteTexture))));
        }
        draw.material = set;
        (draw.blended ? m_blendedDraws : m_draws).push_back(std::move(draw));
    }
    m_device.writeBuffer(m_drawUniforms, drawData.data(), drawData.size());
    m_drawBindings = m_device.createBindingSet(rhi::BindingSetDesc{}.add(
        rhi::BindingItem::uniformBuffer(JANUS_BINDING_DRAW_UNIFORMS, m_drawUniforms, 0, sizeof(DrawUniforms)).setDynamicOffset()));
    for (const Draw& draw : m_blendedDraws) {
        if (draw.topology == MeshTopology::Triangles) m_hasBlendedKind[draw.doubleSided][draw.mirrored] = true;
        m_hasTopology[1][size_t(draw.topology)] = true;
    }

    // Fewer pipeline switches: single-sided draws first, then double-sided ones; mirrored ones
    // after the others of their kind. Within each, fewer material and mesh binds: by material,
    // then mesh.
    std::stable_sort(m_draws.begin(), m_draws.end(), [](const Draw& a, const Draw& b) {
        return std::tuple(a.doubleSided, a.mirrored, a.material, a.mesh) < std::tuple(b.doubleSided, b.mirrored, b.material, b.mesh);
    });
    for (const Draw& draw : m_draws) {
        if (draw.topology == MeshTopology::Triangles) m_hasKind[draw.doubleSided][draw.mirrored] = true;
        m_hasTopology[0][size_t(draw.topology)] = true;
        m_hasMasked = m_hasMasked || draw.masked;
    }
}

rhi::GraphicsPipelineDesc& GpuScene::addVertexLayout(rhi::GraphicsPipelineDesc& desc, uint32_t binding) {
    return desc.addVertexBuffer({binding, sizeof(Vertex), false})
        .addVertexAttribute({0, rhi::VertexFormat::Float3, binding, offsetof(Vertex, position)})
        .addVertexAttribute({1, rhi::VertexFormat::Float3, binding, offsetof(Vertex, normal)})
        .addVertexAttribute({2, rhi::VertexFormat::Float2, binding, offsetof(Vertex, uv)})
        .addVertexAttribute({3, rhi::VertexFormat::Float4, binding, offsetof(Vertex, tangent)})
        .addVertexAttribute({4, rhi::VertexFormat::Float2, binding, offsetof(Vertex, uv1)})
        .addVertexAttribute({5, rhi::VertexFormat::Float4, binding, offsetof(Vertex, color)});
}

rhi::PipelineHandle GpuScene::createMeshPipeline(const rhi::ShaderHandle& vertexShader, const rhi::ShaderHandle& fragmentShader,
                                                 rhi::CullMode cull, bool clockwise, rhi::DepthState depth, rhi::BlendAttachment blend,
                                                 const std::vector<rhi::Format>& colorFormats, rhi::Format depthFormat,
                                                 const std::string& name, rhi::PrimitiveTopology topology,
                                                 const rhi::RasterState& depthBias, uint32_t sampleCount, bool alphaToCoverage) const {
    rhi::RasterState raster = depthBias;
    raster.cullMode = cull;
    raster.frontFace = clockwise ? rhi::FrontFace::Clockwise : rhi::FrontFace::CounterClockwise;
    rhi::GraphicsPipelineDesc desc;
    addVertexLayout(desc.setShaders(vertexShader, fragmentShader).setTopology(topology))
        .addDynamicUniformBuffer(JANUS_SET_DRAW, JANUS_BINDING_DRAW_UNIFORMS)
        // glTF front faces are counter-clockwise; an ordinary projection keeps that as seen in
        // the image, a mirrored one (cube faces) or a mirrored instance turns it clockwise.
        .setRaster(raster)
        .setDepth(depth)
        .setDepthFormat(depthFormat)
        .setSampleCount(sampleCount)
        .setAlphaToCoverage(alphaToCoverage)
        .setDebugName(name);
    for (rhi::Format format : colorFormats) desc.addColorFormat(format, blend);
    return m_device.createGraphicsPipeline(desc);
}

namespace {
std::vector<rhi::Format> formatList(rhi::Format colorFormat) {
    return colorFormat == rhi::Format::Unknown ? std::vector<rhi::Format>{} : std::vector<rhi::Format>{colorFormat};
}
}  // namespace

GpuScene::MeshPipelines GpuScene::createUnculledPipelines(const rhi::ShaderHandle& vertexShader, const rhi::ShaderHandle& fragmentShader,
                                                          rhi::DepthState depth, const std::vector<rhi::Format>& colorFormats,
                                                          rhi::Format depthFormat, bool mirrored, const std::string& name) const {
    auto pipeline = [&](bool clockwise, const char* variant) {
        return createMeshPipeline(vertexShader, fragmentShader, rhi::CullMode::None, clockwise, depth, {}, colorFormats, depthFormat,
                                  fmt::format("{} ({})", name, variant));
    };
    MeshPipelines pipelines;
    pipelines.culled = pipelines.doubleSided = pipeline(mirrored, "no culling");
    if (m_hasKind[0][1] || m_hasKind[1][1])
        pipelines.culledMirrored = pipelines.doubleSidedMirrored = pipeline(!mirrored, "no culling, mirrored instances");
    // No line or point pipelines: the G-buffer's surfaces are areas (drawMeshes skips the rest).
    return pipelines;
}

GpuScene::MeshPipelines GpuScene::createMeshPipelines(const rhi::ShaderHandle& vertexShader, const rhi::ShaderHandle& fragmentShader,
                                                      rhi::DepthState depth, rhi::Format colorFormat, rhi::Format depthFormat,
                                                      bool mirrored, const std::string& name, const rhi::RasterState& depthBias,
                                                      uint32_t sampleCount, bool alphaToCoverage) const {
    auto pipeline = [&](rhi::CullMode cull, bool clockwise, const char* variant) {
        return createMeshPipeline(vertexShader, fragmentShader, cull, clockwise, depth, {}, formatList(colorFormat), depthFormat,
                                  fmt::format("{} ({})", name, variant), rhi::PrimitiveTopology::TriangleList, depthBias,
                                  sampleCount, alphaToCoverage);
    };
    MeshPipelines pipelines;
    pipelines.culled = pipeline(rhi::CullMode::Back, mirrored, "back-face culled");
    if (m_hasKind[1][0]) pipelines.doubleSided = pipeline(rhi::CullMode::None, mirrored, "double-sided");
    if (m_hasKind[0][1]) pipelines.culledMirrored = pipeline(rhi::CullMode::Back, !mirrored, "back-face culled, mirrored instances");
    if (m_hasKind[1][1]) pipelines.doubleSidedMirrored = pipeline(rhi::CullMode::None, !mirrored, "double-sided, mirrored instances");
    addLineAndPointPipelines(pipelines.lines, pipelines.points, vertexShader, fragmentShader, depth, {}, formatList(colorFormat),
                             depthFormat, name, false, sampleCount, alphaToCoverage);
    return pipelines;
}

GpuScene::BlendedPipelines GpuScene::createBlendedPipelines(const rhi::ShaderHandle& vertexShader,
                                                            const rhi::ShaderHandle& fragmentShader, rhi::DepthState depth,
                                                            rhi::BlendAttachment blend, rhi::Format colorFormat,
                                                            rhi::Format depthFormat, bool mirrored, const std::string& name,
                                                            uint32_t sampleCount) const {
    auto pipeline = [&](rhi::CullMode cull, bool clockwise, const char* variant) {
        return createMeshPipeline(vertexShader, fragmentShader, cull, clockwise, depth, blend, formatList(colorFormat), depthFormat,
                                  fmt::format("{} ({})", name, variant), rhi::PrimitiveTopology::TriangleList, {}, sampleCount);
    };
    BlendedPipelines pipelines;
    // Every blended draw uses a back-culled pipeline (a double-sided one for its front faces).
    if (m_hasBlendedKind[0][0] || m_hasBlendedKind[1][0]) pipelines.backCulled = pipeline(rhi::CullMode::Back, mirrored, "front faces");
    if (m_hasBlendedKind[1][0]) pipelines.frontCulled = pipeline(rhi::CullMode::Front, mirrored, "back faces of double-sided");
    if (m_hasBlendedKind[0][1] || m_hasBlendedKind[1][1])
        pipelines.backCulledMirrored = pipeline(rhi::CullMode::Back, !mirrored, "front faces, mirrored instances");
    if (m_hasBlendedKind[1][1])
        pipelines.frontCulledMirrored = pipeline(rhi::CullMode::Front, !mirrored, "back faces of double-sided, mirrored instances");
    addLineAndPointPipelines(pipelines.lines, pipelines.points, vertexShader, fragmentShader, depth, blend, formatList(colorFormat),
                             depthFormat, name, true, sampleCount);
    return pipelines;
}

void GpuScene::addLineAndPointPipelines(rhi::PipelineHandle& lines, rhi::PipelineHandle& points, const rhi::ShaderHandle& vertexShader,
                                        const rhi::ShaderHandle& fragmentShader, rhi::DepthState depth, rhi::BlendAttachment blend,
                                        const std::vector<rhi::Format>& colorFormats, rhi::Format depthFormat, const std::string& name,
                                        bool blended, uint32_t sampleCount, bool alphaToCoverage) const {
    // Lines and points have no faces: no culling, and winding does not matter.
    if (m_hasTopology[blended][size_t(MeshTopology::Lines)])
        lines = createMeshPipeline(vertexShader, fragmentShader, rhi::CullMode::None, false, depth, blend, colorFormats, depthFormat,
                                   fmt::format("{} (lines)", name), rhi::PrimitiveTopology::LineList, {}, sampleCount, alphaToCoverage);
    if (m_hasTopology[blended][size_t(MeshTopology::Points)])
        points = createMeshPipeline(vertexShader, fragmentShader, rhi::CullMode::None, false, depth, blend, colorFormats, depthFormat,
                                    fmt::format("{} (points)", name), rhi::PrimitiveTopology::PointList, {}, sampleCount,
                                    alphaToCoverage);
}

namespace {
// A view of every layer draws everything, including meshes in no layer (lit by ambient only).
bool viewSees(const SceneView& view, const GpuScene::Draw& draw) {
    return view.renderingLayers == ~0u || (draw.renderingLayers & view.renderingLayers) != 0;
}
}  // namespace

bool GpuScene::viewSeesBlended(const SceneView& view) const {
    return std::any_of(m_blendedDraws.begin(), m_blendedDraws.end(), [&](const Draw& draw) { return viewSees(view, draw); });
}

// One mesh draw: the draw set at its uniforms' offset; the pipeline (with the view set), the
// material set and the mesh's buffers only when they change.
void GpuScene::recordDraw(rhi::ICommandList& cmd, const rhi::PipelineHandle& pipeline, const Draw& draw,
                          const rhi::BindingSetHandle& viewBindings, BoundForDraws& bound, PassReport& report) const {
    if (pipeline.get() != bound.pipeline) {
        cmd.setPipeline(pipeline);
        cmd.setBindingSet(JANUS_SET_VIEW, viewBindings);
        bound = {pipeline.get()};   // and the rest again, as a new pipeline reads them
    }
    if (draw.material != bound.material) {
        cmd.setBindingSet(JANUS_SET_MATERIAL, m_materialBindings[draw.material]);
        bound.material = draw.material;
    }
    cmd.setBindingSet(JANUS_SET_DRAW, m_drawBindings, std::span(&draw.uniformsOffset, 1));
    const Mesh& mesh = m_meshes[draw.mesh];
    if (draw.vertices.get() != bound.vertices) {
        cmd.setVertexBuffer(0, draw.vertices);
        bound.vertices = draw.vertices.get();
    }
    if (mesh.indices.get() != bound.indices) {
        cmd.setIndexBuffer(mesh.indices, rhi::IndexType::UInt32);
        bound.indices = mesh.indices.get();
    }
    cmd.drawIndexed(mesh.indexCount);
    ++report.draws;
}

void GpuScene::drawMeshes(rhi::ICommandList& cmd, const SceneView& view, const MeshPipelines& pipelines,
                          const rhi::BindingSetHandle& viewBindings, PassReport& report, const MeshPipelines* maskedPipelines) const {
    BoundForDraws bound;
    for (const Draw& draw : m_draws) {
        if (!viewSees(view, draw)) continue;
        const rhi::PipelineHandle& pipeline = (draw.masked && maskedPipelines ? *maskedPipelines : pipelines).forDraw(draw);
        // A pass without line or point pipelines, or one that leaves masked draws out.
        if (!pipeline && (draw.topology != MeshTopology::Triangles || (draw.masked && maskedPipelines))) continue;
        recordDraw(cmd, pipeline, draw, viewBindings, bound, report);
    }
}

void GpuScene::drawSelected(rhi::ICommandList& cmd, std::span<const uint32_t> drawIndices, const MeshPipelines& pipelines,
                            const rhi::BindingSetHandle& viewBindings, PassReport& report) const {
    BoundForDraws bound;
    for (uint32_t index : drawIndices) {
        const Draw& draw = m_draws.at(index);
        const rhi::PipelineHandle& pipeline = pipelines.forDraw(draw);
        if (!pipeline && draw.topology != MeshTopology::Triangles) continue;   // a pass without line or point pipelines
        recordDraw(cmd, pipeline, draw, viewBindings, bound, report);
    }
}

std::vector<uint32_t> GpuScene::sortBlendedBackToFront(const SceneView& view) const {
    std::vector<std::pair<float, uint32_t>> keyed;   // (view-space depth along the view axis, index)
    for (uint32_t i = 0; i < m_blendedDraws.size(); ++i) {
        const Draw& draw = m_blendedDraws[i];
        if (!viewSees(view, draw)) continue;
        // View space looks down -z: the distance along the view axis is -z.
        keyed.emplace_back(-(view.view * glm::vec4(draw.boundsCenter, 1.0f)).z, i);
    }
    std::stable_sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<uint32_t> order;
    order.reserve(keyed.size());
    for (const auto& entry : keyed) order.push_back(entry.second);
    return order;
}

void GpuScene::drawBlended(rhi::ICommandList& cmd, const std::vector<uint32_t>& order, const BlendedPipelines& pipelines,
                           const rhi::BindingSetHandle& viewBindings, PassReport& report) const {
    BoundForDraws bound;
    auto drawWith = [&](const rhi::PipelineHandle& pipeline, const Draw& draw) {
        recordDraw(cmd, pipeline, draw, viewBindings, bound, report);
    };
    for (uint32_t index : order) {
        const Draw& draw = m_blendedDraws.at(index);
        if (draw.topology != MeshTopology::Triangles) {
            drawWith(draw.topology == MeshTopology::Lines ? pipelines.lines : pipelines.points, draw);
            continue;
        }
        if (draw.doubleSided) drawWith(draw.mirrored ? pipelines.frontCulledMirrored : pipelines.frontCulled, draw);
        drawWith(draw.mirrored ? pipelines.backCulledMirrored : pipelines.backCulled, draw);
    }
}

}  // namespace janus::renderer
