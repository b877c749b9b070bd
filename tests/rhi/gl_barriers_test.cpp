// The GL backend's memory barriers (issue 10, items 4 and 6): a barrier goes only where a command
// reads or overwrites what a shader wrote, with the bits for how it reads, and one ends a list
// that wrote anything. No GL tool reports a missing glMemoryBarrier (llvmpipe even runs correctly
// without one), so these tests watch the calls themselves: the device's GL entry points for
// barriers, dispatches, draws and buffer copies are wrapped to log the order they are made in,
// and each test checks the log as well as the values.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <string>
#include <vector>

#include "gl_call_log.h"

namespace janus::rhi::test {
namespace {

// One "dispatch", "draw", "copy" or "barrier <bits>" per call, in order.
GLCallLog& callLog() { return GLCallLogTest::log(); }

void APIENTRY loggedMemoryBarrier(GLbitfield bits) {
    // Bits glMemoryBarrier defines, or GL_ALL_BARRIER_BITS whole: NVIDIA rejects any other bit.
    EXPECT_TRUE(bits == GL_ALL_BARRIER_BITS || (bits & ~gl::kEveryMemoryBarrierBit) == 0) << fmt::format("{:#x}", bits);
    callLog().calls.push_back(fmt::format("barrier {:#x}", bits));
    callLog().original.glMemoryBarrier(bits);
}
void APIENTRY loggedDispatchCompute(GLuint x, GLuint y, GLuint z) {
    callLog().calls.push_back("dispatch");
    callLog().original.glDispatchCompute(x, y, z);
}
void APIENTRY loggedDrawArrays(GLenum mode, GLint first, GLsizei count) {
    callLog().calls.push_back("draw");
    callLog().original.glDrawArrays(mode, first, count);
}
void APIENTRY loggedDrawArraysInstanced(GLenum mode, GLint first, GLsizei count, GLsizei instances) {
    callLog().calls.push_back("draw");
    callLog().original.glDrawArraysInstanced(mode, first, count, instances);
}
void APIENTRY loggedCopyBufferSubData(GLenum read, GLenum write, GLintptr readOffset, GLintptr writeOffset,
                                      GLsizeiptr size) {
    callLog().calls.push_back("copy");
    callLog().original.glCopyBufferSubData(read, write, readOffset, writeOffset, size);
}

std::string barrier(GLbitfield bits) { return fmt::format("barrier {:#x}", bits); }
// What a barrier after every pending write ends up as: the bits not yet issued, each one a bit
// glMemoryBarrier defines (NVIDIA rejects any other with GL_INVALID_VALUE; Mesa ignores them).
constexpr GLbitfield kEvery = gl::kEveryMemoryBarrierBit;

class GLBarriersTest : public GLCallLogTest {
protected:
    const char* watched() const override { return "GL's glMemoryBarrier policy"; }
    void watch(gl::GLFunctions& gl, GLEntryPointOverrides& overrides) override {
        JANUS_REQUIRE_CAPABILITY(Capability::Compute);
        JANUS_REQUIRE_CAPABILITY(Capability::StorageBuffers);
        overrides.replace(gl.glMemoryBarrier, loggedMemoryBarrier);
        overrides.replace(gl.glDispatchCompute, loggedDispatchCompute);
        overrides.replace(gl.glDrawArrays, loggedDrawArrays);
        overrides.replace(gl.glDrawArraysInstanced, loggedDrawArraysInstanced);
        overrides.replace(gl.glCopyBufferSubData, loggedCopyBufferSubData);
    }
    // The calls the last submit() made (readBuffer's own copy is left out).
    std::vector<std::string> submitLogged(const std::function<void(ICommandList&)>& body) {
        takeCalls();
        submit(body);
        return takeCalls();
    }
};
JANUS_INSTANTIATE_BACKEND_TESTS(GLBarriersTest);

// (a) A dispatch reading what the previous one wrote waits for it; the list ends with a barrier.
TEST_P(GLBarriersTest, DispatchReadingThePreviousDispatchesWriteGetsABarrierBeforeIt) {
    BufferHandle counter = createBufferFrom(BufferUsage::Storage, std::vector<uint32_t>{10});
    PipelineHandle increment = computePipeline("bench_increment_comp");
    BindingSetHandle bindings = storageSlice(counter, 0, sizeof(uint32_t));
    const std::vector<std::string> calls = submitLogged([&](ICommandList& cmd) {
        cmd.setPipeline(increment);
        cmd.setBindingSet(0, bindings);
        cmd.dispatch(1);
        cmd.dispatch(1);
    });
    // The second write is new since the first barrier: the last one has every bit.
    EXPECT_EQ(calls, (std::vector<std::string>{"dispatch", barrier(GL_SHADER_STORAGE_BARRIER_BIT), "dispatch",
                                               barrier(kEvery)}));
    EXPECT_EQ(readBufferAs<uint32_t>(counter), std::vector<uint32_t>{12});
}

// (b) Dispatches writing disjoint slices need no barrier between them: one ends the list.
TEST_P(GLBarriersTest, DispatchesWritingDisjointSlicesGetNoBarrierBetweenThem) {
    const uint64_t stride = storageSliceStride(sizeof(uint32_t));
    const uint32_t slices = 4;
    BufferHandle counters = createBufferFrom(BufferUsage::Storage, std::vector<std::byte>(stride * slices));
    PipelineHandle increment = computePipeline("bench_increment_comp");
    std::vector<BindingSetHandle> sets;
    for (uint32_t i = 0; i < slices; ++i) sets.push_back(storageSlice(counters, i * stride, sizeof(uint32_t)));
    const std::vector<std::string> calls = submitLogged([&](ICommandList& cmd) {
        cmd.setPipeline(increment);
        for (const BindingSetHandle& set : sets) {
            cmd.setBindingSet(0, set);
            cmd.dispatch(1);
        }
    });
    EXPECT_EQ(calls, (std::vector<std::string>{"dispatch", "dispatch", "dispatch", "dispatch",
                                               barrier(kEvery)}));
    const std::vector<std::byte> bytes = device().readBuffer(counters);
    for (uint32_t i = 0; i < slices; ++i) {
        uint32_t value = 0;
        std::memcpy(&value, bytes.data() + i * stride, sizeof(value));
        EXPECT_EQ(value, 1u) << "slice " << i;
    }
}

// (c) A copy after a dispatch waits for it (buffer-update bit) and copies the new value.
TEST_P(GLBarriersTest, CopyAfterDispatchSeesItsResult) {
    BufferHandle counter = createBufferFrom(BufferUsage::Storage, std::vector<uint32_t>{41});
    BufferHandle copy = createBuffer(BufferUsage::Storage, sizeof(uint32_t));
    PipelineHandle increment = computePipeline("bench_increment_comp");
    BindingSetHandle bindings = storageSlice(counter, 0, sizeof(uint32_t));
    const std::vector<std::string> calls = submitLogged([&](ICommandList& cmd) {
        cmd.setPipeline(increment);
        cmd.setBindingSet(0, bindings);
        cmd.dispatch(1);
        cmd.copyBuffer(copy, 0, counter, 0, sizeof(uint32_t));
    });
    EXPECT_EQ(calls, (std::vector<std::string>{"dispatch", barrier(GL_BUFFER_UPDATE_BARRIER_BIT), "copy",
                                               barrier(kEvery & ~GL_BUFFER_UPDATE_BARRIER_BIT)}));
    EXPECT_EQ(readBufferAs<uint32_t>(copy), std::vector<uint32_t>{42});
}

// (c) Draws reading vertices a dispatch wrote: a barrier for vertex fetching comes before the
// draw even after an earlier barrier for storage reads (which does not cover vertex fetching),
// and the draw shows what compute wrote.
TEST_P(GLBarriersTest, DrawAfterDispatchSeesItsVertices) {
    const uint64_t rectangleBytes = 6 * sizeof(ColorVertex);   // what write_vertices.comp writes
    BufferHandle vertices = createBuffer(BufferUsage::Storage | BufferUsage::Vertex, rectangleBytes);
    BufferHandle unrelated = createBuffer(BufferUsage::Storage, sizeof(uint32_t));
    PipelineHandle writeVertices = computePipeline("rt_write_vertices_comp");
    PipelineHandle increment = computePipeline("bench_increment_comp");
    BindingSetHandle vertexSlice = storageSlice(vertices, 0, rectangleBytes);
    // Reads (and rewrites) the first float's bits: one ulp moves nothing on an 8x8 target.
    BindingSetHandle firstWord = storageSlice(vertices, 0, sizeof(uint32_t));
    BindingSetHandle unrelatedSlice = storageSlice(unrelated, 0, sizeof(uint32_t));
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 8, 8, TextureUsage::RenderTarget);
    PipelineHandle draw = colorPipeline(Format::RGBA8_UNORM);
    const std::vector<std::string> calls = submitLogged([&](ICommandList& cmd) {
        cmd.setPipeline(writeVertices);
        cmd.setBindingSet(0, vertexSlice);
        cmd.dispatch(1);
        cmd.setPipeline(increment);
        cmd.setBindingSet(0, unrelatedSlice);
        cmd.dispatch(1);   // disjoint: no barrier
        cmd.setBindingSet(0, firstWord);
        cmd.dispatch(1);   // reads what the first dispatch wrote
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target, {1, 0, 0, 1})));
        cmd.setPipeline(draw);
        cmd.setVertexBuffer(0, vertices, 0);
        cmd.draw(6);
        cmd.draw(6);   // nothing new to wait for
        cmd.endRenderPass();
    });
    EXPECT_EQ(calls, (std::vector<std::string>{"dispatch", "dispatch", barrier(GL_SHADER_STORAGE_BARRIER_BIT),
                                               "dispatch", barrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT), "draw", "draw",
                                               barrier(kEvery & ~GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT)}));
    std::vector<Rgba8> expected(64);
    for (uint32_t i = 0; i < 64; ++i) expected[i] = i % 8 < 4 ? Rgba8{0, 255, 0, 255} : Rgba8{255, 0, 0, 255};
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(target), expected, 8));
}

// A dynamic uniform buffer's window is wherever its offset puts it: a dispatch reading slice 2
// through it waits for the dispatch that wrote slice 2, though the set's own window (slice 0) does
// not overlap that write. The written index says which value the read saw (llvmpipe runs in order
// either way: the log is what fails without the barrier).
TEST_P(GLBarriersTest, ADynamicWindowMovedOntoAWrittenSliceGetsABarrier) {
    const uint32_t stride = uint32_t(std::max<uint64_t>({caps().limits.uniformBufferOffsetAlignment,
                                                         caps().limits.storageBufferOffsetAlignment, 16}));
    std::vector<uint32_t> words(4 * stride / sizeof(uint32_t), 0);
    words[2 * stride / sizeof(uint32_t)] = 1;       // slice 2: index 1, incremented to 2 below
    words[2 * stride / sizeof(uint32_t) + 1] = 7;   // and value 7
    BufferHandle slices = createBufferFrom(BufferUsage::Storage | BufferUsage::Uniform, words);
    BufferHandle results = createBufferFrom(BufferUsage::Storage, std::vector<uint32_t>(4, 0));
    PipelineHandle increment = computePipeline("bench_increment_comp");
    PipelineHandle reading = computePipeline("rt_dynamic_slice_comp", {{0, 0}});
    BindingSetHandle writeSlice2 = storageSlice(slices, 2 * stride, sizeof(uint32_t));
    BindingSetHandle window = device().createBindingSet(BindingSetDesc()
                                                            .add(BindingItem::uniformBuffer(0, slices, 0, 8).setDynamicOffset())
                                                            .add(BindingItem::storageBuffer(1, results)));
    const std::array<uint32_t, 1> slice2 = {2 * stride};
    const std::vector<std::string> calls = submitLogged([&](ICommandList& cmd) {
        cmd.setPipeline(increment);
        cmd.setBindingSet(0, writeSlice2);
        cmd.dispatch(1);
        cmd.setPipeline(reading);
        cmd.setBindingSet(0, window, slice2);
        cmd.dispatch(1);
    });
    ASSERT_GE(calls.size(), 3u);
    EXPECT_EQ(calls[0], "dispatch");
    EXPECT_TRUE(calls[1].starts_with("barrier") &&
                (std::stoul(calls[1].substr(8), nullptr, 16) & GL_UNIFORM_BARRIER_BIT) != 0)
        << "the read through the moved window must wait for the write; calls: " << fmt::format("{}", fmt::join(calls, ", "));
    EXPECT_EQ(readBufferAs<uint32_t>(results), (std::vector<uint32_t>{0, 0, 7, 0}));
}

// A list that only draws and copies (no shader writes) issues no barrier at all.
TEST_P(GLBarriersTest, ListWithoutShaderWritesHasNoBarrier) {
    BufferHandle source = createBufferFrom(BufferUsage::Storage, std::vector<uint32_t>{7});
    BufferHandle copy = createBuffer(BufferUsage::Storage, sizeof(uint32_t));
    const std::vector<std::string> calls =
        submitLogged([&](ICommandList& cmd) { cmd.copyBuffer(copy, 0, source, 0, sizeof(uint32_t)); });
    EXPECT_EQ(calls, std::vector<std::string>{"copy"});
    EXPECT_EQ(readBufferAs<uint32_t>(copy), std::vector<uint32_t>{7});
}

// (g) A write still pending after a draw that did not wait for it: the next draw, whose new set
// reads the written buffer, waits for it, though the set's binding check is cached (binding it
// then checks nothing at the draw) and the draw before needed no checks.
TEST_P(GLBarriersTest, ADrawAfterOneThatLeftAWritePendingIsTracked) {
    BufferHandle written = createBuffer(BufferUsage::Storage | BufferUsage::Uniform, 256);
    PipelineHandle increment = computePipeline("bench_increment_comp");
    BindingSetHandle counter = storageSlice(written, 0, sizeof(uint32_t));
    PipelineHandle reading = fullscreenPipeline("rt_std140_read_frag", Format::R32_UINT);
    BindingSetHandle other = device().createBindingSet(
        BindingSetDesc().add(BindingItem::uniformBuffer(0, createBuffer(BufferUsage::Uniform, 256))));
    BindingSetHandle readsWritten = device().createBindingSet(BindingSetDesc().add(BindingItem::uniformBuffer(0, written)));
    TextureHandle target = createTexture2D(Format::R32_UINT, 32, 1, TextureUsage::RenderTarget);
    auto draws = [&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(reading);
        cmd.setBindingSet(0, other);
        cmd.draw(3);
        cmd.setBindingSet(0, readsWritten);
        cmd.draw(3);
        cmd.endRenderPass();
    };
    EXPECT_EQ(submitLogged(draws), (std::vector<std::string>{"draw", "draw"}));   // caches both sets' checks
    const std::vector<std::string> calls = submitLogged([&](ICommandList& cmd) {
        cmd.setPipeline(increment);
        cmd.setBindingSet(0, counter);
        cmd.dispatch(1);
        draws(cmd);
    });
    EXPECT_EQ(calls, (std::vector<std::string>{"dispatch", "draw", barrier(GL_UNIFORM_BARRIER_BIT), "draw",
                                               barrier(kEvery & ~GL_UNIFORM_BARRIER_BIT)}));
}

// rt_layout_std430_comp's set: `source` read (readonly) at 0, the flat copy and the block written at 1 and 2.
BindingSetHandle layoutBindings(IDevice& device, const BufferHandle& source, const BufferHandle& flat,
                                const BufferHandle& block) {
    return device.createBindingSet(BindingSetDesc()
                                       .add(BindingItem::storageBuffer(0, source))
                                       .add(BindingItem::storageBuffer(1, flat))
                                       .add(BindingItem::storageBuffer(2, block)));
}

// (h) A `readonly` storage buffer is only read: dispatches reading what one dispatch wrote wait for
// it once, and none of them counts as writing it. Before, every storage binding counted as a
// write, so each of them waited for the one before (a barrier per dispatch, and per draw in the
// renderer's forward pass, which reads its light lists so).
TEST_P(GLBarriersTest, ReadOnlyStorageIsNotAWrite) {
    BufferHandle source = createBufferFrom(BufferUsage::Storage, std::vector<uint32_t>(64, 0u));
    PipelineHandle increment = computePipeline("bench_increment_comp");
    PipelineHandle layout = computePipeline("rt_layout_std430_comp");
    BindingSetHandle counter = storageSlice(source, 0, sizeof(uint32_t));
    std::vector<BufferHandle> flats;
    std::vector<BindingSetHandle> reads;
    for (int i = 0; i < 3; ++i) {
        flats.push_back(createBuffer(BufferUsage::Storage, 256));
        reads.push_back(layoutBindings(device(), source, flats.back(), createBuffer(BufferUsage::Storage, 256)));
    }
    const std::vector<std::string> calls = submitLogged([&](ICommandList& cmd) {
        cmd.setPipeline(increment);
        cmd.setBindingSet(0, counter);
        cmd.dispatch(1);
        cmd.setPipeline(layout);
        for (const BindingSetHandle& set : reads) {
            cmd.setBindingSet(0, set);
            cmd.dispatch(1);
        }
    });
    EXPECT_EQ(calls, (std::vector<std::string>{"dispatch", barrier(GL_SHADER_STORAGE_BARRIER_BIT), "dispatch", "dispatch",
                                               "dispatch", barrier(kEvery)}));
    for (const BufferHandle& flat : flats) EXPECT_EQ(readBufferAs<uint32_t>(flat)[0], 1u);   // src.v.x: the counter's bits
}

// (i) Dispatches writing the same two buffers in turn keep one pending write each: every one
// waits for the one before, and the list of writes to check does not grow with them (it grew by
// two entries a dispatch, which every later dispatch scanned).
TEST_P(GLBarriersTest, RepeatedWritesKeepOnePendingEntryPerRange) {
    PipelineHandle layout = computePipeline("rt_layout_std430_comp");
    BindingSetHandle set = layoutBindings(device(), createBuffer(BufferUsage::Storage, 256),
                                          createBuffer(BufferUsage::Storage, 256), createBuffer(BufferUsage::Storage, 256));
    constexpr int kDispatches = 16;
    size_t pending = 0;
    const std::vector<std::string> calls = submitLogged([&](ICommandList& cmd) {
        cmd.setPipeline(layout);
        cmd.setBindingSet(0, set);
        for (int i = 0; i < kDispatches; ++i) cmd.dispatch(1);
        pending = dynamic_cast<gl::CommandList&>(cmd).pendingWriteCountForTesting();
    });
    EXPECT_EQ(pending, 2u) << "the flat copy and the block";
    std::vector<std::string> expected{"dispatch"};
    for (int i = 1; i < kDispatches; ++i) {
        expected.push_back(barrier(GL_SHADER_STORAGE_BARRIER_BIT));
        expected.push_back("dispatch");
    }
    expected.push_back(barrier(kEvery));
    EXPECT_EQ(calls, expected);
}

}  // namespace
}  // namespace janus::rhi::test
