// Array textures and cube arrays: creation, transfers of every layer and mip, copies,
// generateMips, rendering into any layer(-face) and mip, sampling and compute writes.
// Cube arrays need Capability::CubeArrays (not on gles, whose ESSL 300 has no samplerCubeArray).
#include "layered_texture_test.h"

namespace janus::rhi::test {
namespace {

class ArrayTextureTest : public LayeredTextureTest {
protected:
    // The layered kinds this device has, with a layer count that exercises them.
    std::vector<std::pair<TextureDimension, uint32_t>> layeredKinds() const {
        std::vector<std::pair<TextureDimension, uint32_t>> kinds = {{TextureDimension::Texture2DArray, 3}};
        if (caps().cubeArrays) kinds.push_back({TextureDimension::TextureCubeArray, 12});
        return kinds;
    }
};
JANUS_INSTANTIATE_BACKEND_TESTS(ArrayTextureTest);

TEST_P(ArrayTextureTest, LimitsAndDescriptions) {
    EXPECT_GE(caps().limits.maxTextureArrayLayers, 256u);
    TextureHandle array = createLayered(TextureDimension::Texture2DArray, 4, 5, 0);
    EXPECT_EQ(array->desc().arrayLayers, 5u);
    EXPECT_EQ(array->desc().mipLevels, 3u) << "0 = full chain";
    EXPECT_EQ(textureLayerCount(array->desc()), 5u);
    EXPECT_EQ(textureLayerCount(TextureDesc().setDimension(TextureDimension::TextureCube)), 6u);

    auto create = [&](TextureDesc desc) { return [this, desc] { device().createTexture(desc); }; };
    EXPECT_TRUE(throwsRhiError(create(TextureDesc().setArrayLayers(2)), ErrorCode::InvalidDescription,
                               {"arrayLayers", "Texture2DArray"}));
    EXPECT_TRUE(throwsRhiError(create(TextureDesc().setDimension(TextureDimension::TextureCube).setArrayLayers(6)),
                               ErrorCode::InvalidDescription, {"arrayLayers must be 1"}));
    EXPECT_TRUE(throwsRhiError(create(TextureDesc().setDimension(TextureDimension::Texture2DArray).setArrayLayers(0)),
                               ErrorCode::InvalidDescription, {"arrayLayers"}));
    EXPECT_TRUE(throwsRhiError(create(TextureDesc()
                                          .setDimension(TextureDimension::Texture2DArray)
                                          .setArrayLayers(caps().limits.maxTextureArrayLayers + 1)),
                               ErrorCode::InvalidDescription, {"maxTextureArrayLayers"}));
    const auto cubeArray = TextureDesc().setDimension(TextureDimension::TextureCubeArray).setSize(4, 4);
    if (caps().cubeArrays) {
        EXPECT_TRUE(throwsRhiError(create(TextureDesc(cubeArray).setArrayLayers(8)), ErrorCode::InvalidDescription,
                                   {"multiple of 6"}));
        EXPECT_TRUE(throwsRhiError(create(TextureDesc(cubeArray).setArrayLayers(6).setSize(4, 2)),
                                   ErrorCode::InvalidDescription, {"width == height"}));
    } else {
        EXPECT_TRUE(throwsRhiError(create(TextureDesc(cubeArray).setArrayLayers(6)), ErrorCode::UnsupportedCapability,
                                   {"cube-arrays"}));
    }
    // Layers past the end are a usage error of the transfer, as for cube faces.
    Rgba8 texel{};
    EXPECT_TRUE(throwsRhiError([&] { device().writeTexture(array, {0, 5}, &texel, 0); }, ErrorCode::InvalidUsage,
                               {"layer 5"}));
}

TEST_P(ArrayTextureTest, EveryLayerAndMipRoundTrips) {
    for (auto [dimension, layers] : layeredKinds()) {
        SCOPED_TRACE(toString(dimension));
        TextureHandle texture = createLayered(dimension, 4, layers, 3);
        writeEveryLayer(texture);
        expectEveryLayer(texture, [&](uint32_t mip, uint32_t layer) { return layerImage(texture->desc(), mip, layer); });
    }
}

TEST_P(ArrayTextureTest, BufferCopiesAndTextureCopiesReachEveryLayer) {
    for (auto [dimension, layers] : layeredKinds()) {
        SCOPED_TRACE(toString(dimension));
        TextureHandle source = createLayered(dimension, 4, layers, 2);
        TextureHandle copy = createLayered(dimension, 4, layers, 2);
        const TextureDesc& d = source->desc();
        // Through buffers: every (mip, layer) image at its own offset, up and down again.
        std::vector<Rgba8> all;
        std::vector<std::pair<TextureSubresource, uint64_t>> offsets;
        for (uint32_t mip = 0; mip < d.mipLevels; ++mip)
            for (uint32_t layer = 0; layer < layers; ++layer) {
                offsets.push_back({{mip, layer}, all.size() * sizeof(Rgba8)});
                std::vector<Rgba8> image = layerImage(d, mip, layer);
                all.insert(all.end(), image.begin(), image.end());
            }
        BufferHandle upload = createBufferFrom(BufferUsage::None, all);
        BufferHandle download = createBuffer(BufferUsage::None, all.size() * sizeof(Rgba8));
        submit([&](ICommandList& cmd) {
            for (auto [sub, offset] : offsets) cmd.copyBufferToTexture(source, sub, upload, offset);
            // Layers and mips in the reverse order: layer L of `copy` gets layer (n - 1 - L).
            for (auto [sub, offset] : offsets)
                cmd.copyTexture(copy, {sub.mipLevel, layers - 1 - sub.layer}, source, sub);
            for (auto [sub, offset] : offsets) cmd.copyTextureToBuffer(download, offset, source, sub);
        });
        EXPECT_TRUE(imagesEqual(readBufferAs<Rgba8>(download), all, 4));
        expectEveryLayer(copy, [&](uint32_t mip, uint32_t layer) { return layerImage(d, mip, layers - 1 - layer); });
    }
}

TEST_P(ArrayTextureTest, GenerateMipsFiltersEveryLayer) {
    for (auto [dimension, layers] : layeredKinds()) {
        SCOPED_TRACE(toString(dimension));
        TextureHandle texture = createLayered(dimension, 8, layers, 0, TextureUsage::Sampled | TextureUsage::RenderTarget);
        // One colour per layer: any box filter gives it back exactly at every level.
        auto colour = [](uint32_t layer) { return Rgba8{uint8_t(20 * layer), uint8_t(250 - 20 * layer), 60, 255}; };
        for (uint32_t layer = 0; layer < layers; ++layer) {
            std::vector<Rgba8> texels(64, colour(layer));
            device().writeTexture(texture, {0, layer}, texels.data(), texels.size() * sizeof(Rgba8));
        }
        submit([&](ICommandList& cmd) { cmd.generateMips(texture); });
        expectEveryLayer(texture, [&](uint32_t mip, uint32_t layer) {
            return std::vector<Rgba8>(size_t(1) << (2 * (3 - mip)), colour(layer));
        });
    }
}

TEST_P(ArrayTextureTest, RendersIntoEveryLayerAndMip) {
    JANUS_REQUIRE_CAPABILITY(Capability::RenderToCubeFaceMip);
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM);
    // Left part (x < 0.1 in NDC, no pixel centre on an edge at 8, 4, 2 or 1 pixels) in one colour
    // over a clear colour, both unique per layer and mip.
    auto background = [](uint32_t mip, uint32_t layer) { return Color{0.0f, layer / 17.0f, mip / 5.0f, 1.0f}; };
    auto paint = [](uint32_t mip, uint32_t layer) { return Color{1.0f, mip / 5.0f, layer / 17.0f, 1.0f}; };
    for (auto [dimension, layers] : layeredKinds()) {
        SCOPED_TRACE(toString(dimension));
        TextureHandle texture = createLayered(dimension, 8, layers, 4, TextureUsage::Sampled | TextureUsage::RenderTarget);
        for (uint32_t mip = 0; mip < 4; ++mip)
            for (uint32_t layer = 0; layer < layers; ++layer)
                drawVertices(RenderPassDesc().addColor(Attachment::clear(texture, background(mip, layer), {mip, layer})),
                             pipeline, rectangle(-1.0f, -1.0f, 0.1f, 1.0f, paint(mip, layer)));
        expectEveryLayer(texture, [&](uint32_t mip, uint32_t layer) {
            const uint32_t size = mipExtent(8, mip);
            std::vector<Rgba8> expected;
            for (const Color& c : rasterize(rectangle(-1.0f, -1.0f, 0.1f, 1.0f, paint(mip, layer)), size, size,
                                            background(mip, layer)))
                expected.push_back(toRgba8(c));
            return expected;
        });
    }
}

TEST_P(ArrayTextureTest, SamplesEveryLayerAndMip) {
    SamplerHandle sampler = nearestClampSampler();
    for (auto [dimension, layers] : layeredKinds()) {
        SCOPED_TRACE(toString(dimension));
        const bool cubes = dimension == TextureDimension::TextureCubeArray;
        // 2 x 2 x layers texels at mip 0 and one texel per layer at mip 1: at most 60 lookups.
        TextureHandle texture = createLayered(dimension, 2, layers, 2);
        writeEveryLayer(texture);
        std::vector<Lookup> lookups;
        std::vector<Rgba8> expected;
        for (uint32_t mip = 0; mip < 2; ++mip) {
            const uint32_t size = mipExtent(2, mip);
            for (uint32_t layer = 0; layer < layers; ++layer)
                for (uint32_t y = 0; y < size; ++y)
                    for (uint32_t x = 0; x < size; ++x) {
                        const float s = (x + 0.5f) / size, t = (y + 0.5f) / size;
                        lookups.push_back({cubes ? cubeTexelDirection(layer % 6, s, t, float(layer / 6))
                                                 : std::array<float, 4>{s, t, float(layer), 0},
                                           float(mip)});
                        expected.push_back(layerTexel(mip, layer, x, y));
                    }
        }
        ASSERT_LE(lookups.size(), 64u);
        std::vector<Rgba8> seen = sampleLookups(cubes ? "rt_sample_lookup_cube_array_frag" : "rt_sample_lookup_array_frag",
                                                BindingItem::sampledTexture(1, texture, sampler), lookups);
        EXPECT_TRUE(imagesEqual(seen, expected, uint32_t(expected.size())))
            << "pixel i = lookup i: mip 0 layers first (4 texels each), then mip 1";
    }
}

TEST_P(ArrayTextureTest, ComputeWritesEveryLayerThroughStorageImages) {
    JANUS_REQUIRE_CAPABILITY(Capability::Compute);
    JANUS_REQUIRE_CAPABILITY(Capability::StorageImages);
    struct Kind {
        TextureDimension dimension;
        uint32_t layers;
        const char* shader;
    };
    std::vector<Kind> kinds = {{TextureDimension::Texture2DArray, 3, "rt_fill_layers_array_comp"},
                               {TextureDimension::TextureCube, 1, "rt_fill_layers_cube_comp"}};
    if (caps().cubeArrays) kinds.push_back({TextureDimension::TextureCubeArray, 12, "rt_fill_layers_cube_array_comp"});
    for (const Kind& kind : kinds) {
        SCOPED_TRACE(toString(kind.dimension));
        TextureHandle texture = createLayered(kind.dimension, 4, kind.layers, 2, TextureUsage::Sampled | TextureUsage::Storage);
        PipelineHandle pipeline = device().createComputePipeline(ComputePipelineDesc().setShader(shader(kind.shader)));
        const uint32_t layers = textureLayerCount(texture->desc());
        submit([&](ICommandList& cmd) {
            cmd.setPipeline(pipeline);
            for (uint32_t mip = 0; mip < 2; ++mip) {
                const std::array<uint32_t, 4> params = {mip, 0, 0, 0};
                cmd.setBindingSet(0, device().createBindingSet(
                                         BindingSetDesc()
                                             .add(BindingItem::uniformBuffer(0, createBufferFrom(BufferUsage::Uniform, std::vector(params.begin(), params.end()))))
                                             .add(BindingItem::storageImage(1, texture, mip))));
                cmd.dispatch(mipExtent(4, mip), mipExtent(4, mip), layers);
            }
        });
        expectEveryLayer(texture, [&](uint32_t mip, uint32_t layer) { return layerImage(texture->desc(), mip, layer); });
    }
}

// One layer of an array (or face of a cube) bound as an image2D: only that layer changes.
TEST_P(ArrayTextureTest, ComputeWritesOneLayerAsA2DImage) {
    JANUS_REQUIRE_CAPABILITY(Capability::Compute);
    JANUS_REQUIRE_CAPABILITY(Capability::StorageImages);
    PipelineHandle pipeline = device().createComputePipeline(ComputePipelineDesc().setShader(shader("rt_fill_layers_layer_comp")));
    for (auto [dimension, layers] : std::vector<std::pair<TextureDimension, uint32_t>>{
             {TextureDimension::Texture2DArray, 3}, {TextureDimension::TextureCube, 1}}) {
        SCOPED_TRACE(toString(dimension));
        TextureHandle texture = createLayered(dimension, 4, layers, 2, TextureUsage::Sampled | TextureUsage::Storage);
        const uint32_t target = 2, mip = 1;
        const std::vector<uint32_t> params = {mip, target, 0, 0};
        submit([&](ICommandList& cmd) {
            cmd.setPipeline(pipeline);
            cmd.setBindingSet(0, device().createBindingSet(
                                     BindingSetDesc()
                                         .add(BindingItem::uniformBuffer(0, createBufferFrom(BufferUsage::Uniform, params)))
                                         .add(BindingItem::storageImage(1, texture, mip)
                                                  .setLayers(target, 1)
                                                  .setViewDimension(TextureDimension::Texture2D))));
            cmd.dispatch(2, 2, 1);
        });
        expectEveryLayer(texture, [&](uint32_t m, uint32_t layer) {
            return m == mip && layer == target ? layerImage(texture->desc(), m, layer)
                                               : std::vector<Rgba8>(size_t(mipExtent(4, m)) * mipExtent(4, m));
        });
    }
}

}  // namespace
}  // namespace janus::rhi::test
