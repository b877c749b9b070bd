#include "probes/probe_update_plan.h"

#include <cmath>
#include <limits>

namespace janus::renderer {

std::vector<ProbeUpdateStep> planProbeUpdate(ProbeTimeSlicing slicing, const std::vector<double>& mipCosts) {
    const uint32_t mips = uint32_t(std::max<size_t>(1, mipCosts.size()));
    if (slicing == ProbeTimeSlicing::None) return {ProbeUpdateStep{kAllCubeFaces, 0, mips, true}};

    // The first mip run ends before `split`: the prefix of mips 1.. whose cost is nearest half.
    double total = 0.0;
    for (uint32_t m = 1; m < mips; ++m) total += mipCosts[m];
    uint32_t split = std::min(2u, mips);
    double best = std::numeric_limits<double>::max(), prefix = 0.0;
    for (uint32_t end = 2; end <= mips; ++end) {
        prefix += mipCosts[end - 1];
        if (const double imbalance = std::abs(total - 2.0 * prefix); imbalance < best) best = imbalance, split = end;
    }
    std::vector<ProbeUpdateStep> steps;
    if (slicing == ProbeTimeSlicing::AllFacesThenMips) {
        steps.push_back(ProbeUpdateStep{kAllCubeFaces, 0, 0, false});
    } else {
        for (uint32_t face = 0; face < 6; ++face) steps.push_back(ProbeUpdateStep{1u << face, 0, 0, false});
    }
    steps.push_back(ProbeUpdateStep{0, 0, split, false});
    steps.push_back(ProbeUpdateStep{0, split, mips, true});
    return steps;
}

}  // namespace janus::renderer
