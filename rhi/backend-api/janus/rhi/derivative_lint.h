// Finds implicit derivatives a fragment shader takes where the quad's other fragments may not be.
//
// Implicit-LOD texture lookups (texture(), textureProj(), texture() with a bias), textureQueryLod
// and dFdx/dFdy/fwidth take their values from the 2x2 quad of fragments. They are undefined where
// a neighbour is missing: after it executed OpKill (GLSL `discard`), and in control flow that
// depends on a value that differs within the quad (a branch on a texture coordinate, a loop whose
// trip count comes from one). The SPIR-V and GLSL specifications say so; Mesa happens to keep the
// missing lanes running, NVIDIA's GL driver does not (issue 10: alpha-masked labels sampled mip 0
// at their edges, up to 121 steps off Vulkan). Sample first, or use textureLod/textureGrad with
// derivatives taken in uniform control flow.
//
// With validation on, IDevice::createShader reports each finding of a fragment shader as a Warning
// debug message (the same on every backend); tests hold our own shaders to none.
//
// Both checks are conservative. After a discard: anything reachable in the control-flow graph
// after a block that branches to a discard counts, whether or not the condition could differ
// within a quad, and a call counts as a discard when the callee (or one it calls) discards.
// Divergence: a value varies when it depends on an input that is not flat or per-primitive, or on
// a variable stored to in divergent flow, and through calls as summarised per function (a
// parameter varies when any call passes a varying argument; a call's result when the function
// may return a varying value); a branch on a varying value makes what it leads to divergent until
// its merge, the rest of the loop too after a break or continue, and the rest of the function
// after a return (after a discard: the first check).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace janus::rhi {

// One message per implicit derivative in `spirv` that may run after a discard, naming what it
// samples (the variable, when the module has names), its source line (when the module has debug
// info: glslangValidator -g), the function it is in and the discard (or call) it follows. Empty
// for shaders without a fragment entry point. Throws std::invalid_argument on a module that is not
// SPIR-V (bad magic number, truncated instruction).
std::vector<std::string> derivativesAfterDiscard(std::span<const uint32_t> spirv);

// One message per implicit derivative in divergent control flow (see above), naming what it
// samples and the function it is in. Empty and throws as derivativesAfterDiscard.
std::vector<std::string> derivativesInDivergentFlow(std::span<const uint32_t> spirv);

// Both of the above.
std::vector<std::string> derivativeHazards(std::span<const uint32_t> spirv);

}  // namespace janus::rhi
