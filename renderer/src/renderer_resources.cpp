// Renderer resources: the render targets (HDR radiance, depth, display), scene textures with
// their mips made on the CPU, samplers, and mesh vertex/index buffers.
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "renderer_impl.h"

namespace janus::renderer {
namespace {

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

}  // namespace

void Renderer::Impl::createTargets() {
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

rhi::TextureHandle Renderer::Impl::createTexture(const std::string& name, uint32_t width, uint32_t height, std::vector<uint8_t> rgba,
                                                 bool srgb) {
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

rhi::SamplerHandle Renderer::Impl::createSampler(const TextureSampling& sampling) {
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

void Renderer::Impl::uploadTextures(const Scene& scene) {
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

void Renderer::Impl::uploadMeshes(const Scene& scene) {
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

}  // namespace janus::renderer
