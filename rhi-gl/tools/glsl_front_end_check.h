// A second, independent GLSL front end for the GLSL the GL backends compile: glslang parses and
// links SPIRV-Cross's output as OpenGL GLSL (not Vulkan), so output one compiler would reject is
// caught at build time rather than by a user's driver (issue 10: NVIDIA rejected output Mesa took).
#pragma once

#include <string>

#include "janus/rhi/rhi.h"

namespace janus::rhi::gl {

// Empty when glslang accepts `source` (with its own #version, GLSL or ESSL) as a complete shader
// of `stage`; otherwise glslang's info log (parse or link).
std::string glslangRejection(const std::string& source, ShaderStage stage);

}  // namespace janus::rhi::gl
