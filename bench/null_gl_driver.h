// The draw workload's two per-draw GL calls, glBindBufferRange and glDrawArrays, answered by stubs
// that only check and count them: with every per-draw call a stub, what is left of a draw's CPU
// time is the caller's own code (the raw loop, or the RHI's recording and replay), on whichever
// machine this runs, without the driver's noise or its cache footprint. The per-frame calls
// (framebuffer, clear, program, vertex setup) still reach the driver; a frame has 1000 draws, so
// they add little per draw, to both sides alike.
//
// scripts/bench.sh prints RHI minus raw with such a driver (the RHI's own ns per draw) and what
// ratio that would give over the real raw draw, next to the measured ratio: on hardware, where
// the measured RHI / raw is noisy, this says how much of it is the RHI's code and how much is
// the driver reacting to it.
#pragma once

#include <GL/glcorearb.h>

#include <cstdint>
#include <string>

namespace janus::bench {

struct NullGLCalls {
    uint64_t binds = 0;
    uint64_t draws = 0;
    uint64_t offsetSum = 0;   // of the binds: each frame binds every slice once
    uint64_t unexpected = 0;   // a call with arguments the workload never makes
};

// Points `bindBufferRange` and `drawArrays` (slots of a GL function table) at the stubs, zeroes
// the counts, and puts the originals back when destroyed.
class NullGLDriver {
public:
    NullGLDriver(PFNGLBINDBUFFERRANGEPROC& bindBufferRange, PFNGLDRAWARRAYSPROC& drawArrays);
    ~NullGLDriver();
    NullGLDriver(const NullGLDriver&) = delete;
    NullGLDriver& operator=(const NullGLDriver&) = delete;

    // Throws WrongResult unless exactly `frames` frames of the workload's calls arrived: one bind
    // of each uniform slice (binding 0, kSliceBytes) and one 3-vertex triangle list per draw.
    void requireFrames(uint64_t frames, const std::string& who) const;

private:
    PFNGLBINDBUFFERRANGEPROC& m_bindSlot;
    PFNGLDRAWARRAYSPROC& m_drawSlot;
    PFNGLBINDBUFFERRANGEPROC m_bind;
    PFNGLDRAWARRAYSPROC m_draw;
};

}  // namespace janus::bench
