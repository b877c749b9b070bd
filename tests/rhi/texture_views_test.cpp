// Texture views in bindings (BindingItem::setMips / setLayers / setViewDimension): mip ranges
// (every backend; emulated on gles), single faces and layers (Capability::TextureViews), mip
// chains written from the level before, and the checks: invalid views, views overlapping what
// the same draw / dispatch writes, and the gles limits.
#include "layered_texture_test.h"

namespace janus::rhi::test {
namespace {

class TextureViewTest : public LayeredTextureTest {
protected:
    // 2x2 texel-centre lookups of one 2D image at `lod`, for the *_2d / *_array shaders.
    static void addImageLookups(std::vector<Lookup>& lookups, uint32_t size, float lod, float layer = 0) {
        for (uint32_t y = 0; y < size; ++y)
            for (uint32_t x = 0; x < size; ++x) lookups.push_back({{(x + 0.5f) / size, (y + 0.5f) / size, layer, 0}, lod});
    }
    static void addImageTexels(std::vector<Rgba8>& texels, uint32_t size, uint32_t mip, uint32_t layer) {
        for (uint32_t y = 0; y < size; ++y)
            for (uint32_t x = 0; x < size; ++x) texels.push_back(layerTexel(mip, layer, x, y));
    }
    // Records `body` and returns the rhi::Error a call in it throws, without executing the list.
    testing::AssertionResult recordingThrows(const std::function<void(ICommandList&)>& body, ErrorCode code,
                                             std::vector<std::string> mentions) {
        CommandListHandle cmd = device().createCommandList();
        cmd->begin();
        return throwsRhiError([&] { body(*cmd); }, code, std::move(mentions));
    }
};
JANUS_INSTANTIATE_BACKEND_TESTS(TextureViewTest);

// Mip ranges work on every backend: level of detail 0 of the view is its baseMip and the view
// ends at its last level (a larger lod clamps there).
TEST_P(TextureViewTest, MipRangeViewSamplesOnlyItsLevels) {
    SamplerHandle sampler = nearestClampSampler();
    struct Kind {
        TextureDimension dimension;
        const char* shader;
    };
    for (const Kind& kind : {Kind{TextureDimension::Texture2D, "rt_sample_lookup_2d_frag"},
                             Kind{TextureDimension::Texture2DArray, "rt_sample_lookup_array_frag"},
                             Kind{TextureDimension::TextureCube, "rt_sample_lookup_cube_frag"}}) {
        SCOPED_TRACE(toString(kind.dimension));
        const bool cube = kind.dimension == TextureDimension::TextureCube;
        const uint32_t layer = kind.dimension == TextureDimension::Texture2DArray ? 2 : cube ? 4 : 0;
        TextureHandle texture = createLayered(kind.dimension, 8, kind.dimension == TextureDimension::Texture2DArray ? 3 : 1, 4);
        writeEveryLayer(texture);
        // View mips 1..2: lod 0 -> mip 1 (4x4), lod 1 -> mip 2 (2x2), lod 3 -> clamped to mip 2.
        std::vector<Lookup> lookups;
        std::vector<Rgba8> expected;
        for (auto [lod, mip] : {std::pair{0.0f, 1u}, {1.0f, 2u}, {3.0f, 2u}}) {
            const uint32_t size = mipExtent(8, mip);
            for (uint32_t y = 0; y < size; ++y)
                for (uint32_t x = 0; x < size; ++x) {
                    const float s = (x + 0.5f) / size, t = (y + 0.5f) / size;
                    lookups.push_back({cube ? cubeTexelDirection(layer, s, t) : std::array<float, 4>{s, t, float(layer), 0}, lod});
                    expected.push_back(layerTexel(mip, layer, x, y));
                }
        }
        std::vector<Rgba8> seen = sampleLookups(kind.shader, BindingItem::sampledTexture(1, texture, sampler).setMips(1, 2), lookups);
        EXPECT_TRUE(imagesEqual(seen, expected, uint32_t(expected.size()))) << "lookups: 16 at lod 0, 4 at lod 1, 4 at lod 3";
    }
}

// GLES emulates mip ranges with texture state; a later binding of the whole texture (in the same
// command list) must see every level again.
TEST_P(TextureViewTest, MipRangeDoesNotLeakIntoLaterBindings) {
    TextureHandle texture = createLayered(TextureDimension::Texture2D, 4, 1, 3);
    writeEveryLayer(texture);
    std::vector<Lookup> lookups;
    addImageLookups(lookups, 4, 0.0f);
    struct Block {
        std::array<std::array<float, 4>, 64> coords{};
        std::array<float, 64> lods{};
    } data;
    for (size_t i = 0; i < lookups.size(); ++i) data.coords[i] = lookups[i].coords;
    BufferHandle ubo = createBuffer(BufferUsage::Uniform, std::as_bytes(std::span(&data, 1)));
    SamplerHandle sampler = nearestClampSampler();
    auto set = [&](BindingItem item) {
        return device().createBindingSet(BindingSetDesc().add(BindingItem::uniformBuffer(0, ubo)).add(item));
    };
    BindingSetHandle lastMip = set(BindingItem::sampledTexture(1, texture, sampler).setMips(2, 1));
    BindingSetHandle whole = set(BindingItem::sampledTexture(1, texture, sampler));
    PipelineHandle pipeline = fullscreenPipeline("rt_sample_lookup_2d_frag", Format::RGBA8_UNORM);
    TextureHandle first = createTexture2D(Format::RGBA8_UNORM, 16, 1, TextureUsage::RenderTarget);
    TextureHandle second = createTexture2D(Format::RGBA8_UNORM, 16, 1, TextureUsage::RenderTarget);
    submit([&](ICommandList& cmd) {
        for (auto [target, bindings] : {std::pair{first, lastMip}, {second, whole}}) {
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
            cmd.setPipeline(pipeline);
            cmd.setBindingSet(0, bindings);
            cmd.draw(3);
            cmd.endRenderPass();
        }
    });
    std::vector<Rgba8> mip2(16, layerTexel(2, 0, 0, 0)), mip0;
    addImageTexels(mip0, 4, 0, 0);
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(first), mip2, 16)) << "the 1x1 view of mip 2";
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(second), mip0, 16)) << "the whole texture at lod 0 is mip 0";
}

// A set bound after the draw's own, whose item (unused by the draw) views another mip range of
// the same texture, must not change what the draw samples (gles: ranges are texture state).
TEST_P(TextureViewTest, UnusedLaterBindingDoesNotChangeTheRange) {
    TextureHandle texture = createLayered(TextureDimension::Texture2D, 4, 1, 3);
    writeEveryLayer(texture);
    struct Block {
        std::array<std::array<float, 4>, 64> coords{};
        std::array<float, 64> lods{};
    } data;
    std::vector<Lookup> lookups;
    addImageLookups(lookups, 4, 0.0f);
    for (size_t i = 0; i < lookups.size(); ++i) data.coords[i] = lookups[i].coords;
    BufferHandle ubo = createBuffer(BufferUsage::Uniform, std::as_bytes(std::span(&data, 1)));
    SamplerHandle sampler = nearestClampSampler();
    BindingSetHandle used = device().createBindingSet(
        BindingSetDesc().add(BindingItem::uniformBuffer(0, ubo)).add(BindingItem::sampledTexture(1, texture, sampler)));
    BindingSetHandle unused =
        device().createBindingSet(BindingSetDesc().add(BindingItem::sampledTexture(3, texture, sampler).setMips(2, 1)));
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 16, 1, TextureUsage::RenderTarget);
    PipelineHandle pipeline = fullscreenPipeline("rt_sample_lookup_2d_frag", Format::RGBA8_UNORM);
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(pipeline);
        cmd.setBindingSet(0, used);
        cmd.setBindingSet(1, unused);   // the pipeline reads set 0 only
        cmd.draw(3);
        cmd.endRenderPass();
    });
    std::vector<Rgba8> mip0;
    addImageTexels(mip0, 4, 0, 0);
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(target), mip0, 16)) << "lod 0 of the whole texture is mip 0";
}

// One face of a cube, one layer of an array, one cube of a cube array, a layer subrange: views
// with layers need Capability::TextureViews. On gles creating them is UnsupportedCapability.
TEST_P(TextureViewTest, SingleFaceAndLayerViews) {
    SamplerHandle sampler = nearestClampSampler();
    TextureHandle cube = createLayered(TextureDimension::TextureCube, 4, 1, 2);
    TextureHandle array = createLayered(TextureDimension::Texture2DArray, 4, 4, 2);
    writeEveryLayer(cube);
    writeEveryLayer(array);
    auto faceView = [&](uint32_t face) {
        return BindingItem::sampledTexture(1, cube, sampler).setMips(1, 1).setLayers(face, 1).setViewDimension(TextureDimension::Texture2D);
    };
    if (!caps().textureViews) {
        ASSERT_TRUE(isGLES()) << "every backend but gles has texture views";
        EXPECT_TRUE(throwsRhiError([&] { device().createBindingSet(BindingSetDesc().add(faceView(3))); },
                                   ErrorCode::UnsupportedCapability, {"texture-views", "binding 1"}));
        EXPECT_TRUE(throwsRhiError(
            [&] { device().createBindingSet(BindingSetDesc().add(BindingItem::sampledTexture(1, array, sampler).setLayers(1, 2))); },
            ErrorCode::UnsupportedCapability, {"texture-views"}));
        return;
    }
    // Each face of mip 1 as a sampler2D.
    for (uint32_t face = 0; face < 6; ++face) {
        std::vector<Lookup> lookups;
        std::vector<Rgba8> expected;
        addImageLookups(lookups, 2, 0.0f);
        addImageTexels(expected, 2, 1, face);
        EXPECT_TRUE(imagesEqual(sampleLookups("rt_sample_lookup_2d_frag", faceView(face), lookups), expected, 4))
            << "face " << face;
    }
    // Layer 3 of the array as a sampler2D (both mips: lod 0 and 1).
    {
        std::vector<Lookup> lookups;
        std::vector<Rgba8> expected;
        addImageLookups(lookups, 4, 0.0f);
        addImageLookups(lookups, 2, 1.0f);
        addImageTexels(expected, 4, 0, 3);
        addImageTexels(expected, 2, 1, 3);
        EXPECT_TRUE(imagesEqual(sampleLookups("rt_sample_lookup_2d_frag",
                                              BindingItem::sampledTexture(1, array, sampler).setLayers(3, 1).setViewDimension(TextureDimension::Texture2D),
                                              lookups),
                                expected, 20));
    }
    // Layers 1..2 of the array as a 2D array: its layer 0 is the texture's layer 1.
    {
        std::vector<Lookup> lookups;
        std::vector<Rgba8> expected;
        addImageLookups(lookups, 4, 0.0f, 0.0f);
        addImageLookups(lookups, 4, 0.0f, 1.0f);
        addImageTexels(expected, 4, 0, 1);
        addImageTexels(expected, 4, 0, 2);
        EXPECT_TRUE(imagesEqual(sampleLookups("rt_sample_lookup_array_frag",
                                              BindingItem::sampledTexture(1, array, sampler).setLayers(1, 2), lookups),
                                expected, 32));
    }
    // A cube's faces as a 2D array (layer = face).
    {
        std::vector<Lookup> lookups;
        std::vector<Rgba8> expected;
        for (uint32_t face = 0; face < 6; ++face) {
            addImageLookups(lookups, 2, 0.0f, float(face));
            addImageTexels(expected, 2, 1, face);
        }
        EXPECT_TRUE(imagesEqual(sampleLookups("rt_sample_lookup_array_frag",
                                              BindingItem::sampledTexture(1, cube, sampler).setMips(1, 1).setViewDimension(TextureDimension::Texture2DArray),
                                              lookups),
                                expected, 24));
    }
    if (!caps().cubeArrays) return;
    // Cube 1 of a cube array (layer-faces 6..11) as a samplerCube, and one of its faces as 2D.
    TextureHandle cubes = createLayered(TextureDimension::TextureCubeArray, 2, 18, 1);
    writeEveryLayer(cubes);
    std::vector<Lookup> lookups;
    std::vector<Rgba8> expected;
    for (uint32_t face = 0; face < 6; ++face)
        for (uint32_t y = 0; y < 2; ++y)
            for (uint32_t x = 0; x < 2; ++x) {
                lookups.push_back({cubeTexelDirection(face, (x + 0.5f) / 2, (y + 0.5f) / 2), 0});
                expected.push_back(layerTexel(0, 6 + face, x, y));
            }
    EXPECT_TRUE(imagesEqual(sampleLookups("rt_sample_lookup_cube_frag",
                                          BindingItem::sampledTexture(1, cubes, sampler).setLayers(6, 6).setViewDimension(TextureDimension::TextureCube),
                                          lookups),
                            expected, 24));
    lookups.clear();
    expected.clear();
    addImageLookups(lookups, 2, 0.0f);
    addImageTexels(expected, 2, 0, 16);
    EXPECT_TRUE(imagesEqual(sampleLookups("rt_sample_lookup_2d_frag",
                                          BindingItem::sampledTexture(1, cubes, sampler).setLayers(16, 1).setViewDimension(TextureDimension::Texture2D),
                                          lookups),
                            expected, 4))
        << "layer-face 16 = cube 2, face 4";
}

// A mip chain built on the GPU from the level before, in one command list: compute writes mip N
// (storage image) while sampling mip N - 1 (a one-mip view). Exact: each level copies a parent
// texel and adds 1/255 to red.
TEST_P(TextureViewTest, ComputeWritesMipNWhileSamplingMipNMinusOne) {
    JANUS_REQUIRE_CAPABILITY(Capability::Compute);   // gles: no compute, so no storage images either
    JANUS_REQUIRE_CAPABILITY(Capability::StorageImages);
    SamplerHandle sampler = nearestClampSampler();
    struct Kind {
        TextureDimension dimension;
        uint32_t layers;
        const char* shader;
    };
    std::vector<Kind> kinds = {{TextureDimension::Texture2DArray, 3, "rt_downsample_layers_array_comp"}};
    // The shader reads mip N - 1 of a cube as a 2D array (texelFetch has no cube form).
    if (caps().textureViews) kinds.push_back({TextureDimension::TextureCube, 1, "rt_downsample_layers_cube_comp"});
    if (caps().textureViews && caps().cubeArrays)
        kinds.push_back({TextureDimension::TextureCubeArray, 12, "rt_downsample_layers_cube_array_comp"});
    for (const Kind& kind : kinds) {
        SCOPED_TRACE(toString(kind.dimension));
        TextureHandle texture = createLayered(kind.dimension, 8, kind.layers, 4, TextureUsage::Sampled | TextureUsage::Storage);
        const TextureDesc& d = texture->desc();
        const uint32_t layers = textureLayerCount(d);
        for (uint32_t layer = 0; layer < layers; ++layer) {
            std::vector<Rgba8> texels = layerImage(d, 0, layer);
            device().writeTexture(texture, {0, layer}, texels.data(), texels.size() * sizeof(Rgba8));
        }
        PipelineHandle pipeline = device().createComputePipeline(ComputePipelineDesc().setShader(shader(kind.shader)));
        submit([&](ICommandList& cmd) {
            cmd.setPipeline(pipeline);
            for (uint32_t mip = 1; mip < 4; ++mip) {
                cmd.setBindingSet(0, device().createBindingSet(
                                         BindingSetDesc()
                                             .add(BindingItem::sampledTexture(0, texture, sampler)
                                                      .setMips(mip - 1, 1)
                                                      .setViewDimension(TextureDimension::Texture2DArray))
                                             .add(BindingItem::storageImage(1, texture, mip))));
                cmd.dispatch(mipExtent(8, mip), mipExtent(8, mip), layers);
            }
        });
        expectEveryLayer(texture, [&](uint32_t mip, uint32_t layer) {
            std::vector<Rgba8> texels;
            for (uint32_t y = 0; y < mipExtent(8, mip); ++y)
                for (uint32_t x = 0; x < mipExtent(8, mip); ++x) {
                    Rgba8 t = layerTexel(0, layer, x << mip, y << mip);
                    t.r = uint8_t(t.r + mip);
                    texels.push_back(t);
                }
            return texels;
        });
    }
}

// The same chain for each cube face by render passes: pass into mip N face F while sampling
// mip N - 1. Through a samplerCube mip-range view this works on every backend; through a 2D
// view of the face it needs TextureViews (gles: UnsupportedCapability).
TEST_P(TextureViewTest, RenderPassWritesMipNOfAFaceWhileSamplingMipNMinusOne) {
    JANUS_REQUIRE_CAPABILITY(Capability::RenderToCubeFaceMip);
    SamplerHandle sampler = nearestClampSampler();
    for (bool faceViews : {false, true}) {
        SCOPED_TRACE(faceViews ? "sampler2D view of the face" : "samplerCube view of the level");
        TextureHandle cube = createLayered(TextureDimension::TextureCube, 8, 1, 4, TextureUsage::Sampled | TextureUsage::RenderTarget);
        for (uint32_t face = 0; face < 6; ++face) {
            std::vector<Rgba8> texels = layerImage(cube->desc(), 0, face);
            device().writeTexture(cube, {0, face}, texels.data(), texels.size() * sizeof(Rgba8));
        }
        auto source = [&](uint32_t mip, uint32_t face) {
            BindingItem item = BindingItem::sampledTexture(1, cube, sampler).setMips(mip - 1, 1);
            if (faceViews) item.setLayers(face, 1).setViewDimension(TextureDimension::Texture2D);
            return item;
        };
        std::vector<BufferHandle> faceIndex;
        for (uint32_t face = 0; face < 6; ++face)
            faceIndex.push_back(createBufferFrom(BufferUsage::Uniform, std::vector<int32_t>{int32_t(face), 0, 0, 0}));
        if (faceViews && !caps().textureViews) {
            EXPECT_TRUE(throwsRhiError([&] { device().createBindingSet(BindingSetDesc().add(source(1, 2))); },
                                       ErrorCode::UnsupportedCapability, {"texture-views"}));
            continue;
        }
        PipelineHandle pipeline = fullscreenPipeline(faceViews ? "rt_downsample_face_2d_frag" : "rt_downsample_face_cube_frag",
                                                     Format::RGBA8_UNORM);
        submit([&](ICommandList& cmd) {
            for (uint32_t mip = 1; mip < 4; ++mip)
                for (uint32_t face = 0; face < 6; ++face) {
                    cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(cube, {0, 0, 0, 0}, {mip, face})));
                    cmd.setPipeline(pipeline);
                    cmd.setBindingSet(0, device().createBindingSet(BindingSetDesc()
                                                                        .add(BindingItem::uniformBuffer(0, faceIndex[face]))
                                                                        .add(source(mip, face))));
                    cmd.draw(3);
                    cmd.endRenderPass();
                }
        });
        expectEveryLayer(cube, [&](uint32_t mip, uint32_t face) {
            std::vector<Rgba8> texels;
            for (uint32_t y = 0; y < mipExtent(8, mip); ++y)
                for (uint32_t x = 0; x < mipExtent(8, mip); ++x) {
                    Rgba8 t = layerTexel(0, face, x << mip, y << mip);
                    t.r = uint8_t(t.r + mip);
                    texels.push_back(t);
                }
            return texels;
        });
    }
}

TEST_P(TextureViewTest, InvalidViewsAreRejected) {
    SamplerHandle sampler = nearestClampSampler();
    TextureHandle texture = createLayered(TextureDimension::Texture2D, 4, 1, 3);
    TextureHandle cube = createLayered(TextureDimension::TextureCube, 4, 1, 1);
    TextureHandle volume = device().createTexture(TextureDesc().setDimension(TextureDimension::Texture3D).setSize(4, 4, 4));
    auto bind = [&](BindingItem item) { return [this, item] { device().createBindingSet(BindingSetDesc().add(item)); }; };
    const auto invalid = ErrorCode::InvalidDescription;
    EXPECT_TRUE(throwsRhiError(bind(BindingItem::sampledTexture(2, texture, sampler).setMips(3, 1)), invalid,
                               {"binding 2", "baseMip 3", "below 3"}));
    EXPECT_TRUE(throwsRhiError(bind(BindingItem::sampledTexture(2, texture, sampler).setMips(1, 3)), invalid, {"count 3"}));
    EXPECT_TRUE(throwsRhiError(bind(BindingItem::sampledTexture(2, texture, sampler).setMips(0, 0)), invalid, {"count 0"}));
    EXPECT_TRUE(throwsRhiError(bind(BindingItem::sampledTexture(2, cube, sampler).setLayers(6, 1)), invalid, {"baseLayer 6"}));
    EXPECT_TRUE(throwsRhiError(bind(BindingItem::sampledTexture(2, cube, sampler).setLayers(4, 3)), invalid, {"count 3"}));
    EXPECT_TRUE(throwsRhiError(bind(BindingItem::sampledTexture(2, volume, sampler).setLayers(1, 1)), invalid,
                               {"3D textures are viewed whole"}));
    EXPECT_TRUE(throwsRhiError(bind(BindingItem::sampledTexture(2, texture, sampler).setViewDimension(TextureDimension::TextureCube)),
                               invalid, {"cannot be viewed as cube", "2d or 2d-array"}));
    EXPECT_TRUE(throwsRhiError(bind(BindingItem::sampledTexture(2, volume, sampler).setViewDimension(TextureDimension::Texture2D)),
                               invalid, {"3d only"}));
    EXPECT_TRUE(throwsRhiError(bind(BindingItem::sampledTexture(2, cube, sampler).setLayers(0, 5)), invalid,
                               {"cube view shows 6 layers"}));
    EXPECT_TRUE(throwsRhiError(bind(BindingItem::sampledTexture(2, cube, sampler).setLayers(0, 2).setViewDimension(TextureDimension::Texture2D)),
                               invalid, {"2d view shows one layer"}));
    // The shader's type must match the view's dimension (the texture's when none is set).
    {
        std::vector<Lookup> lookups(1);
        EXPECT_TRUE(throwsRhiError([&] { sampleLookups("rt_sample_lookup_2d_frag", BindingItem::sampledTexture(1, cube, sampler), lookups); },
                                   ErrorCode::InvalidUsage, {"binding 1", "viewDimension"}));
    }
    if (!caps().storageImages) return;
    TextureHandle storage = createLayered(TextureDimension::Texture2DArray, 4, 3, 2, TextureUsage::Storage);
    EXPECT_TRUE(throwsRhiError(bind(BindingItem::storageImage(0, storage, 1).setMips(0, 2)), invalid,
                               {"storage image binds one mip level"}));
    EXPECT_TRUE(throwsRhiError(bind(BindingItem::storageImage(0, storage, 0).setLayers(0, 2)), invalid,
                               {"storage image binds all layers"}));
    EXPECT_TRUE(throwsRhiError(bind(BindingItem::storageImage(0, storage, 0).setLayers(1, 1)), invalid,
                               {"one layer as 2d"}));
}

// A view may not overlap what the same draw or dispatch writes: InvalidUsage on every backend,
// at the draw / dispatch.
TEST_P(TextureViewTest, ViewsOverlappingWrittenSubresourcesAreRejected) {
    SamplerHandle sampler = nearestClampSampler();
    TextureHandle texture = createLayered(TextureDimension::Texture2D, 8, 1, 2, TextureUsage::Sampled | TextureUsage::RenderTarget);
    writeEveryLayer(texture);
    PipelineHandle pipeline = fullscreenPipeline("rt_sample_lookup_2d_frag", Format::RGBA8_UNORM);
    BufferHandle ubo = createBuffer(BufferUsage::Uniform, 80 * 16);
    auto set = [&](BindingItem item) {
        return device().createBindingSet(BindingSetDesc().add(BindingItem::uniformBuffer(0, ubo)).add(item));
    };
    auto drawInto = [&](TextureSubresource target, BindingSetHandle bindings) {
        return [=, this](ICommandList& cmd) {
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::load(texture, target)));
            cmd.setPipeline(pipeline);
            cmd.setBindingSet(0, bindings);
            cmd.draw(3);
            cmd.endRenderPass();
        };
    };
    // Sampling the whole texture (mip 0 included) while rendering into mip 0.
    EXPECT_TRUE(recordingThrows(drawInto({0, 0}, set(BindingItem::sampledTexture(1, texture, sampler))),
                                ErrorCode::InvalidUsage, {"draw", "binding 1", "colour attachment 0", "mip 0"}));
    EXPECT_TRUE(recordingThrows(drawInto({1, 0}, set(BindingItem::sampledTexture(1, texture, sampler).setMips(1, 1))),
                                ErrorCode::InvalidUsage, {"colour attachment 0", "mip 1"}));
    // Sampling mip 1 while rendering into mip 0 is fine (and gives mip 1's texel at lod 0).
    submit(drawInto({0, 0}, set(BindingItem::sampledTexture(1, texture, sampler).setMips(1, 1))));
    if (caps().textureViews) {
        TextureHandle cube = createLayered(TextureDimension::TextureCube, 4, 1, 1, TextureUsage::Sampled | TextureUsage::RenderTarget);
        auto face = [&](uint32_t f) {
            return set(BindingItem::sampledTexture(1, cube, sampler).setLayers(f, 1).setViewDimension(TextureDimension::Texture2D));
        };
        auto cubePass = [&](uint32_t target, BindingSetHandle bindings) {
            return [=, this](ICommandList& cmd) {
                cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(cube, {0, 0, 0, 0}, {0, target})));
                cmd.setPipeline(pipeline);
                cmd.setBindingSet(0, bindings);
                cmd.draw(3);
                cmd.endRenderPass();
            };
        };
        EXPECT_TRUE(recordingThrows(cubePass(2, face(2)), ErrorCode::InvalidUsage, {"colour attachment 0", "layer 2"}));
        submit(cubePass(2, face(3)));   // another face: fine
    }
    if (!caps().compute || !caps().storageImages) return;
    // A dispatch writing mip 1 as a storage image while sampling a view that contains mip 1.
    TextureHandle array = createLayered(TextureDimension::Texture2DArray, 8, 3, 2, TextureUsage::Sampled | TextureUsage::Storage);
    PipelineHandle downsample =
        device().createComputePipeline(ComputePipelineDesc().setShader(shader("rt_downsample_layers_array_comp")));
    auto dispatchWith = [&](BindingItem source) {
        BindingSetHandle bindings = device().createBindingSet(
            BindingSetDesc().add(source).add(BindingItem::storageImage(1, array, 1)));
        return [=](ICommandList& cmd) {
            cmd.setPipeline(downsample);
            cmd.setBindingSet(0, bindings);
            cmd.dispatch(4, 4, 3);
        };
    };
    EXPECT_TRUE(recordingThrows(dispatchWith(BindingItem::sampledTexture(0, array, sampler)), ErrorCode::InvalidUsage,
                                {"dispatch", "binding 1 writes mip 1", "binding 0 samples mip 0..1"}));
    EXPECT_TRUE(recordingThrows(dispatchWith(BindingItem::sampledTexture(0, array, sampler).setMips(1, 1)),
                                ErrorCode::InvalidUsage, {"storage image"}));
    submit(dispatchWith(BindingItem::sampledTexture(0, array, sampler).setMips(0, 1)));   // disjoint: fine
}

// gles: no texture views (views are mip ranges emulated with GL_TEXTURE_BASE_LEVEL/MAX_LEVEL),
// so one texture can be sampled through one mip range per draw. Elsewhere two ranges of one
// texture in one draw sample their own levels.
TEST_P(TextureViewTest, TwoMipRangesOfOneTextureInOneDraw) {
    TextureHandle texture = createLayered(TextureDimension::Texture2D, 4, 1, 3);
    // Uniform levels, so the implicit level of detail of texture() cannot matter.
    for (uint32_t mip = 0; mip < 3; ++mip) {
        std::vector<Rgba8> texels(size_t(16) >> (2 * mip), Rgba8{uint8_t(50 * mip + 10), uint8_t(200 - 50 * mip), 0, 255});
        device().writeTexture(texture, {mip, 0}, texels.data(), texels.size() * sizeof(Rgba8));
    }
    SamplerHandle sampler = nearestClampSampler();
    BufferHandle params = createBufferFrom(BufferUsage::Uniform, std::vector<float>{0, 0, 0.2f, 0});
    BindingSetHandle bindings = device().createBindingSet(BindingSetDesc()
                                                              .add(BindingItem::uniformBuffer(0, params))
                                                              .add(BindingItem::sampledTexture(1, texture, sampler).setMips(1, 1))
                                                              .add(BindingItem::sampledTexture(2, texture, sampler).setMips(2, 1)));
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 2, 2, TextureUsage::RenderTarget);
    PipelineHandle pipeline = fullscreenPipeline("rt_two_textures_frag", Format::RGBA8_UNORM);
    auto draw = [&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(pipeline);
        cmd.setBindingSet(0, bindings);
        cmd.draw(3);
        cmd.endRenderPass();
    };
    if (isGLES()) {
        EXPECT_FALSE(caps().textureViews);
        EXPECT_FALSE(caps().cubeArrays) << "ESSL 300 has no samplerCubeArray";
        EXPECT_TRUE(recordingThrows(draw, ErrorCode::UnsupportedCapability, {"texture-views", "different mip ranges"}));
        return;
    }
    submit(draw);
    // r from texA = mip 1 (60), g from texB = mip 2 (100), b = 0.2 * 255 = 51.
    EXPECT_EQ(readTextureAs<Rgba8>(target), std::vector<Rgba8>(4, Rgba8{60, 100, 51, 255}));
}

}  // namespace
}  // namespace janus::rhi::test
