// Helpers shared by array_textures_test.cpp and texture_views_test.cpp: a texel pattern that
// differs in every texel, layer and mip, and exact texel-centre lookups through
// shaders/rhi-tests/sample_lookup.frag.
#pragma once

#include "backend_test.h"

namespace janus::rhi::test {

// Texel (x, y) of layer L at mip M, exactly as shaders/rhi-tests/fill_layers.comp writes it.
inline Rgba8 layerTexel(uint32_t mip, uint32_t layer, uint32_t x, uint32_t y) {
    return {uint8_t(10 + 20 * x), uint8_t(10 + 20 * y), uint8_t(5 + 10 * layer), uint8_t(255 - 40 * mip)};
}

inline std::vector<Rgba8> layerImage(const TextureDesc& desc, uint32_t mip, uint32_t layer) {
    std::vector<Rgba8> texels;
    for (uint32_t y = 0; y < mipExtent(desc.height, mip); ++y)
        for (uint32_t x = 0; x < mipExtent(desc.width, mip); ++x) texels.push_back(layerTexel(mip, layer, x, y));
    return texels;
}

// The direction that hits the centre of texel (s, t) of `face` (inverse of the face table of the
// Vulkan and GL specs, |ma| = 1); w = `cube` for cube arrays.
inline std::array<float, 4> cubeTexelDirection(uint32_t face, float s, float t, float cube = 0) {
    const float sc = 2 * s - 1, tc = 2 * t - 1;
    switch (face) {
        case 0: return {1, -tc, -sc, cube};
        case 1: return {-1, -tc, sc, cube};
        case 2: return {sc, 1, tc, cube};
        case 3: return {sc, -1, -tc, cube};
        case 4: return {sc, -tc, 1, cube};
        default: return {-sc, -tc, -1, cube};
    }
}

struct Lookup {
    std::array<float, 4> coords{};   // see sample_lookup.frag: (u, v), (u, v, layer), direction, (direction, cube)
    float lod = 0;
};

class LayeredTextureTest : public BackendTest {
protected:
    TextureHandle createLayered(TextureDimension dimension, uint32_t size, uint32_t layers, uint32_t mips,
                                TextureUsage usage = TextureUsage::Sampled) {
        return device().createTexture(TextureDesc()
                                          .setDimension(dimension)
                                          .setSize(size, size)
                                          .setArrayLayers(layers)
                                          .setMipLevels(mips)
                                          .setUsage(usage)
                                          .setDebugName(fmt::format("{} {}x{} x{}", toString(dimension), size, size,
                                                                    layers)));
    }

    // writeTexture of layerImage into every layer and mip.
    void writeEveryLayer(const TextureHandle& texture) {
        const TextureDesc& d = texture->desc();
        for (uint32_t mip = 0; mip < d.mipLevels; ++mip)
            for (uint32_t layer = 0; layer < textureLayerCount(d); ++layer) {
                std::vector<Rgba8> texels = layerImage(d, mip, layer);
                device().writeTexture(texture, {mip, layer}, texels.data(), texels.size() * sizeof(Rgba8));
            }
    }

    // readTexture of every layer and mip equals `expected(mip, layer)`.
    void expectEveryLayer(const TextureHandle& texture,
                          const std::function<std::vector<Rgba8>(uint32_t mip, uint32_t layer)>& expected) {
        const TextureDesc& d = texture->desc();
        for (uint32_t mip = 0; mip < d.mipLevels; ++mip)
            for (uint32_t layer = 0; layer < textureLayerCount(d); ++layer)
                EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(texture, {mip, layer}), expected(mip, layer),
                                        mipExtent(d.width, mip)))
                    << "mip " << mip << " layer " << layer;
    }

    // Draws one pixel per lookup (at most 64) with sample_lookup `shaderName`, whose binding 1 is
    // `textureBinding`, and returns the pixels.
    std::vector<Rgba8> sampleLookups(const char* shaderName, const BindingItem& textureBinding,
                                     const std::vector<Lookup>& lookups) {
        struct Block {
            std::array<std::array<float, 4>, 64> coords{};
            std::array<float, 64> lods{};   // vec4 lods[16]
        } block;
        for (size_t i = 0; i < lookups.size(); ++i) {
            block.coords[i] = lookups[i].coords;
            block.lods[i] = lookups[i].lod;
        }
        BufferHandle ubo = createBuffer(BufferUsage::Uniform, std::as_bytes(std::span(&block, 1)));
        BindingSetHandle bindings =
            device().createBindingSet(BindingSetDesc().add(BindingItem::uniformBuffer(0, ubo)).add(textureBinding));
        TextureHandle target = createTexture2D(Format::RGBA8_UNORM, uint32_t(lookups.size()), 1, TextureUsage::RenderTarget);
        drawFullscreen(RenderPassDesc().addColor(Attachment::clear(target)),
                       fullscreenPipeline(shaderName, Format::RGBA8_UNORM), {bindings});
        return readTextureAs<Rgba8>(target);
    }
};

}  // namespace janus::rhi::test
