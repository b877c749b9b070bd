// How one reflection-probe update is spread over frames (internal to the renderer;
// docs/PROBES.md, "Time slicing"). Pure CPU: the plan is a list of frame steps, each capturing
// some faces and/or prefiltering some mips; the last step also shows the result.
#pragma once

#include <cstdint>
#include <vector>

#include "janus/renderer/scene.h"

namespace janus::renderer {

inline constexpr uint32_t kAllCubeFaces = 0x3f;

struct ProbeUpdateStep {
    uint32_t captureFaces = 0;   // bit f: render cube face f (RHI order +X, -X, +Y, -Y, +Z, -Z)
    // Prefiltered mips [firstMip, endMip); firstMip 0 also builds the capture's mip chain and
    // copies mip 0 (the mirror). firstMip == endMip: no prefilter work.
    uint32_t firstMip = 0, endMip = 0;
    bool show = false;           // copy the finished update where shading reads it
    bool operator==(const ProbeUpdateStep&) const = default;
};

// The steps of one update: None -> 1 frame; AllFacesThenMips -> 3 (faces; mips 0..k-1; mips
// k..N-1 and show); IndividualFaces -> 8 (faces one by one; then the same two mip steps).
// `mipCosts[m]` is the prefilter's work for mip m (GgxPrefilter::mipCost; mip 0 costs nothing):
// k splits mips 1..N-1 into two runs of nearly equal cost. `mipCosts.size()` is N >= 1.
std::vector<ProbeUpdateStep> planProbeUpdate(ProbeTimeSlicing slicing, const std::vector<double>& mipCosts);

}  // namespace janus::renderer
