// The workload's two per-operation driver calls answered by stubs that only check and count them:
// glBindBufferRange and glDrawArrays on GL, vkCmdBindDescriptorSets and vkCmdDraw on Vulkan, and
// for Vulkan dispatches vkCmdBindDescriptorSets and vkCmdDispatch. With every per-operation call a
// stub, what is left of an operation's CPU time is the caller's own code (the raw loop, or the
// RHI's recording and replay), on whichever machine this runs, without the driver's time, noise or
// cache footprint. The per-frame calls (framebuffer or render pass, clear, program
// or pipeline, vertex setup, submit) still reach the driver; a frame has 1000 draws, so they add
// little per draw, to both sides alike.
//
// scripts/bench.sh prints RHI minus raw with such a driver (the RHI's own ns per draw) and the
// ratio that alone would give over the real raw draw, next to the measured ratio: on hardware,
// where the measured RHI / raw is noisy, this says how much of it is the RHI's code and how much
// the driver meeting it.
//
// JANUS_BENCH_NULL_FOOTPRINT=BYTES makes each stub also write BYTES to a 4 MiB ring, as a driver
// writes its commands into a push buffer: a driver's cache footprint without its time, to see how
// the RHI's own cost grows when the driver keeps evicting the RHI's data (docs/BENCHMARKS.md,
// "Session 21: the RHI's own cost under a driver's cache footprint"). Both sides write alike.
#pragma once

#include <GL/glcorearb.h>
#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>

#include "bench_common.h"

namespace janus::bench {

// What the stubs saw since the last NullGLDriver or NullVulkanDriver was made.
struct NullDriverCalls {
    uint64_t binds = 0;
    uint64_t ops = 0;          // draws or dispatches
    uint64_t offsetSum = 0;    // GL: of the bound ranges; Vulkan: of the dynamic offsets (each frame binds every slice once)
    uint64_t unexpected = 0;   // a call with arguments the workload never makes
};

// Throws WrongResult unless exactly `frames` frames of the workload's calls arrived: one bind and
// one 3-vertex triangle draw (or one 1x1x1 dispatch) per operation (GL: of each uniform slice,
// binding 0, kSliceBytes). `op`: "draw" or "dispatch", for the message.
void requireNullDriverFrames(uint64_t frames, const std::string& who, bool checkOffsets, const char* op);

// Zeroes what the stubs saw (NullDriver's constructor).
void resetNullDriverCalls();

// Points the two per-operation slots of a function table (the bind, and the draw or dispatch) at
// the stubs, zeroes the counts, and puts the originals back when destroyed.
template <class Bind, class Op>
class NullDriver {
public:
    NullDriver(Bind& bindSlot, Op& opSlot, Bind bindStub, Op opStub, bool checkOffsets, const char* op)
        : m_bindSlot(bindSlot), m_opSlot(opSlot), m_bind(bindSlot), m_op(opSlot), m_checkOffsets(checkOffsets),
          m_opName(op) {
        resetNullDriverCalls();
        m_bindSlot = bindStub;
        m_opSlot = opStub;
    }
    ~NullDriver() {
        m_bindSlot = m_bind;
        m_opSlot = m_op;
    }
    NullDriver(const NullDriver&) = delete;
    NullDriver& operator=(const NullDriver&) = delete;
    void requireFrames(uint64_t frames, const std::string& who) const {
        requireNullDriverFrames(frames, who, m_checkOffsets, m_opName);
    }

private:
    Bind& m_bindSlot;
    Op& m_opSlot;
    Bind m_bind;
    Op m_op;
    bool m_checkOffsets;
    const char* m_opName;
};

using NullGLDriver = NullDriver<PFNGLBINDBUFFERRANGEPROC, PFNGLDRAWARRAYSPROC>;
using NullVulkanDriver = NullDriver<PFN_vkCmdBindDescriptorSets, PFN_vkCmdDraw>;
using NullVulkanDispatchDriver = NullDriver<PFN_vkCmdBindDescriptorSets, PFN_vkCmdDispatch>;
NullGLDriver nullGLDriver(PFNGLBINDBUFFERRANGEPROC& bindBufferRange, PFNGLDRAWARRAYSPROC& drawArrays);
NullVulkanDriver nullVulkanDriver(PFN_vkCmdBindDescriptorSets& bindDescriptorSets, PFN_vkCmdDraw& draw,
                                  DrawSlices slices = DrawSlices::PerDrawSets);
NullVulkanDispatchDriver nullVulkanDispatchDriver(PFN_vkCmdBindDescriptorSets& bindDescriptorSets,
                                                  PFN_vkCmdDispatch& dispatch);

}  // namespace janus::bench
