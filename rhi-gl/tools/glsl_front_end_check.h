// A second, independent GLSL front end for the GLSL the GL backends compile: glslang parses and
// links SPIRV-Cross's output as OpenGL GLSL (not Vulkan), so output one compiler would reject is
// caught at build time rather than by a user's driver (issue 10: NVIDIA rejected output Mesa took).
#pragma once

#include <string>

#include "janus/rhi/rhi.h"

namespace janus::rhi::gl {

// The per-stage minimums GL 4.3 and GLES 3.0 both guarantee (GL_MAX_TEXTURE_IMAGE_UNITS and
// GL_MAX_VERTEX_TEXTURE_IMAGE_UNITS: 16; GL_MAX_{VERTEX,FRAGMENT}_UNIFORM_BLOCKS: 12 in GLES 3.0,
// 14 in GL 4.3).
inline constexpr int kMinTextureUnitsPerStage = 16;
inline constexpr int kMinUniformBlocksPerStage = 12;

// Empty when glslang accepts `source` (with its own #version, GLSL or ESSL) as a complete shader
// of `stage` that samples at most kMinTextureUnitsPerStage textures and reads at most
// kMinUniformBlocksPerStage uniform blocks; otherwise glslang's info log (parse or link) or which
// limit it passes.
std::string glslangRejection(const std::string& source, ShaderStage stage);

}  // namespace janus::rhi::gl
