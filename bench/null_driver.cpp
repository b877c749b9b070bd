#include "null_driver.h"

#include <fmt/format.h>

#include <charconv>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "bench_common.h"

namespace janus::bench {

namespace {
NullDriverCalls g_calls;   // driver entry points are plain functions: the stubs count here

// JANUS_BENCH_NULL_FOOTPRINT: what each stub writes, and where (a ring larger than the caches).
struct PushBuffer {
    std::vector<std::byte> ring;
    size_t bytesPerCall = 0;
    size_t cursor = 0;
};
PushBuffer g_push;
constexpr size_t kRingBytes = size_t(4) << 20;

size_t footprintPerCall() {
    const char* footprint = std::getenv("JANUS_BENCH_NULL_FOOTPRINT");
    if (!footprint || !*footprint) return 0;
    size_t bytes = 0;
    const char* end = footprint + std::strlen(footprint);
    if (auto [at, error] = std::from_chars(footprint, end, bytes); error != std::errc() || at != end)
        throw WrongResult(fmt::format("JANUS_BENCH_NULL_FOOTPRINT='{}' is not a number of bytes", footprint));
    if (bytes > kRingBytes)
        throw WrongResult(fmt::format("JANUS_BENCH_NULL_FOOTPRINT={} is more than the {}-byte ring", footprint, kRingBytes));
    return bytes;
}

// Only in the stubs made for a footprint (Footprint below), so the plain ones stay as cheap as
// before it existed.
void writeFootprint() {
    if (g_push.cursor + g_push.bytesPerCall > g_push.ring.size()) g_push.cursor = 0;
    std::memset(g_push.ring.data() + g_push.cursor, int(g_calls.binds & 0xFF), g_push.bytesPerCall);
    g_push.cursor += g_push.bytesPerCall;
}

template <bool Footprint>
void APIENTRY nullBindBufferRange(GLenum target, GLuint index, GLuint, GLintptr offset, GLsizeiptr size) {
    ++g_calls.binds;
    if constexpr (Footprint) writeFootprint();
    g_calls.offsetSum += uint64_t(offset);
    if (target != GL_UNIFORM_BUFFER || index != 0 || size != GLsizeiptr(kSliceBytes)) ++g_calls.unexpected;
}

template <bool Footprint>
void APIENTRY nullDrawArrays(GLenum mode, GLint first, GLsizei count) {
    ++g_calls.ops;
    if constexpr (Footprint) writeFootprint();
    if (mode != GL_TRIANGLES || first != 0 || count != 3) ++g_calls.unexpected;
}

template <bool Footprint, VkPipelineBindPoint Expected>
VKAPI_ATTR void VKAPI_CALL nullBindDescriptorSets(VkCommandBuffer, VkPipelineBindPoint bindPoint, VkPipelineLayout,
                                                  uint32_t firstSet, uint32_t count, const VkDescriptorSet* sets,
                                                  uint32_t dynamicOffsets, const uint32_t* offsets) {
    ++g_calls.binds;
    if constexpr (Footprint) writeFootprint();
    if (bindPoint != Expected || firstSet != 0 || count != 1 || !sets || *sets == VK_NULL_HANDLE ||
        dynamicOffsets > 1)
        ++g_calls.unexpected;
    if (dynamicOffsets == 1) g_calls.offsetSum += *offsets;   // DrawSlices::DynamicOffsets: the slice's
}

template <bool Footprint>
VKAPI_ATTR void VKAPI_CALL nullDraw(VkCommandBuffer, uint32_t vertexCount, uint32_t instanceCount, uint32_t firstVertex,
                                    uint32_t firstInstance) {
    ++g_calls.ops;
    if constexpr (Footprint) writeFootprint();
    if (vertexCount != 3 || instanceCount != 1 || firstVertex != 0 || firstInstance != 0) ++g_calls.unexpected;
}

template <bool Footprint>
VKAPI_ATTR void VKAPI_CALL nullDispatch(VkCommandBuffer, uint32_t groupsX, uint32_t groupsY, uint32_t groupsZ) {
    ++g_calls.ops;
    if constexpr (Footprint) writeFootprint();
    if (groupsX != 1 || groupsY != 1 || groupsZ != 1) ++g_calls.unexpected;
}
}  // namespace

void requireNullDriverFrames(uint64_t frames, const std::string& who, bool checkOffsets, const char* op) {
    const uint64_t ops = opsPerFrame();
    const uint64_t calls = frames * ops;
    // Slice i at offset i * kSliceBytes, once per frame.
    const uint64_t offsets = checkOffsets ? frames * kSliceBytes * (ops * (ops - 1) / 2) : 0;
    if (g_calls.binds != calls || g_calls.ops != calls || g_calls.offsetSum != offsets || g_calls.unexpected != 0)
        throw WrongResult(fmt::format("{} with a null driver: {} frames should bind {} times and {} {} times (bound "
                                      "offsets summing to {}); it bound {}, made {} {} call(s) (offsets summing to "
                                      "{}), {} call(s) with other arguments",
                                      who, frames, calls, op, calls, offsets, g_calls.binds, g_calls.ops, op,
                                      g_calls.offsetSum, g_calls.unexpected));
}

void resetNullDriverCalls() {
    g_calls = {};
    g_push.bytesPerCall = footprintPerCall();
    if (g_push.bytesPerCall != 0 && g_push.ring.empty()) g_push.ring.assign(kRingBytes, std::byte{0});
    g_push.cursor = 0;
}

NullGLDriver nullGLDriver(PFNGLBINDBUFFERRANGEPROC& bindBufferRange, PFNGLDRAWARRAYSPROC& drawArrays) {
    if (footprintPerCall() != 0)
        return NullGLDriver(bindBufferRange, drawArrays, nullBindBufferRange<true>, nullDrawArrays<true>, true, "draw");
    return NullGLDriver(bindBufferRange, drawArrays, nullBindBufferRange<false>, nullDrawArrays<false>, true, "draw");
}

NullVulkanDriver nullVulkanDriver(PFN_vkCmdBindDescriptorSets& bindDescriptorSets, PFN_vkCmdDraw& draw,
                                  DrawSlices slices) {
    constexpr VkPipelineBindPoint kGraphics = VK_PIPELINE_BIND_POINT_GRAPHICS;
    // Dynamic offsets: each frame must pass every slice's offset once; a set per draw: none.
    const bool offsets = slices == DrawSlices::DynamicOffsets;
    if (footprintPerCall() != 0)
        return NullVulkanDriver(bindDescriptorSets, draw, nullBindDescriptorSets<true, kGraphics>, nullDraw<true>,
                                offsets, "draw");
    return NullVulkanDriver(bindDescriptorSets, draw, nullBindDescriptorSets<false, kGraphics>, nullDraw<false>,
                            offsets, "draw");
}

NullVulkanDispatchDriver nullVulkanDispatchDriver(PFN_vkCmdBindDescriptorSets& bindDescriptorSets,
                                                  PFN_vkCmdDispatch& dispatch) {
    constexpr VkPipelineBindPoint kCompute = VK_PIPELINE_BIND_POINT_COMPUTE;
    if (footprintPerCall() != 0)
        return NullVulkanDispatchDriver(bindDescriptorSets, dispatch, nullBindDescriptorSets<true, kCompute>,
                                        nullDispatch<true>, false, "dispatch");
    return NullVulkanDispatchDriver(bindDescriptorSets, dispatch, nullBindDescriptorSets<false, kCompute>,
                                    nullDispatch<false>, false, "dispatch");
}

}  // namespace janus::bench
