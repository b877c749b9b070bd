// SPIR-V from a user is checked by SPIRV-Tools' validator before anything parses it: SPIRV-Cross
// (reflection, the GL translation) assumes a valid module and crashed on damaged ones (session 28:
// most of 300 randomly damaged modules that kept their magic number ended in a segfault). So a
// damaged module is an error that names the problem, never a crash. It costs about 1.2 ms per
// shader here (Janus's 94 embedded shaders: 111 ms), once per createShader (not again when a
// pipeline reflects its shaders), at start-up, beside the driver's own compile of the same module.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace janus::rhi {

// Empty when `spirv` is a valid SPIR-V module (universal SPIR-V 1.6 rules, which accept every
// version a Vulkan or GL target uses); otherwise the validator's first message.
std::string spirvModuleProblem(std::span<const uint32_t> spirv);

}  // namespace janus::rhi
