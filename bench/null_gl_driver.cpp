#include "null_gl_driver.h"

#include <fmt/format.h>

#include "bench_common.h"

namespace janus::bench {

namespace {
NullGLCalls g_calls;   // GL entry points are plain functions: the stubs count here

void APIENTRY nullBindBufferRange(GLenum target, GLuint index, GLuint, GLintptr offset, GLsizeiptr size) {
    ++g_calls.binds;
    g_calls.offsetSum += uint64_t(offset);
    if (target != GL_UNIFORM_BUFFER || index != 0 || size != GLsizeiptr(kSliceBytes)) ++g_calls.unexpected;
}

void APIENTRY nullDrawArrays(GLenum mode, GLint first, GLsizei count) {
    ++g_calls.draws;
    if (mode != GL_TRIANGLES || first != 0 || count != 3) ++g_calls.unexpected;
}
}  // namespace

NullGLDriver::NullGLDriver(PFNGLBINDBUFFERRANGEPROC& bindBufferRange, PFNGLDRAWARRAYSPROC& drawArrays)
    : m_bindSlot(bindBufferRange), m_drawSlot(drawArrays), m_bind(bindBufferRange), m_draw(drawArrays) {
    g_calls = {};
    m_bindSlot = nullBindBufferRange;
    m_drawSlot = nullDrawArrays;
}

NullGLDriver::~NullGLDriver() {
    m_bindSlot = m_bind;
    m_drawSlot = m_draw;
}

void NullGLDriver::requireFrames(uint64_t frames, const std::string& who) const {
    const uint64_t calls = frames * kOpsPerFrame;
    // Slice i at offset i * kSliceBytes, once per frame.
    const uint64_t offsets = frames * kSliceBytes * (uint64_t(kOpsPerFrame) * (kOpsPerFrame - 1) / 2);
    if (g_calls.binds != calls || g_calls.draws != calls || g_calls.offsetSum != offsets || g_calls.unexpected != 0)
        throw WrongResult(fmt::format("{} with a null driver: {} frames should bind {} slices and draw {} times (offsets "
                                      "summing to {}); it bound {}, drew {} (offsets summing to {}), {} call(s) with "
                                      "other arguments",
                                      who, frames, calls, calls, offsets, g_calls.binds, g_calls.draws,
                                      g_calls.offsetSum, g_calls.unexpected));
}

}  // namespace janus::bench
