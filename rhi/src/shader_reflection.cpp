#include "shader_reflection.h"

#include <fmt/format.h>
#include <spirv_cross/spirv_cross.hpp>

#include <algorithm>

#include "janus/rhi/spirv_validation.h"

namespace janus::rhi::detail {
namespace {

constexpr uint32_t kSpirvMagic = 0x07230203u;

spv::ExecutionModel executionModel(ShaderStage stage) {
    switch (stage) {
        case ShaderStage::Vertex: return spv::ExecutionModelVertex;
        case ShaderStage::Fragment: return spv::ExecutionModelFragment;
        case ShaderStage::Compute: return spv::ExecutionModelGLCompute;
    }
    return spv::ExecutionModelVertex;
}

std::string label(const ShaderDesc& desc) {
    return desc.debugName.empty() ? fmt::format("ShaderDesc ({} shader)", toString(desc.stage))
                                  : fmt::format("ShaderDesc '{}' ({} shader)", desc.debugName, toString(desc.stage));
}

[[noreturn]] void invalid(const ShaderDesc& desc, const std::string& problem) {
    throw Error(ErrorCode::InvalidDescription, fmt::format("{}: {}", label(desc), problem));
}

}  // namespace

void checkSpirvModule(const ShaderDesc& desc) {
    if (desc.spirv.empty()) invalid(desc, "spirv is empty; pass SPIR-V words (janus::shaders::get)");
    if (desc.spirv[0] != kSpirvMagic)
        invalid(desc, fmt::format("spirv is not SPIR-V (magic number 0x{:08x}, not 0x{:08x}); pass SPIR-V words "
                                  "(janus::shaders::get)", desc.spirv[0], kSpirvMagic));
    if (const std::string problem = spirvModuleProblem(desc.spirv); !problem.empty())
        invalid(desc, fmt::format("spirv is not a valid SPIR-V module: {}; compile the shader again "
                                  "(glslangValidator -V) and pass all its words", problem));
}

ShaderReflection reflectShader(const ShaderDesc& desc) {
    ShaderReflection result;
    try {
        spirv_cross::Compiler compiler(desc.spirv);
        const auto entryPoints = compiler.get_entry_points_and_stages();
        const bool found = std::any_of(entryPoints.begin(), entryPoints.end(), [&](const spirv_cross::EntryPoint& e) {
            return e.name == desc.entryPoint && e.execution_model == executionModel(desc.stage);
        });
        if (!found)
            invalid(desc, fmt::format("the module has no {} entry point named '{}'; check stage and entryPoint",
                                      toString(desc.stage), desc.entryPoint));
        compiler.set_entry_point(desc.entryPoint, executionModel(desc.stage));
        const spirv_cross::ShaderResources resources =
            compiler.get_shader_resources(compiler.get_active_interface_variables());

        if (!resources.separate_images.empty() || !resources.separate_samplers.empty())
            invalid(desc, fmt::format("'{}' is a separate texture/sampler; the Janus binding model takes combined "
                                      "image samplers (sampler2D, ...), so declare those instead",
                                      resources.separate_images.empty() ? resources.separate_samplers[0].name
                                                                        : resources.separate_images[0].name));
        if (!resources.push_constant_buffers.empty())
            invalid(desc, "the shader uses push constants, which the Janus RHI does not have; use a uniform buffer");

        auto add = [&](const spirv_cross::Resource& r, ResourceType type) {
            const spirv_cross::SPIRType& spirType = compiler.get_type(r.type_id);
            ReflectedResource resource;
            resource.set = compiler.get_decoration(r.id, spv::DecorationDescriptorSet);
            resource.binding = compiler.get_decoration(r.id, spv::DecorationBinding);
            resource.type = type;
            resource.name = r.name;
            if (!spirType.array.empty())
                invalid(desc, fmt::format("'{}' is an array of resources; a BindingItem binds one resource per "
                                          "binding, so declare one binding each", r.name));
            if (resource.set >= kMaxBindingSets)
                invalid(desc, fmt::format("'{}' uses set {}; sets 0..{} are available", r.name, resource.set,
                                          kMaxBindingSets - 1));
            if (type == ResourceType::SampledTexture || type == ResourceType::StorageImage) {
                // sampler2D / image2D, sampler2DArray / image2DArray, samplerCube / imageCube,
                // samplerCubeArray / imageCubeArray, sampler3D / image3D.
                const bool arrayed = spirType.image.arrayed;
                switch (spirType.image.dim) {
                    case spv::Dim3D: resource.dimension = TextureDimension::Texture3D; break;
                    case spv::DimCube:
                        resource.dimension = arrayed ? TextureDimension::TextureCubeArray : TextureDimension::TextureCube;
                        break;
                    default:
                        resource.dimension = arrayed ? TextureDimension::Texture2DArray : TextureDimension::Texture2D;
                        break;
                }
            }
            result.resources.push_back(std::move(resource));
        };
        for (const auto& r : resources.uniform_buffers) add(r, ResourceType::UniformBuffer);
        for (const auto& r : resources.storage_buffers) add(r, ResourceType::StorageBuffer);
        for (const auto& r : resources.sampled_images) add(r, ResourceType::SampledTexture);
        for (const auto& r : resources.storage_images) add(r, ResourceType::StorageImage);
        if (desc.stage == ShaderStage::Fragment) {
            for (const auto& r : resources.stage_outputs)
                if (compiler.has_decoration(r.id, spv::DecorationLocation) && compiler.get_decoration(r.id, spv::DecorationLocation) == 0 &&
                    compiler.get_type(r.type_id).vecsize == 4)
                    result.writesAlphaAtLocation0 = true;
        }
        if (desc.stage == ShaderStage::Vertex) {
            for (const auto& r : resources.stage_inputs) {
                if (!compiler.has_decoration(r.id, spv::DecorationLocation)) continue;   // built-ins
                const auto baseType = compiler.get_type(r.base_type_id).basetype;
                result.inputs.push_back({compiler.get_decoration(r.id, spv::DecorationLocation),
                                         baseType == spirv_cross::SPIRType::Int || baseType == spirv_cross::SPIRType::UInt});
            }
        }
    } catch (const spirv_cross::CompilerError& e) {
        invalid(desc, fmt::format("spirv is malformed (SPIRV-Cross cannot parse it: {}); recompile it with glslang",
                                  e.what()));
    }
    return result;
}

}  // namespace janus::rhi::detail
