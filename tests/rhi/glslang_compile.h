// GLSL 450 -> SPIR-V for Vulkan 1.2 at test time, as the build's glslangValidator -V makes it (no
// optimisation, no inlining: calls stay calls), for tests that need shaders no list embeds.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "janus/rhi/rhi.h"

namespace janus::rhi::test {

// Throws std::runtime_error with glslang's log (and the source) when it does not compile. With a
// `debugFileName`, the module carries debug info (glslangValidator -g): OpString and OpLine.
std::vector<uint32_t> compileGlsl(const std::string& source, ShaderStage stage, const std::string& debugFileName = {});

}  // namespace janus::rhi::test
