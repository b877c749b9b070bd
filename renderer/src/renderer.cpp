// Renderer: uploads a Scene once, then records one frame per renderFrame() from a plan of the
// passes the scene needs (docs/ARCHITECTURE.md, "Data flow of a frame"):
//   shadow-map     (main directional light, when there is one and shadows are on)
//   depth-prepass  (tiled light culling only) meshes -> D32F depth
//   light-cull-*   (tiled only) compute: light_cull.comp | fallback: CPU builder -> tile lists
//   forward        meshes -> RGBA16F HDR radiance (+ depth, or tested against the prepass depth)
//   tonemap        (compute: storage-image dispatch | fallback: fullscreen triangle) HDR -> RGBA8 display
//   tile-heatmap   (DebugView::Tiles) lights per tile blended over the display image
// Both tonemap paths include shaders/renderer/tonemap_common.glsl, so they compute the same bits.
#include "janus/renderer/renderer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>

#include <fmt/format.h>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/packing.hpp>

#include "janus/renderer/light_grid.h"
#include "janus/shaders/shaders.h"
#include "shadow_map.h"

namespace janus::renderer {
namespace {

constexpr uint32_t kMaxDirectionalLights = 4;   // must match forward_common.glsl
constexpr uint32_t kTonemapGroupSize = 8;       // tonemap.comp local_size

// Lighting defaults (renderer.h, LightingSettings).
constexpr uint32_t kDefaultTileSize = 16;
constexpr uint32_t kDefaultMaxLightsPerTile = 256;
constexpr float kDefaultIntensityCutoff = 0.01f;
// LightCulling::Auto loops fewer local lights than this directly. `janus bench forward` on a quiet
// machine (docs/BENCHMARKS.md) finds a tiled mode faster than naive on all four configurations
// from 8 lights (1.2-1.9x) and about even at 0; below 8 the prepass and culling cost what they save.
constexpr uint32_t kDefaultAutoTiledThreshold = 8;
constexpr uint32_t kDefaultShadowMapSize = 1024;

// std140 mirrors of the blocks in shaders/renderer/forward_common.glsl and tonemap_common.glsl.
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

rhi::ShaderHandle makeShader(rhi::IDevice& device, rhi::ShaderStage stage, const char* name) {
    return device.createShader(rhi::ShaderDesc{}.setStage(stage).setSpirv(shaders::get(name)).setDebugName(name));
}

// Settings: the RenderSettings value, else the scene file's "quality" key, else the default.
template <class T>
T resolveSetting(const std::optional<T>& given, const nlohmann::json& quality, const char* key, T fallback) {
    if (given) return *given;
    if (!quality.is_object() || !quality.contains(key)) return fallback;
    const nlohmann::json& value = quality.at(key);
    if constexpr (std::is_same_v<T, bool>) {
        if (value.is_boolean()) return value.get<bool>();
        throw RendererError(fmt::format("scene quality key '{}' must be true or false, not {}", key, value.dump()));
    } else if constexpr (std::is_integral_v<T>) {
        if (value.is_number_integer() && value.get<int64_t>() >= 0 && uint64_t(value.get<int64_t>()) <= std::numeric_limits<T>::max())
            return T(value.get<int64_t>());
        throw RendererError(fmt::format("scene quality key '{}' must be a non-negative integer, not {}", key, value.dump()));
    } else {
        if (value.is_number()) return T(value.get<double>());
        throw RendererError(fmt::format("scene quality key '{}' must be a number, not {}", key, value.dump()));
    }
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

    Impl(rhi::IDevice& d, const Scene& scene, const RenderSettings& s) : device(d), settings(s) {
        validateScene(scene);
        checkSettings();
        resolveLighting(scene);
        packLights(scene);
        chooseCulling();
        createTargets();
        uploadTextures(scene);
        uploadMeshes(scene);
        createShadows(scene);
        createLightArrays();
        createForward(scene);
        createCulling();
        createTonemap(scene);
        createHeatmap();
        commandList = device.createCommandList();
        planFrame();
    }

    // A frame that threw half-way (e.g. in the CPU step between its submissions) may leave work
    // in flight that uses the resources about to be destroyed: wait for it first.
    ~Impl() {
        try {
            device.waitIdle();
        } catch (const std::exception& e) {
            fmt::print(stderr, "janus renderer: warning: waiting for the GPU before teardown failed: {}\n", e.what());
        }
    }

    bool tiled() const { return cullingMode == LightCulling::Tiles2D || cullingMode == LightCulling::TilesDepth; }
    uint32_t tileCount() const { return tilesX * tilesY; }

    // The passes this scene needs, in order. Every frame produces HDR radiance and a display
    // image, so forward and tonemap are always there; the rest join only when the scene has
    // what they work on.
    void planFrame() {
        if (shadowMap) plan.push_back({"shadow-map", &Impl::recordShadowMap, nullptr, nullptr});
        if (tiled()) {
            plan.push_back({"depth-prepass", &Impl::recordDepthPrepass, nullptr, nullptr});
            if (settings.path == FeaturePath::Compute)
                plan.push_back({"light-cull-compute", &Impl::recordLightCullCompute, nullptr, nullptr});
            else
                plan.push_back({"light-cull-cpu", nullptr, &Impl::buildTilesOnCpu, nullptr});
        }
        plan.push_back({"forward", &Impl::recordForward, nullptr, nullptr});
        if (settings.path == FeaturePath::Compute)
            plan.push_back({"tonemap-compute", &Impl::recordTonemapCompute, nullptr, nullptr});
        else
            plan.push_back({"tonemap-fallback", &Impl::recordTonemapFallback, nullptr, nullptr});
        if (heatmapPipeline) plan.push_back({"tile-heatmap", &Impl::recordHeatmap, nullptr, nullptr});
        if (device.capabilities().timestampQueries)
            for (PlannedPass& pass : plan)
                if (pass.record) pass.timer = device.createTimerQuery();
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
            for (rhi::Capability cap : {rhi::Capability::Compute, rhi::Capability::StorageImages, rhi::Capability::StorageBuffers})
                if (!caps.has(cap))
                    throw RendererError(fmt::format("the compute path needs the '{}' capability, which this {} device lacks; render "
                                                    "with the fallback path (FeaturePath::Fallback, --path fallback)",
                                                    rhi::toString(cap), rhi::toString(device.info().backend)));
        }
    }

    void resolveLighting(const Scene& scene) {
        const LightingSettings& given = settings.lighting;
        const nlohmann::json& quality = scene.quality;
        if (given.culling) {
            lighting.culling = *given.culling;
        } else if (quality.is_object() && quality.contains("lightCulling")) {
            const nlohmann::json& value = quality.at("lightCulling");
            const std::optional<LightCulling> parsed =
                value.is_string() ? parseLightCulling(value.get<std::string>()) : std::nullopt;
            if (!parsed)
                throw RendererError(fmt::format("scene quality key 'lightCulling' is {}; expected \"auto\", \"naive\", \"tiles-2d\" or "
                                                "\"tiles-depth\"",
                                                value.dump()));
            lighting.culling = *parsed;
        }
        lighting.tileSize = resolveSetting(given.tileSize, quality, "tileSize", kDefaultTileSize);
        lighting.maxLightsPerTile = resolveSetting(given.maxLightsPerTile, quality, "maxLightsPerTile", kDefaultMaxLightsPerTile);
        lighting.intensityCutoff = resolveSetting(given.intensityCutoff, quality, "intensityCutoff", kDefaultIntensityCutoff);
        lighting.autoTiledThreshold = resolveSetting(given.autoTiledThreshold, quality, "autoTiledThreshold", kDefaultAutoTiledThreshold);
        lighting.shadows = resolveSetting(given.shadows, quality, "shadows", true);
        lighting.shadowMapSize = resolveSetting(given.shadowMapSize, quality, "shadowMapSize", kDefaultShadowMapSize);

        const uint32_t t = lighting.tileSize;
        if (t != 16 && t != 32 && t != 64 && t != 128 && t != 256)
            throw RendererError(fmt::format("tile size {} is not supported: use 16, 32, 64, 128 or 256 pixels", t));
        if (lighting.maxLightsPerTile < 1 || lighting.maxLightsPerTile > 1024)
            throw RendererError(fmt::format("maxLightsPerTile {} is out of range: it must be between 1 and 1024", lighting.maxLightsPerTile));
        if (!std::isfinite(lighting.intensityCutoff) || lighting.intensityCutoff < 0.0f)
            throw RendererError(fmt::format("intensity cut-off {} is not possible: it must be a finite number >= 0 (lux)",
                                            lighting.intensityCutoff));
        if (lighting.intensityCutoff == 0.0f && (lighting.culling == LightCulling::Tiles2D || lighting.culling == LightCulling::TilesDepth))
            throw RendererError(fmt::format("intensity cut-off 0 gives lights without a range an infinite range, which only naive "
                                            "culling can render; use LightCulling::Naive (\"naive\") or a cut-off above 0 with {}",
                                            toString(lighting.culling)));
    }

    // Point and spot lights into the GPU light array (light_grid.h: skips and warns about lights
    // that light nothing, refuses more than kMaxLocalLights). Directional lights stay in the frame
    // uniforms (frameUniformsFor).
    void packLights(const Scene& scene) {
        localLights = packLocalLights(scene, lighting.intensityCutoff).lights;
        const auto directional = std::count_if(scene.lights.begin(), scene.lights.end(),
                                               [](const Light& light) { return light.type == LightType::Directional; });
        directionalCount = uint32_t(std::min<size_t>(size_t(directional), kMaxDirectionalLights));
        if (size_t(directional) > kMaxDirectionalLights)
            fmt::print(stderr, "janus renderer: warning: scene '{}' has {} directional lights; the first {} are shaded\n", scene.name,
                       directional, kMaxDirectionalLights);
        tileGrid = makeTileGrid(scene.camera, settings.width, settings.height, lighting.tileSize, lighting.maxLightsPerTile);
    }

    void chooseCulling() {
        cullingMode = lighting.culling;
        if (cullingMode == LightCulling::Auto) {
            // Infinite ranges (cut-off 0) can only be looped directly.
            const bool tiledPossible = lighting.intensityCutoff > 0.0f;
            cullingMode = tiledPossible && localLights.size() >= lighting.autoTiledThreshold ? LightCulling::TilesDepth : LightCulling::Naive;
        }
        // No local lights: nothing to cull, no prepass.
        if (localLights.empty()) cullingMode = LightCulling::Naive;
        if (tiled()) {
            tilesX = tileGrid.tilesX();
            tilesY = tileGrid.tilesY();
        }
        if (!localLights.empty()) {
            LightCullingReport report;
            report.mode = cullingMode;
            report.builder = tiled() ? (settings.path == FeaturePath::Compute ? "compute" : "cpu") : "";
            report.directionalLights = directionalCount;
            report.localLights = uint32_t(localLights.size());
            if (tiled()) {
                report.tileSize = lighting.tileSize;
                report.tilesX = tilesX;
                report.tilesY = tilesY;
                report.maxLightsPerTile = lighting.maxLightsPerTile;
            }
            cullingReport = report;
        }
    }

    void createTargets() {
        const uint32_t w = settings.width, h = settings.height;
        hdrTarget = device.createTexture(rhi::TextureDesc{}
                                             .setFormat(rhi::Format::RGBA16_FLOAT)
                                             .setSize(w, h)
                                             .setUsage(rhi::TextureUsage::RenderTarget | rhi::TextureUsage::Sampled)
                                             .setDebugName("hdr radiance"));
        // Sampled: light_cull.comp reads the prepass depth for the tile depth bounds.
        depthTarget = device.createTexture(rhi::TextureDesc{}
                                               .setFormat(rhi::Format::D32_FLOAT)
                                               .setSize(w, h)
                                               .setUsage(rhi::TextureUsage::RenderTarget | rhi::TextureUsage::Sampled)
                                               .setDebugName("depth"));
        rhi::TextureUsage displayUsage =
            settings.path == FeaturePath::Compute ? rhi::TextureUsage::Storage : rhi::TextureUsage::RenderTarget;
        // The tile heat map is blended over the display image by a fragment shader on both paths.
        if (settings.debugView == DebugView::Tiles) displayUsage = displayUsage | rhi::TextureUsage::RenderTarget;
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

    void createShadows(const Scene& scene) {
        dummyShadowTexture = device.createTexture(rhi::TextureDesc{}
                                                      .setFormat(DirectionalShadowMap::kDepthFormat)
                                                      .setSize(1, 1)
                                                      .setUsage(rhi::TextureUsage::Sampled | rhi::TextureUsage::RenderTarget)
                                                      .setDebugName("no shadow map"));
        dummyShadowSampler = device.createSampler(rhi::SamplerDesc{}
                                                      .setFilter(rhi::Filter::Nearest)
                                                      .setAddress(rhi::AddressMode::ClampToEdge)
                                                      .setCompare(rhi::CompareOp::LessOrEqual));
        if (!lighting.shadows) return;
        const std::optional<size_t> main = mainDirectionalLight(scene, kMaxDirectionalLights);
        if (!main) return;
        const WorldBounds bounds = sceneWorldBounds(scene);
        if (bounds.empty()) return;
        const Material defaultMaterial;
        for (const Instance& instance : scene.instances) {
            const GpuMesh& mesh = meshes[instance.mesh];
            if (mesh.indexCount == 0) continue;
            const Mesh& sceneMesh = scene.meshes[instance.mesh];
            const Material& material = sceneMesh.material >= 0 ? scene.materials[size_t(sceneMesh.material)] : defaultMaterial;
            shadowCasters.push_back(ShadowCaster{mesh.vertices, mesh.indices, mesh.indexCount, instance.world, material.doubleSided});
        }
        if (shadowCasters.empty()) return;
        shadowMap = std::make_unique<DirectionalShadowMap>(device, lighting.shadowMapSize);
        shadowMap->fit(scene.lights[*main].direction, bounds.min, bounds.max);
        shadowMap->setCasters(shadowCasters);
    }

    // The light array and the tile lists in the form the path reads them. Without local lights
    // (or without tiles) a one-element stand-in keeps the bindings valid.
    void createLightArrays() {
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
    rhi::TextureHandle createDataTexture(rhi::Format format, size_t elements, const char* name) {
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
    void writeDataTexture(const rhi::TextureHandle& texture, const void* data, size_t elements, size_t texelBytes) {
        const rhi::TextureDesc& desc = texture->desc();
        std::vector<std::byte> texels(size_t(desc.width) * desc.height * texelBytes);
        std::memcpy(texels.data(), data, elements * texelBytes);
        device.writeTexture(texture, {}, texels.data(), texels.size());
    }

    FrameUniforms frameUniformsFor(const Scene& scene) const {
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

    void createForward(const Scene& scene) {
        const rhi::Capabilities& caps = device.capabilities();
        const FrameUniforms frame = frameUniformsFor(scene);
        frameUniforms = device.createBuffer(
            rhi::BufferDesc{}.setSize(sizeof(FrameUniforms)).setUsage(rhi::BufferUsage::Uniform).setDebugName("frame uniforms"));
        device.writeBuffer(frameUniforms, &frame, sizeof(frame));
        rhi::BindingSetDesc frameSet;
        frameSet.add(rhi::BindingItem::uniformBuffer(0, frameUniforms));
        if (settings.path == FeaturePath::Compute) {
            frameSet.add(rhi::BindingItem::storageBuffer(7, localLightBuffer)).add(rhi::BindingItem::storageBuffer(8, tileBuffer));
        } else {
            frameSet.add(rhi::BindingItem::sampledTexture(7, localLightTexture, targetSampler))
                .add(rhi::BindingItem::sampledTexture(8, tileTexture, targetSampler));
        }
        frameSet.add(shadowMap ? shadowMap->binding(9) : rhi::BindingItem::sampledTexture(9, dummyShadowTexture, dummyShadowSampler));
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

    // Tile-list building: the compute path's resources (light_cull.comp) or nothing for the CPU
    // builder, which runs between submissions.
    void createCulling() {
        if (!tiled() || settings.path != FeaturePath::Compute) return;
        createCullCompute();
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

    void createHeatmap() {
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
        bindings.add(rhi::BindingItem::uniformBuffer(0, heatmapUniforms));
        if (settings.path == FeaturePath::Compute)
            bindings.add(rhi::BindingItem::storageBuffer(8, tileBuffer));
        else
            bindings.add(rhi::BindingItem::sampledTexture(8, tileTexture, targetSampler));
        heatmapBindings = device.createBindingSet(bindings);
        heatmapPipeline = device.createGraphicsPipeline(
            rhi::GraphicsPipelineDesc{}
                .setShaders(makeShader(device, rhi::ShaderStage::Vertex, "fullscreen_vert"),
                            makeShader(device, rhi::ShaderStage::Fragment,
                                       settings.path == FeaturePath::Compute ? "tile_heatmap_frag" : "tile_heatmap_textures_frag"))
                .addColorFormat(rhi::Format::RGBA8_UNORM, rhi::BlendAttachment::alpha())
                .setDebugName("tile heat map"));
    }

    void recordMeshes(rhi::ICommandList& cmd, PassReport& report, const rhi::PipelineHandle& culled, const rhi::PipelineHandle& doubleSided) {
        const rhi::IPipeline* bound = nullptr;
        for (const Draw& draw : draws) {
            const rhi::PipelineHandle& pipeline = draw.doubleSided ? doubleSided : culled;
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
    }

    void recordShadowMap(rhi::ICommandList& cmd, PassReport& report) { shadowMap->record(cmd, shadowCasters, report.draws); }

    void recordDepthPrepass(rhi::ICommandList& cmd, PassReport& report) {
        cmd.beginRenderPass(rhi::RenderPassDesc{}.setDepth(rhi::Attachment::clearDepthTo(depthTarget, 1.0f)));
        recordMeshes(cmd, report, prepassCulled, prepassDoubleSided);
        cmd.endRenderPass();
    }

    void recordForward(rhi::ICommandList& cmd, PassReport& report) {
        cmd.beginRenderPass(rhi::RenderPassDesc{}
                                .addColor(rhi::Attachment::clear(hdrTarget, backgroundRadiance))
                                .setDepth(tiled() ? rhi::Attachment::load(depthTarget) : rhi::Attachment::clearDepthTo(depthTarget, 1.0f)));
        recordMeshes(cmd, report, forwardCulled, forwardDoubleSided);
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

    void recordHeatmap(rhi::ICommandList& cmd, PassReport& report) {
        cmd.beginRenderPass(rhi::RenderPassDesc{}.addColor(rhi::Attachment::load(displayImage)));
        cmd.setPipeline(heatmapPipeline);
        cmd.setBindingSet(0, heatmapBindings);
        cmd.draw(3);
        ++report.draws;
        cmd.endRenderPass();
    }

    void warnOverflowOnce(const LightCullingReport& report) {
        if (report.overflowTiles == 0 || overflowWarned) return;
        overflowWarned = true;
        fmt::print(stderr, "janus renderer: warning: {} tile(s) had more than maxLightsPerTile = {} lights; {} light reference(s) were "
                           "dropped (highest light indices first), so those tiles miss light. Raise maxLightsPerTile or use smaller "
                           "tiles (reported once per renderer)\n",
                   report.overflowTiles, report.maxLightsPerTile, report.droppedLights);
    }

    FrameReport renderFrame() {
        FrameReport frame;
        frame.backend = rhi::toString(device.info().backend);
        frame.path = toString(settings.path);
        frame.width = settings.width;
        frame.height = settings.height;

        rhi::ICommandList& cmd = *commandList;
        bool recording = false;
        auto submit = [&] {
            if (!recording) return;
            cmd.end();
            device.execute(commandList);
            recording = false;
        };
        for (const PlannedPass& pass : plan) {
            PassReport report{pass.name};
            if (pass.cpuWork) {
                submit();
                (this->*pass.cpuWork)(report);
            } else {
                if (!recording) {
                    cmd.begin();
                    recording = true;
                }
                const auto start = std::chrono::steady_clock::now();
                if (pass.timer) cmd.beginTimer(pass.timer);
                cmd.pushDebugGroup(pass.name);
                (this->*pass.record)(cmd, report);
                cmd.popDebugGroup();
                if (pass.timer) cmd.endTimer(pass.timer);
                report.cpuMs = millisecondsSince(start);
            }
            frame.passes.push_back(std::move(report));
        }
        submit();
        frameRendered = true;

        for (size_t i = 0; i < plan.size(); ++i) {
            if (!plan[i].timer) continue;
            if (std::optional<double> seconds = device.timerSeconds(plan[i].timer)) frame.passes[i].gpuMs = *seconds * 1000.0;
        }
        if (cullingReport && tiled() && settings.path == FeaturePath::Compute) readCullStats(*cullingReport);
        if (cullingReport) warnOverflowOnce(*cullingReport);
        frame.lightCulling = cullingReport;
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

    TileLists readTileLists() {
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

    std::vector<float> readDepth() {
        requireFrame("readDepth()");
        return readDepthTarget();
    }

    std::vector<float> readDepthTarget() {
        const std::vector<std::byte> bytes = device.readTexture(depthTarget, {});
        const size_t pixels = size_t(settings.width) * settings.height;
        if (bytes.size() != pixels * 4)
            throw RendererError(fmt::format("depth readback returned {} bytes, expected {} for {}x{} D32F", bytes.size(), pixels * 4,
                                            settings.width, settings.height));
        std::vector<float> depth(pixels);
        std::memcpy(depth.data(), bytes.data(), bytes.size());
        return depth;
    }

    // ---- Tile-list builders (light_grid.h, light_cull.comp: docs/LIGHTING.md) ----
    void createCullCompute() {
        const CullUniforms uniforms = makeCullUniforms(tileGrid, uint32_t(localLights.size()), cullingMode);
        cullUniforms = device.createBuffer(
            rhi::BufferDesc{}.setSize(sizeof(uniforms)).setUsage(rhi::BufferUsage::Uniform).setDebugName("cull uniforms"));
        device.writeBuffer(cullUniforms, &uniforms, sizeof(uniforms));
        cullStats = device.createBuffer(rhi::BufferDesc{}.setSize(16).setUsage(rhi::BufferUsage::Storage).setDebugName("cull stats"));
        cullBindings = device.createBindingSet(rhi::BindingSetDesc{}
                                                   .add(rhi::BindingItem::uniformBuffer(0, cullUniforms))
                                                   .add(rhi::BindingItem::sampledTexture(1, depthTarget, targetSampler))
                                                   .add(rhi::BindingItem::storageBuffer(2, localLightBuffer))
                                                   .add(rhi::BindingItem::storageBuffer(3, tileBuffer))
                                                   .add(rhi::BindingItem::storageBuffer(4, cullStats)));
        cullPipeline = device.createComputePipeline(rhi::ComputePipelineDesc{}
                                                        .setShader(makeShader(device, rhi::ShaderStage::Compute, "light_cull_comp"))
                                                        .setDebugName("light culling"));
    }

    // One workgroup per tile; the stats are atomics, so they start from zero every frame.
    void recordLightCullCompute(rhi::ICommandList& cmd, PassReport& report) {
        const std::array<uint32_t, 4> zero{};
        cmd.writeBuffer(cullStats, zero.data(), sizeof(zero));
        cmd.setPipeline(cullPipeline);
        cmd.setBindingSet(0, cullBindings);
        cmd.dispatch(tilesX, tilesY);
        ++report.dispatches;
    }

    void readCullStats(LightCullingReport& report) {
        const std::vector<std::byte> bytes = device.readBuffer(cullStats);
        std::array<uint32_t, 4> stats{};
        std::memcpy(stats.data(), bytes.data(), std::min(bytes.size(), sizeof(stats)));
        report.overflowTiles = stats[0];
        report.droppedLights = stats[1];
        report.listedLights = stats[2];
    }

    // Fallback path, between the prepass submission and the forward one: the prepass depth (for
    // TilesDepth) comes back, the multi-threaded CPU builder makes the lists, and they go up as
    // the R32UI tile texture. cpuMs is the builder's time alone.
    void buildTilesOnCpu(PassReport& report) {
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
};

Renderer::Renderer(rhi::IDevice& device, const Scene& scene, const RenderSettings& settings)
    : m_impl(std::make_unique<Impl>(device, scene, settings)) {}
Renderer::~Renderer() = default;
FrameReport Renderer::renderFrame() { return m_impl->renderFrame(); }
ImageRGBA8 Renderer::readDisplayImage() { return m_impl->readDisplayImage(); }
ImageRGBAF Renderer::readHdrImage() { return m_impl->readHdrImage(); }
TileLists Renderer::readTileLists() { return m_impl->readTileLists(); }
std::vector<float> Renderer::readDepth() { return m_impl->readDepth(); }

}  // namespace janus::renderer
