// SPIR-V -> the GLSL a GL context compiles (SPIRV-Cross), without GL: the GL backend's shaders and
// the build-time check of every shader's GLSL/ESSL output (rhi-gl/tools/check_gl_shaders.cpp)
// share it, so what the check parses is what a driver would be given.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "janus/rhi/rhi.h"

namespace janus::rhi::gl {

// What one shader uses at which binding point (from SPIRV-Cross reflection).
struct ShaderBinding {
    ResourceType type;
    uint32_t set;
    uint32_t binding;
    std::string glName;   // block name (buffers) or uniform name (textures, images)
    std::optional<TextureDimension> dimension;   // textures and images
    bool depthCompare = false;   // a shadow sampler (sampler2DShadow and kin)
    uint32_t imageFormat = 0;    // storage images: the format qualifier (SPIR-V ImageFormat, 0: none)
    uint64_t blockSize = 0;      // buffers: the block's bytes (storage: before a runtime array)
    // Storage buffers and images: the shader may write it (no `readonly`, SPIR-V NonWritable).
    // Hazard tracking notes a write only for these, as the Vulkan backend does.
    bool written = false;
    // Uniform buffers: the pipeline reads it with a dynamic offset (its DynamicUniformBuffer list).
    // Set by the pipeline, not the shader.
    bool dynamicOffset = false;
};

// A vertex shader input (from reflection), to check the pipeline's vertex attributes against.
struct ShaderInput {
    uint32_t location;
    bool integer;   // int/uint: needs an integer attribute format (and vice versa)
};

// The GLSL dialect a context takes: ESSL 300 or GLSL 430, and whether clip depth is already
// [0, 1] (clip control) or vertex shaders must rewrite z to GL's [-1, 1].
struct GlslTarget {
    bool es = false;
    bool zeroToOneClipDepth = true;
};

struct GlslTranslation {
    std::string source;
    std::vector<ShaderBinding> bindings;
    std::vector<ShaderInput> inputs;
};

// Names every resource after its binding and every stage variable after its location, so that
// (a) the program's resources can be found by name to assign binding points on ES 3.0, which has
// no `binding` layout, and (b) vertex outputs match fragment inputs whatever the sources called
// them. Throws spirv_cross::CompilerError when SPIRV-Cross cannot express the shader.
GlslTranslation translateToGlsl(const ShaderDesc& desc, const GlslTarget& target);

}  // namespace janus::rhi::gl
