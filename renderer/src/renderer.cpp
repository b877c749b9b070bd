// Renderer: uploads a Scene once, then records one frame per renderFrame():
//   forward  (graphics)  meshes -> RGBA16F HDR radiance + D32F depth
//   tonemap  (compute: storage-image dispatch | fallback: fullscreen triangle) HDR -> RGBA8 display
// Both tonemap paths include shaders/renderer/tonemap_common.glsl, so they compute the same bits.
#include "janus/renderer/renderer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstring>

#include <fmt/format.h>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/packing.hpp>

#include "janus/shaders/shaders.h"

namespace janus::renderer {
namespace {

constexpr uint32_t kMaxDirectionalLights = 4;   // must match forward_common.glsl
constexpr uint32_t kMaxLocalLights = 16;
constexpr uint32_t kTonemapGroupSize = 8;       // tonemap.comp local_size

// std140 mirrors of the blocks in shaders/renderer/forward_common.glsl and tonemap_common.glsl.
struct LightData {
    glm::vec4 positionRange;
    glm::vec4 directionType;
    glm::vec4 colorIntensity;
    glm::vec4 spotScaleOffset;
};

struct FrameUniforms {
    glm::mat4 viewProjection;
    glm::vec4 cameraPosition;
    glm::vec4 ambientColor;
    glm::ivec4 lightCounts;
    LightData directionalLights[kMaxDirectionalLights];
    LightData localLights[kMaxLocalLights];
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
static_assert(sizeof(FrameUniforms) == 112 + 64 * (kMaxDirectionalLights + kMaxLocalLights), "FrameUniforms must match std140");
static_assert(sizeof(DrawUniforms) == 192, "DrawUniforms must match std140");

uint64_t alignUp(uint64_t value, uint64_t alignment) { return alignment ? (value + alignment - 1) / alignment * alignment : value; }

double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

float srgbToLinear(uint8_t value) {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (size_t i = 0; i < t.size(); ++i) {
            const float c = float(i) / 255.0f;
            t[i] = c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
        }
        return t;
    }();
    return table[value];
}

uint8_t linearToSrgb(float c) {
    const float s = c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
    return uint8_t(std::clamp(std::lround(s * 255.0f), 0L, 255L));
}

// The next mip of an RGBA8 image with a 2x2 box filter (sRGB colour averaged in linear light).
// Mips are made on the CPU rather than with generateMips so every backend samples the same texels.
std::vector<uint8_t> downsample(const std::vector<uint8_t>& src, uint32_t width, uint32_t height, bool srgb) {
    const uint32_t w = std::max(width / 2, 1u), h = std::max(height / 2, 1u);
    std::vector<uint8_t> dst(size_t(w) * h * 4);
    for (uint32_t y = 0; y < h; ++y) {
        for (uint32_t x = 0; x < w; ++x) {
            for (uint32_t c = 0; c < 4; ++c) {
                float sum = 0.0f;
                for (uint32_t dy = 0; dy < 2; ++dy) {
                    for (uint32_t dx = 0; dx < 2; ++dx) {
                        const uint32_t sx = std::min(x * 2 + dx, width - 1), sy = std::min(y * 2 + dy, height - 1);
                        const uint8_t v = src[(size_t(sy) * width + sx) * 4 + c];
                        sum += (srgb && c < 3) ? srgbToLinear(v) : float(v);
                    }
                }
                const float average = sum / 4.0f;
                dst[(size_t(y) * w + x) * 4 + c] =
                    (srgb && c < 3) ? linearToSrgb(average) : uint8_t(std::clamp(std::lround(average), 0L, 255L));
            }
        }
    }
    return dst;
}

LightData packLight(const Light& light) {
    LightData data{};
    data.positionRange = glm::vec4(light.position, light.range.value_or(0.0f));
    const float type = light.type == LightType::Directional ? 0.0f : light.type == LightType::Point ? 1.0f : 2.0f;
    data.directionType = glm::vec4(glm::normalize(light.direction), type);
    data.colorIntensity = glm::vec4(light.color * light.intensity, 0.0f);
    // KHR_lights_punctual's smooth cone: clamp(cos * scale + offset, 0, 1)^2.
    const float cosOuter = std::cos(light.outerConeAngle), cosInner = std::cos(light.innerConeAngle);
    const float scale = 1.0f / std::max(0.001f, cosInner - cosOuter);
    data.spotScaleOffset = glm::vec4(scale, -cosOuter * scale, 0.0f, 0.0f);
    return data;
}

rhi::ShaderHandle makeShader(rhi::IDevice& device, rhi::ShaderStage stage, const char* name) {
    return device.createShader(rhi::ShaderDesc{}.setStage(stage).setSpirv(shaders::get(name)).setDebugName(name));
}

}  // namespace

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
    // One entry of the frame plan: a pass the scene needs, how to record it, and its timer.
    struct PlannedPass {
        std::string name;
        void (Impl::*record)(rhi::ICommandList&, PassReport&);
        rhi::TimerQueryHandle timer;   // null without Capability::TimestampQueries
    };

    rhi::IDevice& device;
    RenderSettings settings;
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
    std::array<float, 4> backgroundRadiance{};
    rhi::CommandListHandle commandList;
    std::vector<PlannedPass> plan;
    bool frameRendered = false;   // the targets hold nothing readable before the first frame

    Impl(rhi::IDevice& d, const Scene& scene, const RenderSettings& s) : device(d), settings(s) {
        validateScene(scene);
        checkSettings();
        createTargets();
        uploadTextures(scene);
        uploadMeshes(scene);
        createForward(scene);
        createTonemap(scene);
        commandList = device.createCommandList();
        planFrame();
    }

    // The passes this scene needs, in order. Every frame produces HDR radiance and a display
    // image, so forward and tonemap are always there; features added later (light culling,
    // shadows, probes) join the plan only when the scene has what they work on.
    void planFrame() {
        plan.push_back({"forward", &Impl::recordForward, nullptr});
        if (settings.path == FeaturePath::Compute)
            plan.push_back({"tonemap-compute", &Impl::recordTonemapCompute, nullptr});
        else
            plan.push_back({"tonemap-fallback", &Impl::recordTonemapFallback, nullptr});
        if (device.capabilities().timestampQueries)
            for (PlannedPass& pass : plan) pass.timer = device.createTimerQuery();
    }

    void checkSettings() const {
        const rhi::Capabilities& caps = device.capabilities();
        const uint32_t maxSize = caps.limits.maxTextureSize2D;
        if (settings.width == 0 || settings.height == 0 || settings.width > maxSize || settings.height > maxSize)
            throw RendererError(fmt::format("render size {}x{} is not possible on this {} device: width and height must be "
                                            "between 1 and its maximum 2D texture size {}",
                                            settings.width, settings.height, rhi::toString(device.info().backend), maxSize));
        if (!caps.floatRenderTargets)
            throw RendererError(fmt::format("the forward pass renders into RGBA16F, which needs the '{}' capability that this {} "
                                            "device lacks",
                                            rhi::toString(rhi::Capability::FloatRenderTargets), rhi::toString(device.info().backend)));
        if (settings.path == FeaturePath::Compute) {
            for (rhi::Capability cap : {rhi::Capability::Compute, rhi::Capability::StorageImages})
                if (!caps.has(cap))
                    throw RendererError(fmt::format("the compute path needs the '{}' capability, which this {} device lacks; render "
                                                    "with the fallback path (FeaturePath::Fallback, --path fallback)",
                                                    rhi::toString(cap), rhi::toString(device.info().backend)));
        }
    }

    void createTargets() {
        const uint32_t w = settings.width, h = settings.height;
        hdrTarget = device.createTexture(rhi::TextureDesc{}
                                             .setFormat(rhi::Format::RGBA16_FLOAT)
                                             .setSize(w, h)
                                             .setUsage(rhi::TextureUsage::RenderTarget | rhi::TextureUsage::Sampled)
                                             .setDebugName("hdr radiance"));
        depthTarget = device.createTexture(
            rhi::TextureDesc{}.setFormat(rhi::Format::D32_FLOAT).setSize(w, h).setUsage(rhi::TextureUsage::RenderTarget).setDebugName("depth"));
        const rhi::TextureUsage displayUsage =
            settings.path == FeaturePath::Compute ? rhi::TextureUsage::Storage : rhi::TextureUsage::RenderTarget;
        displayImage = device.createTexture(
            rhi::TextureDesc{}.setFormat(rhi::Format::RGBA8_UNORM).setSize(w, h).setUsage(displayUsage).setDebugName("display"));
    }

    rhi::TextureHandle createTexture(const std::string& name, uint32_t width, uint32_t height, std::vector<uint8_t> rgba, bool srgb) {
        const uint32_t mips = rhi::fullMipCount(width, height);
        rhi::TextureHandle texture = device.createTexture(rhi::TextureDesc{}
                                                              .setFormat(srgb ? rhi::Format::RGBA8_SRGB : rhi::Format::RGBA8_UNORM)
                                                              .setSize(width, height)
                                                              .setMipLevels(mips)
                                                              .setUsage(rhi::TextureUsage::Sampled)
                                                              .setDebugName(name));
        for (uint32_t mip = 0; mip < mips; ++mip) {
            if (mip > 0) {
                rgba = downsample(rgba, width, height, srgb);
                width = std::max(width / 2, 1u);
                height = std::max(height / 2, 1u);
            }
            device.writeTexture(texture, rhi::TextureSubresource{mip, 0}, rgba.data(), rgba.size());
        }
        return texture;
    }

    rhi::SamplerHandle createSampler(const TextureSampling& sampling) {
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
        return device.createSampler(desc);
    }

    void uploadTextures(const Scene& scene) {
        whiteTexture = createTexture("default white", 1, 1, {255, 255, 255, 255}, false);
        flatNormalTexture = createTexture("default normal", 1, 1, {128, 128, 255, 255}, false);
        materialSampler = device.createSampler(rhi::SamplerDesc{});
        std::vector<std::pair<TextureSampling, rhi::SamplerHandle>> samplers{{TextureSampling{}, materialSampler}};
        for (const TextureImage& image : scene.textures) {
            textures.push_back(createTexture(image.name, image.width, image.height, image.rgba, image.srgb));
            auto it = std::find_if(samplers.begin(), samplers.end(), [&](const auto& s) { return s.first == image.sampling; });
            if (it == samplers.end()) it = samplers.insert(samplers.end(), {image.sampling, createSampler(image.sampling)});
            textureSamplers.push_back(it->second);
        }
        targetSampler = device.createSampler(rhi::SamplerDesc{}.setFilter(rhi::Filter::Nearest).setAddress(rhi::AddressMode::ClampToEdge));
    }

    void uploadMeshes(const Scene& scene) {
        for (size_t m = 0; m < scene.meshes.size(); ++m) {
            const Mesh& mesh = scene.meshes[m];
            GpuMesh gpu;
            gpu.indexCount = uint32_t(mesh.indices.size());
            if (!mesh.vertices.empty() && !mesh.indices.empty()) {
                const uint64_t vertexBytes = mesh.vertices.size() * sizeof(Vertex);
                const uint64_t indexBytes = mesh.indices.size() * sizeof(uint32_t);
                gpu.vertices = device.createBuffer(
                    rhi::BufferDesc{}.setSize(vertexBytes).setUsage(rhi::BufferUsage::Vertex).setDebugName(fmt::format("mesh {} vertices", m)));
                gpu.indices = device.createBuffer(
                    rhi::BufferDesc{}.setSize(indexBytes).setUsage(rhi::BufferUsage::Index).setDebugName(fmt::format("mesh {} indices", m)));
                device.writeBuffer(gpu.vertices, mesh.vertices.data(), vertexBytes);
                device.writeBuffer(gpu.indices, mesh.indices.data(), indexBytes);
            }
            meshes.push_back(std::move(gpu));
        }
    }

    FrameUniforms frameUniformsFor(const Scene& scene) const {
        FrameUniforms frame{};
        const Camera& camera = scene.camera;
        const float aspect = float(settings.width) / float(settings.height);
        glm::mat4 projection = glm::perspectiveRH_ZO(camera.fovYRadians, aspect, camera.nearPlane, camera.farPlane);
        // Vulkan convention (docs/ARCHITECTURE.md): world up must land on NDC y = -1, row 0.
        projection[1][1] *= -1.0f;
        frame.viewProjection = projection * glm::lookAt(camera.position, camera.target, camera.up);
        frame.cameraPosition = glm::vec4(camera.position, 1.0f);
        frame.ambientColor = glm::vec4(scene.environment.ambientColor, 0.0f);
        uint32_t directional = 0, local = 0, ignored = 0;
        for (const Light& light : scene.lights) {
            if (light.type == LightType::Directional && directional < kMaxDirectionalLights)
                frame.directionalLights[directional++] = packLight(light);
            else if (light.type != LightType::Directional && local < kMaxLocalLights)
                frame.localLights[local++] = packLight(light);
            else
                ++ignored;
        }
        if (ignored)
            fmt::print(stderr, "janus renderer: warning: scene '{}' has more lights than the forward pass shades ({} directional, {} "
                               "point/spot); {} ignored until the Forward+ light grid lands\n",
                       scene.name, kMaxDirectionalLights, kMaxLocalLights, ignored);
        frame.lightCounts = glm::ivec4(int(directional), int(local), 0, 0);
        return frame;
    }

    void createForward(const Scene& scene) {
        const rhi::Capabilities& caps = device.capabilities();
        const FrameUniforms frame = frameUniformsFor(scene);
        frameUniforms = device.createBuffer(
            rhi::BufferDesc{}.setSize(sizeof(FrameUniforms)).setUsage(rhi::BufferUsage::Uniform).setDebugName("frame uniforms"));
        device.writeBuffer(frameUniforms, &frame, sizeof(frame));
        frameBindings = device.createBindingSet(rhi::BindingSetDesc{}.add(rhi::BindingItem::uniformBuffer(0, frameUniforms)));
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
                                        material.alphaMode == AlphaMode::Mask ? 1 : 0, 0);
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
                    .add(rhi::BindingItem::uniformBuffer(1, drawUniforms, i * stride, sizeof(DrawUniforms)))
                    .add(texture(2, material.baseColorTexture, whiteTexture))
                    .add(texture(3, material.metallicRoughnessTexture, whiteTexture))
                    .add(texture(4, material.normalTexture, flatNormalTexture))
                    .add(texture(5, material.occlusionTexture, whiteTexture))
                    .add(texture(6, material.emissiveTexture, whiteTexture)));
            draws.push_back(std::move(draw));
        }
        device.writeBuffer(drawUniforms, drawData.data(), drawData.size());

        // Fewer pipeline switches: single-sided draws first, then double-sided ones.
        std::stable_sort(draws.begin(), draws.end(), [](const Draw& a, const Draw& b) { return !a.doubleSided && b.doubleSided; });

        const rhi::ShaderHandle vs = makeShader(device, rhi::ShaderStage::Vertex, "forward_vert");
        const rhi::ShaderHandle fs = makeShader(device, rhi::ShaderStage::Fragment, "forward_frag");
        auto pipeline = [&](rhi::CullMode cull, const char* name) {
            rhi::GraphicsPipelineDesc desc;
            desc.setShaders(vs, fs)
                .addVertexBuffer({0, sizeof(Vertex), false})
                .addVertexAttribute({0, rhi::VertexFormat::Float3, 0, offsetof(Vertex, position)})
                .addVertexAttribute({1, rhi::VertexFormat::Float3, 0, offsetof(Vertex, normal)})
                .addVertexAttribute({2, rhi::VertexFormat::Float2, 0, offsetof(Vertex, uv)})
                .addVertexAttribute({3, rhi::VertexFormat::Float4, 0, offsetof(Vertex, tangent)})
                // glTF front faces are counter-clockwise; our projection keeps that as seen in the image.
                .setRaster(rhi::RasterState{cull, rhi::FrontFace::CounterClockwise})
                .setDepth(rhi::DepthState{true, true, rhi::CompareOp::Less})
                .addColorFormat(rhi::Format::RGBA16_FLOAT)
                .setDepthFormat(rhi::Format::D32_FLOAT)
                .setDebugName(name);
            return device.createGraphicsPipeline(desc);
        };
        forwardCulled = pipeline(rhi::CullMode::Back, "forward (back-face culled)");
        if (std::any_of(draws.begin(), draws.end(), [](const Draw& d) { return d.doubleSided; }))
            forwardDoubleSided = pipeline(rhi::CullMode::None, "forward (double-sided)");
    }

    void createTonemap(const Scene& scene) {
        const TonemapUniforms uniforms{glm::vec4(scene.environment.exposure, 0.0f, 0.0f, 0.0f)};
        tonemapUniforms = device.createBuffer(
            rhi::BufferDesc{}.setSize(sizeof(uniforms)).setUsage(rhi::BufferUsage::Uniform).setDebugName("tonemap uniforms"));
        device.writeBuffer(tonemapUniforms, &uniforms, sizeof(uniforms));
        rhi::BindingSetDesc bindings;
        bindings.add(rhi::BindingItem::uniformBuffer(0, tonemapUniforms)).add(rhi::BindingItem::sampledTexture(1, hdrTarget, targetSampler));
        if (settings.path == FeaturePath::Compute) {
            bindings.add(rhi::BindingItem::storageImage(2, displayImage));
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

    void recordForward(rhi::ICommandList& cmd, PassReport& report) {
        cmd.beginRenderPass(rhi::RenderPassDesc{}
                                .addColor(rhi::Attachment::clear(hdrTarget, backgroundRadiance))
                                .setDepth(rhi::Attachment::clearDepthTo(depthTarget, 1.0f)));
        const rhi::IPipeline* bound = nullptr;
        for (const Draw& draw : draws) {
            const rhi::PipelineHandle& pipeline = draw.doubleSided ? forwardDoubleSided : forwardCulled;
            if (pipeline.get() != bound) {
                cmd.setPipeline(pipeline);
                cmd.setBindingSet(0, frameBindings);
                bound = pipeline.get();
            }
            const GpuMesh& mesh = meshes[draw.mesh];
            cmd.setBindingSet(1, draw.bindings);
            cmd.setVertexBuffer(0, mesh.vertices);
            cmd.setIndexBuffer(mesh.indices, rhi::IndexType::UInt32);
            cmd.drawIndexed(mesh.indexCount);
            ++report.draws;
        }
        cmd.endRenderPass();
    }

    void recordTonemapCompute(rhi::ICommandList& cmd, PassReport& report) {
        cmd.setPipeline(tonemapPipeline);
        cmd.setBindingSet(0, tonemapBindings);
        cmd.dispatch((settings.width + kTonemapGroupSize - 1) / kTonemapGroupSize,
                     (settings.height + kTonemapGroupSize - 1) / kTonemapGroupSize);
        ++report.dispatches;
    }

    void recordTonemapFallback(rhi::ICommandList& cmd, PassReport& report) {
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

    FrameReport renderFrame() {
        FrameReport frame;
        frame.backend = rhi::toString(device.info().backend);
        frame.path = toString(settings.path);
        frame.width = settings.width;
        frame.height = settings.height;

        rhi::ICommandList& cmd = *commandList;
        cmd.begin();
        for (const PlannedPass& pass : plan) {
            PassReport report{pass.name};
            const auto start = std::chrono::steady_clock::now();
            if (pass.timer) cmd.beginTimer(pass.timer);
            cmd.pushDebugGroup(pass.name);
            (this->*pass.record)(cmd, report);
            cmd.popDebugGroup();
            if (pass.timer) cmd.endTimer(pass.timer);
            report.cpuMs = millisecondsSince(start);
            frame.passes.push_back(std::move(report));
        }
        cmd.end();
        device.execute(commandList);
        frameRendered = true;

        for (size_t i = 0; i < plan.size(); ++i) {
            if (!plan[i].timer) continue;
            if (std::optional<double> seconds = device.timerSeconds(plan[i].timer)) frame.passes[i].gpuMs = *seconds * 1000.0;
        }
        return frame;
    }
    void requireFrame(const char* what) const {
        if (!frameRendered) throw RendererError(fmt::format("{} was called before any frame was rendered; call renderFrame() first", what));
    }

    ImageRGBA8 readDisplayImage() {
        requireFrame("readDisplayImage()");
        ImageRGBA8 image{settings.width, settings.height, {}};
        const std::vector<std::byte> bytes = device.readTexture(displayImage, {});
        if (bytes.size() != size_t(settings.width) * settings.height * 4)
            throw RendererError(fmt::format("display readback returned {} bytes, expected {} for {}x{} RGBA8", bytes.size(),
                                            size_t(settings.width) * settings.height * 4, settings.width, settings.height));
        image.pixels.resize(bytes.size());
        std::memcpy(image.pixels.data(), bytes.data(), bytes.size());
        return image;
    }

    ImageRGBAF readHdrImage() {
        requireFrame("readHdrImage()");
        ImageRGBAF image{settings.width, settings.height, {}};
        const std::vector<std::byte> bytes = device.readTexture(hdrTarget, {});
        const size_t values = size_t(settings.width) * settings.height * 4;
        if (bytes.size() != values * 2)
            throw RendererError(fmt::format("HDR readback returned {} bytes, expected {} for {}x{} RGBA16F", bytes.size(), values * 2,
                                            settings.width, settings.height));
        image.pixels.resize(values);
        for (size_t i = 0; i < values; ++i) {
            uint16_t half;
            std::memcpy(&half, bytes.data() + i * 2, 2);
            image.pixels[i] = glm::unpackHalf1x16(half);
        }
        return image;
    }
};

Renderer::Renderer(rhi::IDevice& device, const Scene& scene, const RenderSettings& settings)
    : m_impl(std::make_unique<Impl>(device, scene, settings)) {}
Renderer::~Renderer() = default;
FrameReport Renderer::renderFrame() { return m_impl->renderFrame(); }
ImageRGBA8 Renderer::readDisplayImage() { return m_impl->readDisplayImage(); }
ImageRGBAF Renderer::readHdrImage() { return m_impl->readHdrImage(); }

}  // namespace janus::renderer
