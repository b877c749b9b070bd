// Which GL entry point each kind of draw replays as, and what of a binding set replay reads. A draw of one instance goes through the plain
// entry point (glDrawArrays, glDrawElements, glDrawElementsBaseVertex), the call an application
// makes for it and the one the overhead bench's raw side makes (bench/raw_gl.cpp); GL defines it
// as the instanced call with one instance, so only the entry point differs. Instanced draws and
// base instances keep theirs. What the draws produce is tested on every backend elsewhere
// (buffers_test.cpp: VertexAndIndexBuffersFeedIndexedDraws, InstancingTest).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "gl_call_log.h"

namespace janus::rhi::test {
namespace {

GLCallLog& drawLog() { return GLCallLogTest::log(); }

void APIENTRY logDrawArrays(GLenum mode, GLint first, GLsizei count) {
    drawLog().calls.push_back("glDrawArrays");
    drawLog().original.glDrawArrays(mode, first, count);
}
void APIENTRY logDrawArraysInstanced(GLenum mode, GLint first, GLsizei count, GLsizei instances) {
    drawLog().calls.push_back("glDrawArraysInstanced");
    drawLog().original.glDrawArraysInstanced(mode, first, count, instances);
}
void APIENTRY logDrawArraysInstancedBaseInstance(GLenum mode, GLint first, GLsizei count, GLsizei instances,
                                                 GLuint baseInstance) {
    drawLog().calls.push_back("glDrawArraysInstancedBaseInstance");
    drawLog().original.glDrawArraysInstancedBaseInstance(mode, first, count, instances, baseInstance);
}
void APIENTRY logDrawElements(GLenum mode, GLsizei count, GLenum type, const void* indices) {
    drawLog().calls.push_back("glDrawElements");
    drawLog().original.glDrawElements(mode, count, type, indices);
}
void APIENTRY logDrawElementsBaseVertex(GLenum mode, GLsizei count, GLenum type, const void* indices, GLint baseVertex) {
    drawLog().calls.push_back("glDrawElementsBaseVertex");
    drawLog().original.glDrawElementsBaseVertex(mode, count, type, indices, baseVertex);
}
void APIENTRY logDrawElementsInstanced(GLenum mode, GLsizei count, GLenum type, const void* indices, GLsizei instances) {
    drawLog().calls.push_back("glDrawElementsInstanced");
    drawLog().original.glDrawElementsInstanced(mode, count, type, indices, instances);
}
void APIENTRY logDrawElementsInstancedBaseVertexBaseInstance(GLenum mode, GLsizei count, GLenum type, const void* indices,
                                                            GLsizei instances, GLint baseVertex, GLuint baseInstance) {
    drawLog().calls.push_back("glDrawElementsInstancedBaseVertexBaseInstance");
    drawLog().original.glDrawElementsInstancedBaseVertexBaseInstance(mode, count, type, indices, instances, baseVertex,
                                                                      baseInstance);
}

class GLDrawCallsTest : public GLCallLogTest {
protected:
    const char* watched() const override { return "the GL backend's draw entry points"; }
    void watch(gl::GLFunctions& gl, GLEntryPointOverrides& overrides) override {
        overrides.replace(gl.glDrawArrays, logDrawArrays);
        overrides.replace(gl.glDrawArraysInstanced, logDrawArraysInstanced);
        overrides.replace(gl.glDrawArraysInstancedBaseInstance, logDrawArraysInstancedBaseInstance);
        overrides.replace(gl.glDrawElements, logDrawElements);
        overrides.replace(gl.glDrawElementsBaseVertex, logDrawElementsBaseVertex);
        overrides.replace(gl.glDrawElementsInstanced, logDrawElementsInstanced);
        overrides.replace(gl.glDrawElementsInstancedBaseVertexBaseInstance, logDrawElementsInstancedBaseVertexBaseInstance);
    }
    // The entry points one draw, recorded by `draw` in a pass with a fullscreen pipeline and an
    // index buffer bound, replayed as.
    std::vector<std::string> entryPointsOf(const std::function<void(ICommandList&)>& draw) {
        TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 2, 2, TextureUsage::RenderTarget);
        PipelineHandle pipeline = fullscreenPipeline("rt_uv_frag", Format::RGBA8_UNORM);
        BufferHandle indices = createBufferFrom(BufferUsage::Index, std::vector<uint32_t>{0, 1, 2, 0, 1, 2});
        takeCalls();
        submit([&](ICommandList& cmd) {
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
            cmd.setPipeline(pipeline);
            cmd.setIndexBuffer(indices, IndexType::UInt32);
            draw(cmd);
            cmd.endRenderPass();
        });
        device().waitIdle();
        return takeCalls();
    }
    using Calls = std::vector<std::string>;
};
JANUS_INSTANTIATE_BACKEND_TESTS(GLDrawCallsTest);

TEST_P(GLDrawCallsTest, OneInstanceDrawsThroughThePlainEntryPoints) {
    EXPECT_EQ(entryPointsOf([](ICommandList& cmd) { cmd.draw(3); }), Calls{"glDrawArrays"});
    EXPECT_EQ(entryPointsOf([](ICommandList& cmd) { cmd.draw(3, 1, 3); }), Calls{"glDrawArrays"});
    EXPECT_EQ(entryPointsOf([](ICommandList& cmd) { cmd.drawIndexed(3); }), Calls{"glDrawElements"});
    EXPECT_EQ(entryPointsOf([](ICommandList& cmd) { cmd.drawIndexed(3, 1, 3); }), Calls{"glDrawElements"});
    // A vertex offset: GL's base vertex; ES 3.0 has none and shifts the attribute pointers.
    EXPECT_EQ(entryPointsOf([](ICommandList& cmd) { cmd.drawIndexed(3, 1, 0, 1); }),
              Calls{backend() == Backend::GLES ? "glDrawElements" : "glDrawElementsBaseVertex"});
}

TEST_P(GLDrawCallsTest, InstancedDrawsKeepTheInstancedEntryPoints) {
    const bool es = backend() == Backend::GLES;
    EXPECT_EQ(entryPointsOf([](ICommandList& cmd) { cmd.draw(3, 2); }), Calls{"glDrawArraysInstanced"});
    EXPECT_EQ(entryPointsOf([](ICommandList& cmd) { cmd.drawIndexed(3, 2); }),
              Calls{es ? "glDrawElementsInstanced" : "glDrawElementsInstancedBaseVertexBaseInstance"});
    // A first instance: GL's base instance, even for one instance; ES shifts the per-instance
    // attribute pointers (and sets gl_InstanceIndex's base uniform), so one instance is plain.
    EXPECT_EQ(entryPointsOf([](ICommandList& cmd) { cmd.draw(3, 1, 0, 1); }),
              Calls{es ? "glDrawArrays" : "glDrawArraysInstancedBaseInstance"});
    EXPECT_EQ(entryPointsOf([](ICommandList& cmd) { cmd.drawIndexed(3, 1, 0, 0, 1); }),
              Calls{es ? "glDrawElements" : "glDrawElementsInstancedBaseVertexBaseInstance"});
}

// What replay binds of a set, and where it reads it: a one-buffer set (the common per-draw set)
// keeps its binding points and its buffer range in the set's first cache line, with everything
// recording reads of it, so a bind per draw touches one line of the set and no other allocation
// (gl_device.h, BindingSet); larger sets bind their ranges from a vector.
TEST_P(GLDrawCallsTest, BindingSetsKeepTheirBufferRangesForReplay) {
    const std::vector<std::byte> bytes(1024);
    BufferHandle uniforms = createBuffer(BufferUsage::Uniform, bytes);
    BindingSetHandle one = device().createBindingSet(BindingSetDesc().add(BindingItem::uniformBuffer(3, uniforms, 256, 64)));
    const auto& oneSet = dynamic_cast<const gl::BindingSet&>(*one);
    const auto address = reinterpret_cast<uintptr_t>(&oneSet);
    EXPECT_EQ(address % 64, 0u) << "the set is aligned to a cache line";
    EXPECT_LE(oneSet.bindBytes(), 64u) << "a bind reads beyond the set's first line";
    const auto keepMark = reinterpret_cast<uintptr_t>(&keepMarkOf(oneSet));
    EXPECT_LE(keepMark + sizeof(KeepMark), address + 64) << "recording reads the keep mark in the first line";
    const gl::BindingSet::ReplayState& r = oneSet.replayState();
    ASSERT_TRUE(r.inlineRange);
    EXPECT_TRUE(r.range.plain);
    EXPECT_EQ(r.range.target(), GLenum(GL_UNIFORM_BUFFER));
    EXPECT_EQ(r.range.index, 3u);
    EXPECT_EQ(r.range.offset, 256u);
    EXPECT_EQ(r.range.size, 64u);
    EXPECT_EQ(r.range.buffer, dynamic_cast<const gl::Buffer&>(*uniforms).name());
    ASSERT_EQ(oneSet.bufferRanges().size(), 1u);
    EXPECT_EQ(oneSet.bufferRanges()[0].offset, 256);
    EXPECT_EQ(oneSet.bindingPoints(), uint64_t(1) << 3);
    EXPECT_FALSE(oneSet.hasTextures());

    BindingSetHandle three = device().createBindingSet(BindingSetDesc()
                                                           .add(BindingItem::uniformBuffer(0, uniforms, 0, 256))
                                                           .add(BindingItem::uniformBuffer(1, uniforms, 256, 256))
                                                           .add(BindingItem::uniformBuffer(5, uniforms, 512, 128)));
    const auto& threeSet = dynamic_cast<const gl::BindingSet&>(*three);
    EXPECT_FALSE(threeSet.replayState().inlineRange);
    ASSERT_EQ(threeSet.bufferRanges().size(), 3u);
    EXPECT_EQ(threeSet.bufferRanges()[1].index, 1u);
    EXPECT_EQ(threeSet.bufferRanges()[2].index, 5u);
    EXPECT_EQ(threeSet.bufferRanges()[2].offset, 512);
    EXPECT_EQ(threeSet.bufferRanges()[2].size, 128);
    EXPECT_EQ(threeSet.bindingPoints(), uint64_t(0b100011));
    EXPECT_FALSE(threeSet.replayState().range.plain);

    // One buffer and a texture: the buffer's range is inline, but the set is not plain (a command's
    // copy of the range would leave the texture unbound at replay).
    TextureHandle texture = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::Sampled);
    BindingSetHandle withTexture = device().createBindingSet(BindingSetDesc()
                                                                 .add(BindingItem::uniformBuffer(0, uniforms, 0, 64))
                                                                 .add(BindingItem::sampledTexture(1, texture, nearestClampSampler())));
    const auto& withTextureSet = dynamic_cast<const gl::BindingSet&>(*withTexture);
    EXPECT_TRUE(withTextureSet.replayState().inlineRange);
    EXPECT_TRUE(withTextureSet.hasTextures());
    EXPECT_FALSE(withTextureSet.replayState().range.plain);
}

// Binding the vertex or index buffer already bound records nothing (and leaves a ready draw
// ready), as Vulkan skips the bind; another buffer or offset is recorded. What the draws then
// read is checked on every backend by BufferTest.RebindingTheBoundBuffersDrawsTheSame.
TEST_P(GLDrawCallsTest, BindingTheBoundBuffersAgainRecordsNothing) {
    BufferHandle vertices = createBuffer(BufferUsage::Vertex, 256);
    BufferHandle other = createBuffer(BufferUsage::Vertex, 256);
    BufferHandle indices = createBuffer(BufferUsage::Index, 64);
    CommandListHandle list = device().createCommandList();
    list->begin();
    auto& recorded = dynamic_cast<gl::CommandList&>(*list);
    auto commandsAfter = [&](const std::function<void()>& call) {
        const size_t before = recorded.recordedCommandCountForTesting();
        call();
        return recorded.recordedCommandCountForTesting() - before;
    };
    EXPECT_EQ(commandsAfter([&] { list->setVertexBuffer(0, vertices); }), 1u);
    EXPECT_EQ(commandsAfter([&] { list->setVertexBuffer(0, vertices); }), 0u);
    EXPECT_EQ(commandsAfter([&] { list->setVertexBuffer(0, vertices, 16); }), 1u) << "another offset";
    EXPECT_EQ(commandsAfter([&] { list->setVertexBuffer(1, vertices, 16); }), 1u) << "another slot";
    EXPECT_EQ(commandsAfter([&] { list->setVertexBuffer(0, other, 16); }), 1u) << "another buffer";
    EXPECT_EQ(commandsAfter([&] { list->setIndexBuffer(indices, IndexType::UInt32); }), 1u);
    EXPECT_EQ(commandsAfter([&] { list->setIndexBuffer(indices, IndexType::UInt32); }), 0u);
    EXPECT_EQ(commandsAfter([&] { list->setIndexBuffer(indices, IndexType::UInt16); }), 1u) << "another type";
    list->end();
    // A new recording starts with nothing bound: the same buffer is recorded again.
    list->begin();
    EXPECT_EQ(commandsAfter([&] { list->setVertexBuffer(0, vertices); }), 1u);
    EXPECT_EQ(commandsAfter([&] { list->setIndexBuffer(indices, IndexType::UInt16); }), 1u);
    list->end();
}

}  // namespace
}  // namespace janus::rhi::test
