// Finds implicit derivatives a fragment shader may take after a discard.
//
// Implicit-LOD texture lookups (texture(), textureProj(), texture() with a bias) and dFdx/dFdy/
// fwidth take their values from the 2x2 quad of fragments. Once a neighbour has executed OpKill
// (GLSL `discard`) those values are undefined: the SPIR-V and GLSL specifications say so, Mesa
// happens to keep the killed lanes as helpers, and NVIDIA's GL driver does not (issue 10: alpha-
// masked labels sampled mip 0 at their edges, up to 121 steps off Vulkan). Sample before the
// discard, or use textureLod/textureGrad with derivatives taken before it.
//
// The check is conservative: anything reachable in the control-flow graph after a block that
// branches to a discard counts as "after", whether or not the condition could differ within a
// quad, and a function call counts as a discard when the callee (or one it calls) discards.
// Implicit derivatives inside other non-uniform control flow are not detected.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace janus::shaders {

// One message per implicit derivative in `spirv` that may run after a discard, naming what it
// samples (the variable, when the module has names), the function it is in and the discard (or
// call) it follows. Empty for shaders without a fragment entry point. Throws std::invalid_argument
// on a module that is not SPIR-V (bad magic number, truncated instruction).
std::vector<std::string> derivativesAfterDiscard(std::span<const uint32_t> spirv);

}  // namespace janus::shaders
