// Hazards inside one command list: each test records dependent commands into a single list, so a
// backend that synchronises only where it sees a hazard (the Vulkan backend tracks accesses
// since its last barrier) must find every one. Wrong results, or any validation message, fail;
// on Vulkan the suite runs with the layer's synchronisation validation, which reports a missing
// or too narrow barrier even where the CPU driver happens to produce the right result
// (MissingBarrierIsReportedBySynchronizationValidation shows that it does).
#include "backend_test.h"

namespace janus::rhi::test {
namespace {

class HazardTrackingTest : public BackendTest {
protected:
    void customizeDeviceDesc(DeviceDesc& desc) override { desc.setEnableSynchronizationValidation(true); }

    // Three uniform slices of one buffer (red in the first, blue in the last) with a binding set
    // for each end, and a pipeline that fills its target with the bound slice's colour.
    struct RedAndBlueSlices {
        uint64_t stride;
        BufferHandle parameters;
        BindingSetHandle first, last;
        PipelineHandle pipeline;

        // One pass into a 4x4 `target`: `first` draws its left half, then `last` its right half.
        void drawHalves(ICommandList& cmd, const TextureHandle& target) const { drawHalves(cmd, target, first, last); }
        // The same with `left`'s slice, then `right`'s.
        void drawHalves(ICommandList& cmd, const TextureHandle& target, const BindingSetHandle& left,
                        const BindingSetHandle& right) const {
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
            cmd.setPipeline(pipeline);
            cmd.setBindingSet(0, left);
            cmd.setScissor({0, 0, 2, 4});
            cmd.draw(3);
            cmd.setBindingSet(0, right);   // the pass reads `parameters` already
            cmd.setScissor({2, 0, 2, 4});
            cmd.draw(3);
            cmd.endRenderPass();
        }
        // One pass filling `target` with `set`'s slice.
        void fill(ICommandList& cmd, const TextureHandle& target, const BindingSetHandle& set) const {
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
            cmd.setPipeline(pipeline);
            cmd.setBindingSet(0, set);
            cmd.draw(3);
            cmd.endRenderPass();
        }
    };
    RedAndBlueSlices redAndBlueSlices() {
        const uint64_t stride = std::max<uint64_t>(caps().limits.uniformBufferOffsetAlignment, 16);
        std::vector<std::byte> slices(3 * stride);
        std::memcpy(slices.data(), kRed.data(), sizeof kRed);
        std::memcpy(slices.data() + 2 * stride, kBlue.data(), sizeof kBlue);
        BufferHandle parameters = createBufferFrom(BufferUsage::Uniform, slices);
        auto slice = [&](uint64_t index) {
            return device().createBindingSet(
                BindingSetDesc().add(BindingItem::uniformBuffer(0, parameters, index * stride, sizeof kRed)));
        };
        return {stride, parameters, slice(0), slice(2), fullscreenPipeline("bench_uniform_color_frag", Format::RGBA8_UNORM)};
    }
    // A 4x4 target whose left half `first` drew and right half `last`.
    static std::vector<Rgba8> redThenBlue() {
        std::vector<Rgba8> expected(16);
        for (size_t i = 0; i < 16; ++i) expected[i] = i % 4 < 2 ? Rgba8{255, 0, 0, 255} : Rgba8{0, 0, 255, 255};
        return expected;
    }
    static constexpr std::array<float, 4> kRed{1, 0, 0, 1}, kBlue{0, 0, 1, 1}, kGreen{0, 1, 0, 1};
};
JANUS_INSTANTIATE_BACKEND_TESTS(HazardTrackingTest);

// bench_increment_comp adds 1 to the uint it is bound to: read-modify-write of the same range.
TEST_P(HazardTrackingTest, DispatchesIncrementingTheSameCounterSeeEachOther) {
    JANUS_REQUIRE_CAPABILITY(Capability::Compute);
    JANUS_REQUIRE_CAPABILITY(Capability::StorageBuffers);
    BufferHandle counter = createBufferFrom(BufferUsage::Storage, std::vector<uint32_t>{10});
    PipelineHandle increment = computePipeline("bench_increment_comp");
    BindingSetHandle bindings = storageSlice(counter, 0, sizeof(uint32_t));
    submit([&](ICommandList& cmd) {
        cmd.setPipeline(increment);
        cmd.setBindingSet(0, bindings);
        for (int i = 0; i < 5; ++i) cmd.dispatch(1);
    });
    EXPECT_EQ(readBufferAs<uint32_t>(counter), std::vector<uint32_t>{15});
}

// The hazard tracker leaves out the barrier between a dispatch writing a counter and a copy
// reading it: the layer must report the read-after-write. Without synchronisation validation no
// message is recorded at all, so the test fails. (Two dispatches writing the same descriptor
// with no barrier between them are not reported by Debian's 1.3.239 layer; the copy is.)
TEST_P(HazardTrackingTest, MissingBarrierIsReportedBySynchronizationValidation) {
    JANUS_REQUIRE_CAPABILITY(Capability::Compute);
    JANUS_REQUIRE_CAPABILITY(Capability::StorageBuffers);
    if (backend() != Backend::Vulkan) GTEST_SKIP() << "only Vulkan has synchronisation validation";
    BufferHandle counter = createBufferFrom(BufferUsage::Storage, std::vector<uint32_t>{10});
    BufferHandle copy = createBuffer(BufferUsage::Storage, sizeof(uint32_t));
    PipelineHandle increment = computePipeline("bench_increment_comp");
    BindingSetHandle bindings = storageSlice(counter, 0, sizeof(uint32_t));
    submit([&](ICommandList& cmd) {
        cmd.setPipeline(increment);
        cmd.setBindingSet(0, bindings);
        cmd.dispatch(1);
        cmd.omitNextBarrierForTesting();
        cmd.copyBuffer(copy, 0, counter, 0, sizeof(uint32_t));
    });
    device().waitIdle();
    std::vector<std::string> hazards;
    for (const DebugMessage& message : device().takeDebugMessages())
        if (message.text.find("SYNC-HAZARD") != std::string::npos) hazards.push_back(message.text);
    ASSERT_EQ(hazards.size(), 1u) << "a copy reading what a dispatch wrote, with no barrier between, must be "
                                     "reported once";
    EXPECT_NE(hazards.front().find("SYNC-HAZARD-READ-AFTER-WRITE"), std::string::npos) << hazards.front();
    EXPECT_NE(hazards.front().find("SYNC_COMPUTE_SHADER_SHADER_STORAGE_WRITE"), std::string::npos) << hazards.front();
}

// Dispatches on disjoint slices need no barrier between them; the copy reading all of them does.
TEST_P(HazardTrackingTest, DisjointDispatchesThenCopyOfAllSlices) {
    JANUS_REQUIRE_CAPABILITY(Capability::Compute);
    JANUS_REQUIRE_CAPABILITY(Capability::StorageBuffers);
    const uint64_t stride = storageSliceStride(sizeof(uint32_t));
    const uint32_t slices = 4;
    BufferHandle counters =
        createBufferFrom(BufferUsage::Storage, std::vector<std::byte>(stride * slices));
    BufferHandle copy = createBuffer(BufferUsage::Storage, stride * slices);
    PipelineHandle increment = computePipeline("bench_increment_comp");
    std::vector<BindingSetHandle> sets;
    for (uint32_t i = 0; i < slices; ++i) sets.push_back(storageSlice(counters, i * stride, sizeof(uint32_t)));
    submit([&](ICommandList& cmd) {
        cmd.setPipeline(increment);
        // Slice i is incremented i + 1 times, interleaved so neighbours alternate.
        for (uint32_t round = 0; round < slices; ++round)
            for (uint32_t i = round; i < slices; ++i) {
                cmd.setBindingSet(0, sets[i]);
                cmd.dispatch(1);
            }
        cmd.copyBuffer(copy, 0, counters, 0, stride * slices);
    });
    const std::vector<std::byte> bytes = device().readBuffer(copy);
    for (uint32_t i = 0; i < slices; ++i) {
        uint32_t value = 0;
        std::memcpy(&value, bytes.data() + i * stride, sizeof(value));
        EXPECT_EQ(value, i + 1) << "slice " << i;
    }
}

// Two dispatches write the two halves of a vertex buffer (disjoint ranges); one draw reads each.
TEST_P(HazardTrackingTest, DisjointComputeWritesThenDrawsReadingBoth) {
    JANUS_REQUIRE_CAPABILITY(Capability::Compute);
    JANUS_REQUIRE_CAPABILITY(Capability::StorageBuffers);
    const uint64_t rectangleBytes = 6 * sizeof(ColorVertex);   // what write_vertices.comp writes
    const uint64_t second = storageSliceStride(rectangleBytes);
    BufferHandle vertices = createBuffer(BufferUsage::Storage | BufferUsage::Vertex, second + rectangleBytes);
    PipelineHandle writeVertices = computePipeline("rt_write_vertices_comp");
    BindingSetHandle first = storageSlice(vertices, 0, rectangleBytes);
    BindingSetHandle last = storageSlice(vertices, second, rectangleBytes);
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 8, 8, TextureUsage::RenderTarget);
    PipelineHandle draw = colorPipeline(Format::RGBA8_UNORM);
    TextureHandle second8 = createTexture2D(Format::RGBA8_UNORM, 8, 8, TextureUsage::RenderTarget);
    submit([&](ICommandList& cmd) {
        cmd.setPipeline(writeVertices);
        cmd.setBindingSet(0, first);
        cmd.dispatch(1);
        cmd.setBindingSet(0, last);
        cmd.dispatch(1);
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target, {1, 0, 0, 1})));
        cmd.setPipeline(draw);
        cmd.setVertexBuffer(0, vertices, 0);
        cmd.draw(6);
        cmd.endRenderPass();
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(second8, {1, 0, 0, 1})));
        cmd.setPipeline(draw);
        cmd.setVertexBuffer(0, vertices, second);
        cmd.draw(6);
        cmd.endRenderPass();
    });
    // The rectangle covers the left half (x < 4) in green over the red clear.
    std::vector<Rgba8> expected(64);
    for (uint32_t i = 0; i < 64; ++i) expected[i] = i % 8 < 4 ? Rgba8{0, 255, 0, 255} : Rgba8{255, 0, 0, 255};
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(target), expected, 8)) << "first half of the buffer";
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(second8), expected, 8)) << "second half of the buffer";
}

// Draws in one pass read two uniform slices of a buffer (the Vulkan backend gathers a pass's
// reads of one buffer into one range); after the pass a write replaces the first slice (write
// after read) and the next pass must see the new value, the first one the old.
TEST_P(HazardTrackingTest, DrawsReadingUniformSlicesThenOverwritingOne) {
    const RedAndBlueSlices slices = redAndBlueSlices();
    TextureHandle before = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    TextureHandle after = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    submit([&](ICommandList& cmd) {
        slices.drawHalves(cmd, before);
        cmd.writeBuffer(slices.parameters, kGreen.data(), sizeof kGreen, 0);
        slices.fill(cmd, after, slices.first);
    });
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(before), redThenBlue(), 4)) << "the pass before the write";
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(after), std::vector<Rgba8>(16, {0, 255, 0, 255}), 4))
        << "the pass after the write";
}

// A set changed per draw in a pass is bound and tracked when it is set, before its draw (the
// Vulkan backend's bindInPass): its slice still joins what the pass read, so a write to that slice
// after the pass waits for the pass (write after read; Vulkan's synchronization validation reports
// the hazard otherwise, and an unmerged slice is one the pass's first set does not cover).
TEST_P(HazardTrackingTest, ASliceBoundBeforeItsDrawIsTrackedForLaterWrites) {
    const RedAndBlueSlices slices = redAndBlueSlices();
    TextureHandle before = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    TextureHandle after = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    // Each set's descriptor set for the pipeline's layout exists from then on, so in the next list
    // `last` is bound and tracked where it is set (bindInPass).
    submit([&](ICommandList& cmd) { slices.drawHalves(cmd, before); });
    submit([&](ICommandList& cmd) {
        slices.drawHalves(cmd, before);
        cmd.writeBuffer(slices.parameters, kGreen.data(), sizeof kGreen, 2 * slices.stride);   // only `last`'s slice
        slices.fill(cmd, after, slices.last);
    });
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(before), redThenBlue(), 4)) << "the pass before the write";
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(after), std::vector<Rgba8>(16, {0, 255, 0, 255}), 4))
        << "the pass after the write";
}

// The same with the slices in the other order: the second draw's slice lies below the first's, so
// the pass's read of the buffer grows at its start (the Vulkan backend widens one range per
// buffer; a range that only grew at its end would leave the first slice's write unguarded, which
// synchronization validation reports).
TEST_P(HazardTrackingTest, ASliceBelowTheOnesBeforeItIsTrackedForLaterWrites) {
    const RedAndBlueSlices slices = redAndBlueSlices();
    TextureHandle before = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    TextureHandle after = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    submit([&](ICommandList& cmd) { slices.drawHalves(cmd, before, slices.last, slices.first); });
    submit([&](ICommandList& cmd) {
        slices.drawHalves(cmd, before, slices.last, slices.first);
        cmd.writeBuffer(slices.parameters, kGreen.data(), sizeof kGreen, 0);   // only `first`'s slice
        slices.fill(cmd, after, slices.first);
    });
    std::vector<Rgba8> blueThenRed(16);
    for (size_t i = 0; i < 16; ++i) blueThenRed[i] = i % 4 < 2 ? Rgba8{0, 0, 255, 255} : Rgba8{255, 0, 0, 255};
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(before), blueThenRed, 4)) << "the pass before the write";
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(after), std::vector<Rgba8>(16, {0, 255, 0, 255}), 4))
        << "the pass after the write";
}

// The same with draws alternating between slices of two buffers (the Vulkan backend's gathered
// range is handed over whenever the buffer changes, and its straight-line draw path gives way to
// the general one there): after the pass both buffers' first slices are overwritten, and only
// the next pass may see the new values.
TEST_P(HazardTrackingTest, DrawsAlternatingBetweenTwoBuffersThenOverwritingBoth) {
    const uint64_t stride = std::max<uint64_t>(caps().limits.uniformBufferOffsetAlignment, 16);
    const std::array<float, 4> red{1, 0, 0, 1}, blue{0, 0, 1, 1}, white{1, 1, 1, 1}, green{0, 1, 0, 1};
    auto buffer = [&](std::array<float, 4> first, std::array<float, 4> second) {
        std::vector<std::byte> slices(2 * stride);
        std::memcpy(slices.data(), first.data(), sizeof first);
        std::memcpy(slices.data() + stride, second.data(), sizeof second);
        return createBufferFrom(BufferUsage::Uniform, slices);
    };
    BufferHandle a = buffer(red, white), b = buffer(blue, white);
    auto slice = [&](const BufferHandle& of, uint64_t index) {
        return device().createBindingSet(BindingSetDesc().add(BindingItem::uniformBuffer(0, of, index * stride, sizeof red)));
    };
    // Columns 0..3 read a[0], b[0], a[1], b[1].
    const std::array<BindingSetHandle, 4> columns{slice(a, 0), slice(b, 0), slice(a, 1), slice(b, 1)};
    PipelineHandle pipeline = fullscreenPipeline("bench_uniform_color_frag", Format::RGBA8_UNORM);
    TextureHandle before = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    TextureHandle after = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    auto drawColumns = [&](ICommandList& cmd, const TextureHandle& target) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(pipeline);
        for (int32_t x = 0; x < 4; ++x) {
            cmd.setBindingSet(0, columns[x]);
            cmd.setScissor({x, 0, 1, 4});
            cmd.draw(3);
        }
        cmd.endRenderPass();
    };
    // Once before: a binding set takes the Vulkan backend's straight-line path only from its
    // second use on (the first creates its descriptor set).
    submit([&](ICommandList& cmd) { drawColumns(cmd, before); });
    submit([&](ICommandList& cmd) {
        drawColumns(cmd, before);
        // b first: a's write would be ordered by a barrier (barriers order everything before).
        cmd.writeBuffer(b, green.data(), sizeof green, 0);
        cmd.writeBuffer(a, green.data(), sizeof green, 0);
        drawColumns(cmd, after);
    });
    const Rgba8 r{255, 0, 0, 255}, bl{0, 0, 255, 255}, w{255, 255, 255, 255}, g{0, 255, 0, 255};
    std::vector<Rgba8> expectedBefore(16), expectedAfter(16);
    for (size_t i = 0; i < 16; ++i) {
        expectedBefore[i] = std::array{r, bl, w, w}[i % 4];
        expectedAfter[i] = std::array{g, g, w, w}[i % 4];
    }
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(before), expectedBefore, 4)) << "the pass before the writes";
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(after), expectedAfter, 4)) << "the pass after the writes";
}

// An index buffer changed between indexed draws of a pass is tracked as read by that pass, as the
// first one is (the Vulkan backend's straight-line drawIndexed takes a tracked index buffer only):
// overwriting the second after the pass waits for the pass (write after read; Vulkan's
// synchronization validation reports the hazard otherwise), and the next pass sees the new indices.
TEST_P(HazardTrackingTest, IndexBuffersSwitchedInAPassAreTrackedForLaterWrites) {
    const std::array<float, 6> wholeTarget{-1, -1, 3, -1, -1, 3};
    std::vector<ColorVertex> redThenGreen = triangle(wholeTarget, {1, 0, 0, 1});
    for (const ColorVertex& v : triangle(wholeTarget, {0, 1, 0, 1})) redThenGreen.push_back(v);
    BufferHandle vertices = createBufferFrom(BufferUsage::Vertex, redThenGreen);
    BufferHandle redIndices = createBufferFrom(BufferUsage::Index, std::vector<uint16_t>{0, 1, 2, 0});
    BufferHandle greenIndices = createBufferFrom(BufferUsage::Index, std::vector<uint16_t>{3, 4, 5, 3});
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM);
    TextureHandle before = createTexture2D(Format::RGBA8_UNORM, 2, 1, TextureUsage::RenderTarget);
    TextureHandle after = createTexture2D(Format::RGBA8_UNORM, 2, 1, TextureUsage::RenderTarget);
    auto drawHalves = [&](ICommandList& cmd, const TextureHandle& target) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(pipeline);
        cmd.setVertexBuffer(0, vertices);
        cmd.setIndexBuffer(redIndices, IndexType::UInt16);
        cmd.setScissor({0, 0, 1, 1});
        cmd.drawIndexed(3);
        cmd.setIndexBuffer(greenIndices, IndexType::UInt16);
        cmd.setScissor({1, 0, 1, 1});
        cmd.drawIndexed(3);
        cmd.endRenderPass();
    };
    const std::vector<uint16_t> nowRed{0, 1, 2, 0};
    submit([&](ICommandList& cmd) {
        drawHalves(cmd, before);
        cmd.writeBuffer(greenIndices, nowRed.data(), nowRed.size() * sizeof(uint16_t), 0);
        drawHalves(cmd, after);
    });
    const Rgba8 r{255, 0, 0, 255}, g{0, 255, 0, 255};
    EXPECT_EQ(readTextureAs<Rgba8>(before), (std::vector<Rgba8>{r, g})) << "the pass before the write";
    EXPECT_EQ(readTextureAs<Rgba8>(after), (std::vector<Rgba8>{r, r})) << "the pass after the write";
}

// Render into a texture, sample it into a second one, then render over the first again (write
// after read) and sample again: each sampling pass must see the pass recorded just before it.
TEST_P(HazardTrackingTest, RenderThenSampleThenRenderAgain) {
    TextureHandle canvas = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget | TextureUsage::Sampled);
    TextureHandle firstCopy = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    TextureHandle secondCopy = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    PipelineHandle sample = fullscreenPipeline("rt_sample_2d_frag", Format::RGBA8_UNORM);
    BindingSetHandle canvasSet = device().createBindingSet(
        BindingSetDesc().add(BindingItem::sampledTexture(0, canvas, nearestClampSampler())));
    auto sampleInto = [&](ICommandList& cmd, const TextureHandle& target) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(sample);
        cmd.setBindingSet(0, canvasSet);
        cmd.draw(3);
        cmd.endRenderPass();
    };
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(canvas, {0, 0, 1, 1})));
        cmd.endRenderPass();
        sampleInto(cmd, firstCopy);
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(canvas, {1, 1, 0, 1})));
        cmd.endRenderPass();
        sampleInto(cmd, secondCopy);
    });
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(firstCopy), std::vector<Rgba8>(16, {0, 0, 255, 255}), 4));
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(secondCopy), std::vector<Rgba8>(16, {255, 255, 0, 255}), 4));
}

// Copy into a counter, increment it, copy it out, then overwrite the source of the first copy
// (write after read) and repeat: every step depends on the one before.
TEST_P(HazardTrackingTest, CopyThenDispatchThenCopy) {
    JANUS_REQUIRE_CAPABILITY(Capability::Compute);
    JANUS_REQUIRE_CAPABILITY(Capability::StorageBuffers);
    BufferHandle source = createBufferFrom(BufferUsage::Storage, std::vector<uint32_t>{100});
    BufferHandle counter = createBuffer(BufferUsage::Storage, sizeof(uint32_t));
    BufferHandle results = createBuffer(BufferUsage::Storage, 2 * sizeof(uint32_t));
    PipelineHandle increment = computePipeline("bench_increment_comp");
    BindingSetHandle bindings = storageSlice(counter, 0, sizeof(uint32_t));
    const uint32_t twoHundred = 200;
    submit([&](ICommandList& cmd) {
        cmd.setPipeline(increment);
        cmd.setBindingSet(0, bindings);
        cmd.copyBuffer(counter, 0, source, 0, sizeof(uint32_t));
        cmd.dispatch(1);
        cmd.copyBuffer(results, 0, counter, 0, sizeof(uint32_t));
        cmd.writeBuffer(source, &twoHundred, sizeof(twoHundred), 0);
        cmd.copyBuffer(counter, 0, source, 0, sizeof(uint32_t));
        cmd.dispatch(1);
        cmd.dispatch(1);
        cmd.copyBuffer(results, sizeof(uint32_t), counter, 0, sizeof(uint32_t));
    });
    EXPECT_EQ(readBufferAs<uint32_t>(results), (std::vector<uint32_t>{101, 202}));
}

// A storage image written by compute, copied to a texture that a pass samples, in one list.
TEST_P(HazardTrackingTest, StorageImageWriteThenCopyThenSample) {
    JANUS_REQUIRE_CAPABILITY(Capability::Compute);
    JANUS_REQUIRE_CAPABILITY(Capability::StorageImages);
    const std::vector<Rgba8> pattern = {{10, 20, 30, 255}, {40, 50, 60, 255}, {70, 80, 90, 255}, {100, 110, 120, 255}};
    TextureHandle source = createTexture2D(Format::RGBA8_UNORM, 2, 2, TextureUsage::Sampled);
    device().writeTexture(source, {}, pattern.data(), pattern.size() * sizeof(Rgba8));
    TextureHandle image = createTexture2D(Format::RGBA8_UNORM, 2, 2, TextureUsage::Storage);
    TextureHandle copy = createTexture2D(Format::RGBA8_UNORM, 2, 2, TextureUsage::Sampled);
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 2, 2, TextureUsage::RenderTarget);
    PipelineHandle fetch = computePipeline("rt_fetch_to_image_comp");
    BindingSetHandle fetchSet = device().createBindingSet(BindingSetDesc()
                                                              .add(BindingItem::sampledTexture(0, source, nearestClampSampler()))
                                                              .add(BindingItem::storageImage(1, image)));
    PipelineHandle sample = fullscreenPipeline("rt_sample_2d_frag", Format::RGBA8_UNORM);
    BindingSetHandle sampleSet =
        device().createBindingSet(BindingSetDesc().add(BindingItem::sampledTexture(0, copy, nearestClampSampler())));
    submit([&](ICommandList& cmd) {
        cmd.setPipeline(fetch);
        cmd.setBindingSet(0, fetchSet);
        cmd.dispatch(2, 2);
        cmd.copyTexture(copy, {}, image, {});
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(sample);
        cmd.setBindingSet(0, sampleSet);
        cmd.draw(3);
        cmd.endRenderPass();
    });
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(target), pattern, 2));
}

}  // namespace
}  // namespace janus::rhi::test
