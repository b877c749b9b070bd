// What a SPIR-V shader declares, read with SPIRV-Cross for the validation layer (validation.cpp):
// the resources it binds and the vertex inputs it reads. Backend-independent.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "janus/rhi/rhi.h"

namespace janus::rhi::detail {

struct ReflectedResource {
    uint32_t set = 0;
    uint32_t binding = 0;
    ResourceType type = ResourceType::UniformBuffer;
    std::optional<TextureDimension> dimension;   // textures and images
    std::string name;
};

struct ReflectedInput {
    uint32_t location = 0;
    bool integer = false;   // int/uint: needs an integer attribute format (and vice versa)
};

struct ShaderReflection {
    std::vector<ReflectedResource> resources;   // statically used by the entry point
    std::vector<ReflectedInput> inputs;         // vertex shaders only
    bool writesAlphaAtLocation0 = false;        // fragment shaders: a 4-component output at location 0
};

// Whether `desc.spirv` is a SPIR-V module SPIRV-Cross may parse: words, the magic number, and
// SPIRV-Tools' validator (SPIRV-Cross assumes a valid module; a damaged one could crash it). Once
// per module, at createShader: pipelines reflect shaders that passed it. Throws
// Error(InvalidDescription) naming the shader and the problem.
void checkSpirvModule(const ShaderDesc& desc);

// Parses `desc.spirv` (which checkSpirvModule accepted) and checks what the Janus binding model
// cannot express. Throws Error(InvalidDescription) naming the shader and what to change.
ShaderReflection reflectShader(const ShaderDesc& desc);

}  // namespace janus::rhi::detail
