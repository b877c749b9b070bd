// Which GL entry point each kind of draw replays as. A draw of one instance goes through the plain
// entry point (glDrawArrays, glDrawElements, glDrawElementsBaseVertex), the call an application
// makes for it and the one the overhead bench's raw side makes (bench/raw_gl.cpp); GL defines it
// as the instanced call with one instance, so only the entry point differs. Instanced draws and
// base instances keep theirs. What the draws produce is tested on every backend elsewhere
// (buffers_test.cpp: VertexAndIndexBuffersFeedIndexedDraws, InstancingTest).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "backend_test.h"
#include "gl_device.h"
#include "gl_entry_points.h"

namespace janus::rhi::test {
namespace {

struct DrawCallLog {
    std::vector<std::string> calls;
    gl::GLFunctions original;
};
DrawCallLog* g_drawLog = nullptr;   // GL entry points are plain functions: the wrappers find it here

void APIENTRY logDrawArrays(GLenum mode, GLint first, GLsizei count) {
    g_drawLog->calls.push_back("glDrawArrays");
    g_drawLog->original.glDrawArrays(mode, first, count);
}
void APIENTRY logDrawArraysInstanced(GLenum mode, GLint first, GLsizei count, GLsizei instances) {
    g_drawLog->calls.push_back("glDrawArraysInstanced");
    g_drawLog->original.glDrawArraysInstanced(mode, first, count, instances);
}
void APIENTRY logDrawArraysInstancedBaseInstance(GLenum mode, GLint first, GLsizei count, GLsizei instances,
                                                 GLuint baseInstance) {
    g_drawLog->calls.push_back("glDrawArraysInstancedBaseInstance");
    g_drawLog->original.glDrawArraysInstancedBaseInstance(mode, first, count, instances, baseInstance);
}
void APIENTRY logDrawElements(GLenum mode, GLsizei count, GLenum type, const void* indices) {
    g_drawLog->calls.push_back("glDrawElements");
    g_drawLog->original.glDrawElements(mode, count, type, indices);
}
void APIENTRY logDrawElementsBaseVertex(GLenum mode, GLsizei count, GLenum type, const void* indices, GLint baseVertex) {
    g_drawLog->calls.push_back("glDrawElementsBaseVertex");
    g_drawLog->original.glDrawElementsBaseVertex(mode, count, type, indices, baseVertex);
}
void APIENTRY logDrawElementsInstanced(GLenum mode, GLsizei count, GLenum type, const void* indices, GLsizei instances) {
    g_drawLog->calls.push_back("glDrawElementsInstanced");
    g_drawLog->original.glDrawElementsInstanced(mode, count, type, indices, instances);
}
void APIENTRY logDrawElementsInstancedBaseVertexBaseInstance(GLenum mode, GLsizei count, GLenum type, const void* indices,
                                                            GLsizei instances, GLint baseVertex, GLuint baseInstance) {
    g_drawLog->calls.push_back("glDrawElementsInstancedBaseVertexBaseInstance");
    g_drawLog->original.glDrawElementsInstancedBaseVertexBaseInstance(mode, count, type, indices, instances, baseVertex,
                                                                      baseInstance);
}

class GLDrawCallsTest : public BackendTest {
protected:
    void SetUp() override {
        BackendTest::SetUp();
        if (IsSkipped() || HasFatalFailure()) return;   // configuration not selected: no device
        if (backend() == Backend::Vulkan) GTEST_SKIP() << "the GL backend's draw entry points";
        gl::GLFunctions& gl = dynamic_cast<gl::Device&>(device()).context().gl;
        g_drawLog = &m_log;
        m_log.original = gl;
        m_overrides.replace(gl.glDrawArrays, logDrawArrays);
        m_overrides.replace(gl.glDrawArraysInstanced, logDrawArraysInstanced);
        m_overrides.replace(gl.glDrawArraysInstancedBaseInstance, logDrawArraysInstancedBaseInstance);
        m_overrides.replace(gl.glDrawElements, logDrawElements);
        m_overrides.replace(gl.glDrawElementsBaseVertex, logDrawElementsBaseVertex);
        m_overrides.replace(gl.glDrawElementsInstanced, logDrawElementsInstanced);
        m_overrides.replace(gl.glDrawElementsInstancedBaseVertexBaseInstance, logDrawElementsInstancedBaseVertexBaseInstance);
    }
    void TearDown() override {
        m_overrides.restoreAll();
        g_drawLog = nullptr;
        BackendTest::TearDown();
    }
    // The entry points one draw, recorded by `draw` in a pass with a fullscreen pipeline and an
    // index buffer bound, replayed as.
    std::vector<std::string> entryPointsOf(const std::function<void(ICommandList&)>& draw) {
        TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 2, 2, TextureUsage::RenderTarget);
        PipelineHandle pipeline = fullscreenPipeline("rt_uv_frag", Format::RGBA8_UNORM);
        BufferHandle indices = createBufferFrom(BufferUsage::Index, std::vector<uint32_t>{0, 1, 2, 0, 1, 2});
        m_log.calls.clear();
        submit([&](ICommandList& cmd) {
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
            cmd.setPipeline(pipeline);
            cmd.setIndexBuffer(indices, IndexType::UInt32);
            draw(cmd);
            cmd.endRenderPass();
        });
        device().waitIdle();
        return std::move(m_log.calls);
    }
    using Calls = std::vector<std::string>;

private:
    GLEntryPointOverrides m_overrides;
    DrawCallLog m_log;
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

}  // namespace
}  // namespace janus::rhi::test
