// How the GL backend gives a new buffer its zeros (rhi.h: new buffers read as zero): from the
// host, in the glBufferData that makes its storage, never with glClearBufferData.
//
// On NVIDIA's GL driver (580, H200; session 19) a glClearBufferData followed by the host's
// glBufferSubData could leave the clear's zeros over the written data, in a process that had not
// started NVIDIA's Vulkan driver first: a 6-byte index buffer and the overhead bench's buffers
// drew nothing, every time. BufferTest.IndexBuffersWrittenRightAfterCreationFeedTheirDraws shows
// that on such a driver; Mesa runs the calls in order, so here the calls themselves are checked.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "backend_test.h"
#include "gl_device.h"
#include "gl_entry_points.h"

namespace janus::rhi::test {
namespace {

int g_bufferClears = 0;   // GL entry points are plain functions: the wrapper counts here

void APIENTRY countBufferClear(GLenum, GLenum, GLenum, GLenum, const void*) { ++g_bufferClears; }

class GLBufferCreationTest : public BackendTest {};
JANUS_INSTANTIATE_BACKEND_TESTS(GLBufferCreationTest);

TEST_P(GLBufferCreationTest, NewBuffersGetTheirZerosFromTheHost) {
    if (backend() == Backend::Vulkan) GTEST_SKIP() << "how the GL backend zeroes new buffers";
    gl::GLFunctions& gl = dynamic_cast<gl::Device&>(device()).context().gl;
    GLEntryPointOverrides overrides;
    g_bufferClears = 0;
    // ES 3.0 has no glClearBufferData: the slot is null, and the replacement shows any call too.
    overrides.replace(gl.glClearBufferData, PFNGLCLEARBUFFERDATAPROC(countBufferClear));
    for (BufferUsage usage : {BufferUsage::Index, BufferUsage::Vertex, BufferUsage::Uniform, BufferUsage::Storage}) {
        if (usage == BufferUsage::Storage && !device().capabilities().has(Capability::StorageBuffers)) continue;
        for (uint64_t size : {6u, 24u, 4096u}) {
            BufferHandle buffer = device().createBuffer(BufferDesc().setSize(size).setUsage(usage));
            EXPECT_EQ(readBufferAs<uint8_t>(buffer), std::vector<uint8_t>(size, 0)) << size << " bytes";
        }
    }
    EXPECT_EQ(g_bufferClears, 0) << "glClearBufferData zeroed a new buffer";
}

}  // namespace
}  // namespace janus::rhi::test
