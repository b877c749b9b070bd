// Compute (capability-gated): dispatch group counts and ids, storage buffers at offsets, every
// slice of a 3D storage image, and compute output consumed by a draw in the same command list.
#include "backend_test.h"

namespace janus::rhi::test {
namespace {

class ComputeTest : public BackendTest {
protected:
    void SetUp() override {
        BackendTest::SetUp();
        if (IsSkipped() || HasFatalFailure()) return;
        JANUS_REQUIRE_CAPABILITY(Capability::Compute);
    }

    void dispatch(const PipelineHandle& pipeline, const BindingSetHandle& bindings, uint32_t x, uint32_t y = 1, uint32_t z = 1) {
        submit([&](ICommandList& cmd) {
            cmd.setPipeline(pipeline);
            cmd.setBindingSet(0, bindings);
            cmd.dispatch(x, y, z);
        });
    }
};
JANUS_INSTANTIATE_BACKEND_TESTS(ComputeTest);

using Slot = std::array<uint32_t, 4>;   // invocation_ids.comp: (workgroup id xyz, 1 + index)
constexpr uint32_t kUnwritten = 0xFFFFFFFFu;

// Expected slots of invocation_ids.comp (local size 2x1x1) for dispatch(gx, gy, gz).
std::vector<Slot> expectedSlots(uint32_t gx, uint32_t gy, uint32_t gz, size_t total) {
    std::vector<Slot> slots(total, Slot{kUnwritten, kUnwritten, kUnwritten, kUnwritten});
    const uint32_t sizeX = gx * 2;
    for (uint32_t i = 0; i < sizeX * gy * gz; ++i) {
        uint32_t x = i % sizeX, y = (i / sizeX) % gy, z = i / (sizeX * gy);
        slots[i] = {x / 2, y, z, 1 + i};
    }
    return slots;
}

TEST_P(ComputeTest, DispatchRunsEveryInvocationOnceWithItsIds) {
    JANUS_REQUIRE_CAPABILITY(Capability::StorageBuffers);
    const size_t total = 64;   // 48 invocations + 16 slots that must stay untouched
    std::vector<Slot> initial(total, Slot{kUnwritten, kUnwritten, kUnwritten, kUnwritten});
    BufferHandle buffer = createBufferFrom(BufferUsage::Storage, initial);
    dispatch(computePipeline("rt_invocation_ids_comp"),
             device().createBindingSet(BindingSetDesc().add(BindingItem::storageBuffer(0, buffer))), 3, 2, 4);
    EXPECT_TRUE(imagesEqual(readBufferAs<Slot>(buffer), expectedSlots(3, 2, 4, total), 6 * 2));
}

TEST_P(ComputeTest, StorageBufferBindingHonoursOffsetAndRange) {
    JANUS_REQUIRE_CAPABILITY(Capability::StorageBuffers);
    const uint64_t offset = std::max<uint64_t>(caps().limits.storageBufferOffsetAlignment, 16);
    const size_t slotsBefore = offset / sizeof(Slot), total = slotsBefore + 8;
    std::vector<Slot> initial(total, Slot{kUnwritten, kUnwritten, kUnwritten, kUnwritten});
    BufferHandle buffer = createBufferFrom(BufferUsage::Storage, initial);
    dispatch(computePipeline("rt_invocation_ids_comp"),
             device().createBindingSet(BindingSetDesc().add(BindingItem::storageBuffer(0, buffer, offset, 4 * sizeof(Slot)))), 2);
    std::vector<Slot> expected = initial;
    std::vector<Slot> written = expectedSlots(2, 1, 1, 4);
    std::copy(written.begin(), written.end(), expected.begin() + slotsBefore);
    EXPECT_TRUE(imagesEqual(readBufferAs<Slot>(buffer), expected, 4));
}

// The layered-binding pitfall: a 3D image bound for load/store must expose every slice.
TEST_P(ComputeTest, WritesEverySliceOf3DStorageImage) {
    JANUS_REQUIRE_CAPABILITY(Capability::StorageImages);
    TextureHandle volume = device().createTexture(TextureDesc().setDimension(TextureDimension::Texture3D)
                                                      .setFormat(Format::R32_UINT).setSize(8, 4, 4).setMipLevels(2)
                                                      .setUsage(TextureUsage::Storage | TextureUsage::Sampled));
    PipelineHandle pipeline = computePipeline("rt_fill_volume_comp");
    for (uint32_t mip : {0u, 1u}) {
        uint32_t w = mipExtent(8, mip), h = mipExtent(4, mip), d = mipExtent(4, mip);
        dispatch(pipeline, device().createBindingSet(BindingSetDesc().add(BindingItem::storageImage(0, volume, mip))), w, h, d);
        for (uint32_t z = 0; z < d; ++z) {
            SCOPED_TRACE(fmt::format("mip {} slice {}", mip, z));
            std::vector<uint32_t> expected;
            for (uint32_t y = 0; y < h; ++y)
                for (uint32_t x = 0; x < w; ++x) expected.push_back(1 + x + 16 * y + 256 * z);
            EXPECT_TRUE(imagesEqual(readTextureAs<uint32_t>(volume, {mip, z}), expected, w));
        }
    }
}

std::vector<Rgba8> fillImagePattern(uint32_t size) {
    std::vector<Rgba8> texels;
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) texels.push_back({uint8_t(17 * x), uint8_t(17 * y), uint8_t(255 - 17 * x), 255});
    return texels;
}

TEST_P(ComputeTest, Writes2DStorageImage) {
    JANUS_REQUIRE_CAPABILITY(Capability::StorageImages);
    TextureHandle image = createTexture2D(Format::RGBA8_UNORM, 16, 16, TextureUsage::Storage);
    dispatch(computePipeline("rt_fill_image_2d_comp"),
             device().createBindingSet(BindingSetDesc().add(BindingItem::storageImage(0, image))), 16, 16);
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(image), fillImagePattern(16), 16)) << "row 0 = invocation y 0";
}

TEST_P(ComputeTest, WritesFloatStorageImages) {
    JANUS_REQUIRE_CAPABILITY(Capability::StorageImages);
    for (auto [format, shaderName] : {std::pair{Format::RGBA16_FLOAT, "rt_fill_image_rgba16f_comp"},
                                      std::pair{Format::RGBA32_FLOAT, "rt_fill_image_rgba32f_comp"},
                                      std::pair{Format::R32_FLOAT, "rt_fill_image_r32f_comp"}}) {
        SCOPED_TRACE(toString(format));
        TextureHandle image = createTexture2D(format, 8, 8, TextureUsage::Storage);
        dispatch(computePipeline(shaderName), device().createBindingSet(BindingSetDesc().add(BindingItem::storageImage(0, image))), 8, 8);
        std::vector<Color> expected;
        for (uint32_t y = 0; y < 8; ++y)
            for (uint32_t x = 0; x < 8; ++x) expected.push_back(quantize(format, {x / 16.0f, y / 16.0f, 4.0f - x / 4.0f, 1.0f + y}));
        EXPECT_TRUE(imagesEqual(readColors(device(), image), expected, 8));
    }
}

// Render pass output read by a dispatch in the same command list (render -> compute ordering),
// through a sampler in a compute shader.
TEST_P(ComputeTest, DispatchReadsWhatARenderPassDrew) {
    JANUS_REQUIRE_CAPABILITY(Capability::StorageImages);
    TextureHandle rendered = createTexture2D(Format::RGBA8_UNORM, 8, 8, TextureUsage::RenderTarget | TextureUsage::Sampled);
    TextureHandle copy = createTexture2D(Format::RGBA8_UNORM, 8, 8, TextureUsage::Storage);
    PipelineHandle draw = colorPipeline(Format::RGBA8_UNORM);
    PipelineHandle fetch = computePipeline("rt_fetch_to_image_comp");
    BufferHandle vertices = createBufferFrom(BufferUsage::Vertex, orientationPattern());
    BindingSetHandle bindings = device().createBindingSet(BindingSetDesc()
                                                              .add(BindingItem::sampledTexture(0, rendered, nearestClampSampler()))
                                                              .add(BindingItem::storageImage(1, copy)));
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(rendered, {0, 0, 0, 1})));
        cmd.setPipeline(draw);
        cmd.setVertexBuffer(0, vertices);
        cmd.draw(uint32_t(orientationPattern().size()));
        cmd.endRenderPass();
        cmd.setPipeline(fetch);
        cmd.setBindingSet(0, bindings);
        cmd.dispatch(8, 8);
    });
    std::vector<Rgba8> expected;
    for (const Color& c : rasterize(orientationPattern(), 8, 8, {0, 0, 0, 1})) expected.push_back(toRgba8(c));
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(copy), expected, 8));
}

// The missing-barrier pitfall: a draw sampling what a dispatch just wrote, in one command list.
TEST_P(ComputeTest, DrawSamplesWhatADispatchWroteInTheSameCommandList) {
    JANUS_REQUIRE_CAPABILITY(Capability::StorageImages);
    TextureHandle image = createTexture2D(Format::RGBA8_UNORM, 16, 16, TextureUsage::Storage | TextureUsage::Sampled);
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 16, 16, TextureUsage::RenderTarget);
    PipelineHandle fill = computePipeline("rt_fill_image_2d_comp");
    PipelineHandle draw = fullscreenPipeline("rt_sample_2d_frag", Format::RGBA8_UNORM);
    BindingSetHandle storage = device().createBindingSet(BindingSetDesc().add(BindingItem::storageImage(0, image)));
    BindingSetHandle sampled = device().createBindingSet(BindingSetDesc().add(BindingItem::sampledTexture(0, image, nearestClampSampler())));
    submit([&](ICommandList& cmd) {
        cmd.setPipeline(fill);
        cmd.setBindingSet(0, storage);
        cmd.dispatch(16, 16);
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(draw);
        cmd.setBindingSet(0, sampled);
        cmd.draw(3);
        cmd.endRenderPass();
    });
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(target), fillImagePattern(16), 16));
}

// Compute -> vertex fetch needs its own barrier (GL: GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT).
TEST_P(ComputeTest, DrawReadsVerticesADispatchWrote) {
    JANUS_REQUIRE_CAPABILITY(Capability::StorageBuffers);
    BufferHandle vertices = createBuffer(BufferUsage::Storage | BufferUsage::Vertex, 6 * sizeof(ColorVertex));
    PipelineHandle fill = computePipeline("rt_write_vertices_comp");
    PipelineHandle draw = colorPipeline(Format::RGBA8_UNORM);
    BindingSetHandle bindings = device().createBindingSet(BindingSetDesc().add(BindingItem::storageBuffer(0, vertices)));
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    submit([&](ICommandList& cmd) {
        cmd.setPipeline(fill);
        cmd.setBindingSet(0, bindings);
        cmd.dispatch(1);
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target, {0, 0, 0, 1})));
        cmd.setPipeline(draw);
        cmd.setVertexBuffer(0, vertices);
        cmd.draw(6);
        cmd.endRenderPass();
    });
    std::vector<Rgba8> expected(16, Rgba8{0, 0, 0, 255});
    for (size_t i = 0; i < 16; ++i)
        if (i % 4 < 2) expected[i] = {0, 255, 0, 255};
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(target), expected, 4)) << "left half green";
}

TEST_P(ComputeTest, DispatchSeesBufferWrittenEarlierInTheCommandList) {
    JANUS_REQUIRE_CAPABILITY(Capability::StorageBuffers);
    std::vector<Slot> initial(8, Slot{1, 2, 3, 4});
    BufferHandle buffer = createBufferFrom(BufferUsage::Storage, initial);
    BufferHandle copy = createBuffer(BufferUsage::None, 8 * sizeof(Slot));
    PipelineHandle pipeline = computePipeline("rt_invocation_ids_comp");
    BindingSetHandle bindings = device().createBindingSet(BindingSetDesc().add(BindingItem::storageBuffer(0, buffer)));
    std::vector<Slot> unwritten(8, Slot{kUnwritten, kUnwritten, kUnwritten, kUnwritten});
    submit([&](ICommandList& cmd) {
        cmd.writeBuffer(buffer, unwritten.data(), unwritten.size() * sizeof(Slot));   // before the dispatch
        cmd.setPipeline(pipeline);
        cmd.setBindingSet(0, bindings);
        cmd.dispatch(1);
        cmd.copyBuffer(copy, 0, buffer, 0, 8 * sizeof(Slot));   // after it
    });
    EXPECT_TRUE(imagesEqual(readBufferAs<Slot>(copy), expectedSlots(1, 1, 1, 8), 2));
}

}  // namespace
}  // namespace janus::rhi::test
