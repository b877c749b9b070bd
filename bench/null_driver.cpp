#include "null_driver.h"

#include <fmt/format.h>

#include "bench_common.h"

namespace janus::bench {

namespace {
NullDriverCalls g_calls;   // driver entry points are plain functions: the stubs count here

void APIENTRY nullBindBufferRange(GLenum target, GLuint index, GLuint, GLintptr offset, GLsizeiptr size) {
    ++g_calls.binds;
    g_calls.offsetSum += uint64_t(offset);
    if (target != GL_UNIFORM_BUFFER || index != 0 || size != GLsizeiptr(kSliceBytes)) ++g_calls.unexpected;
}

void APIENTRY nullDrawArrays(GLenum mode, GLint first, GLsizei count) {
    ++g_calls.draws;
    if (mode != GL_TRIANGLES || first != 0 || count != 3) ++g_calls.unexpected;
}

VKAPI_ATTR void VKAPI_CALL nullBindDescriptorSets(VkCommandBuffer, VkPipelineBindPoint bindPoint, VkPipelineLayout,
                                                  uint32_t firstSet, uint32_t count, const VkDescriptorSet* sets,
                                                  uint32_t dynamicOffsets, const uint32_t*) {
    ++g_calls.binds;
    if (bindPoint != VK_PIPELINE_BIND_POINT_GRAPHICS || firstSet != 0 || count != 1 || !sets || *sets == VK_NULL_HANDLE ||
        dynamicOffsets != 0)
        ++g_calls.unexpected;
}

VKAPI_ATTR void VKAPI_CALL nullDraw(VkCommandBuffer, uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex,
                                    uint32_t firstInstance) {
    ++g_calls.draws;
    if (vertexCount != 3 || instanceCount != 1 || firstVertex != 0 || firstInstance != 0) ++g_calls.unexpected;
}
}  // namespace

void requireNullDriverFrames(uint64_t frames, const std::string& who, bool checkOffsets) {
    const uint64_t calls = frames * kOpsPerFrame;
    // Slice i at offset i * kSliceBytes, once per frame.
    const uint64_t offsets = checkOffsets ? frames * kSliceBytes * (uint64_t(kOpsPerFrame) * (kOpsPerFrame - 1) / 2) : 0;
    if (g_calls.binds != calls || g_calls.draws != calls || g_calls.offsetSum != offsets || g_calls.unexpected != 0)
        throw WrongResult(fmt::format("{} with a null driver: {} frames should bind {} times and draw {} times (bound "
                                      "offsets summing to {}); it bound {}, drew {} (offsets summing to {}), {} "
                                      "call(s) with other arguments",
                                      who, frames, calls, calls, offsets, g_calls.binds, g_calls.draws,
                                      g_calls.offsetSum, g_calls.unexpected));
}

void resetNullDriverCalls() { g_calls = {}; }

NullGLDriver nullGLDriver(PFNGLBINDBUFFERRANGEPROC& bindBufferRange, PFNGLDRAWARRAYSPROC& drawArrays) {
    return NullGLDriver(bindBufferRange, drawArrays, nullBindBufferRange, nullDrawArrays, true);
}

NullVulkanDriver nullVulkanDriver(PFN_vkCmdBindDescriptorSets& bindDescriptorSets, PFN_vkCmdDraw& draw) {
    return NullVulkanDriver(bindDescriptorSets, draw, nullBindDescriptorSets, nullDraw, false);
}

}  // namespace janus::bench
