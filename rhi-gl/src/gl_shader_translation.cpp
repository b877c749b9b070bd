// SPIR-V -> GLSL 430 / ESSL 300 with SPIRV-Cross: the only GLSL the GL backends compile. Kept free
// of GL so that the build-time shader check (rhi-gl/tools/check_gl_shaders.cpp) translates every
// shader exactly as the backend does.
#include "gl_shader_translation.h"

#include <spirv_cross/spirv_glsl.hpp>

#include <fmt/format.h>

#include "janus/rhi/shader_writes.h"

namespace janus::rhi::gl {

namespace {

spv::ExecutionModel executionModel(ShaderStage stage) {
    switch (stage) {
        case ShaderStage::Vertex: return spv::ExecutionModelVertex;
        case ShaderStage::Fragment: return spv::ExecutionModelFragment;
        case ShaderStage::Compute: return spv::ExecutionModelGLCompute;
    }
    return spv::ExecutionModelVertex;
}

// `invariant gl_Position` in every vertex shader: the renderer's depth prepass and forward pass run
// one vertex shader in two GL programs and the forward pass tests LessOrEqual against the
// prepass's depth, so both must compute the same depth bits. Across GL programs only `invariant`
// promises that (`precise`, which the shaders use, forbids FMA contraction within one program; a
// driver may still compile the stage differently per program). The SPIR-V leaves the decoration
// out because Mesa's SPIR-V reader warns on glslang's Invariant member decoration of gl_PerVertex.
void markPositionInvariant(spirv_cross::CompilerGLSL& compiler, const spirv_cross::ShaderResources& resources) {
    for (const spirv_cross::BuiltInResource& builtin : resources.builtin_outputs) {
        if (builtin.builtin != spv::BuiltInPosition) continue;
        const spirv_cross::SPIRType& type = compiler.get_type(builtin.resource.base_type_id);
        if (type.basetype != spirv_cross::SPIRType::Struct) {
            compiler.set_decoration(builtin.resource.id, spv::DecorationInvariant);
            continue;
        }
        for (uint32_t member = 0; member < uint32_t(type.member_types.size()); ++member)
            if (compiler.has_member_decoration(type.self, member, spv::DecorationBuiltIn) &&
                compiler.get_member_decoration(type.self, member, spv::DecorationBuiltIn) == spv::BuiltInPosition)
                compiler.set_member_decoration(type.self, member, spv::DecorationInvariant);
    }
}

}  // namespace

GlslTranslation translateToGlsl(const ShaderDesc& desc, const GlslTarget& target) {
    const bool es = target.es;
    spirv_cross::CompilerGLSL compiler(desc.spirv);
    // The validation layer has checked the entry point and the binding model (combined image
    // samplers, no push constants).
    compiler.set_entry_point(desc.entryPoint, executionModel(desc.stage));
    const spirv_cross::ShaderResources resources = compiler.get_shader_resources();

    GlslTranslation result;
    auto flatten = [&](const spirv_cross::Resource& resource, ResourceType type) {
        const uint32_t binding = compiler.get_decoration(resource.id, spv::DecorationBinding);
        const uint32_t set = compiler.get_decoration(resource.id, spv::DecorationDescriptorSet);
        // Sets are flattened: the binding number alone is the GL binding point.
        compiler.unset_decoration(resource.id, spv::DecorationDescriptorSet);
        std::string glName;
        switch (type) {
            case ResourceType::UniformBuffer:
                glName = fmt::format("JanusUniforms{}", binding);
                compiler.set_name(resource.base_type_id, glName);
                break;
            case ResourceType::StorageBuffer:
                glName = fmt::format("JanusStorage{}", binding);
                compiler.set_name(resource.base_type_id, glName);
                break;
            case ResourceType::SampledTexture:
                glName = fmt::format("janus_texture{}", binding);
                compiler.set_name(resource.id, glName);
                break;
            case ResourceType::StorageImage:
                glName = fmt::format("janus_image{}", binding);
                compiler.set_name(resource.id, glName);
                break;
        }
        std::optional<TextureDimension> dimension;
        bool depthCompare = false;
        uint32_t imageFormat = 0;
        if (type == ResourceType::SampledTexture || type == ResourceType::StorageImage) {
            const auto& image = compiler.get_type(resource.type_id).image;
            depthCompare = type == ResourceType::SampledTexture && image.depth;
            if (type == ResourceType::StorageImage) imageFormat = uint32_t(image.format);
            switch (image.dim) {
                case spv::Dim3D: dimension = TextureDimension::Texture3D; break;
                case spv::DimCube:
                    dimension = image.arrayed ? TextureDimension::TextureCubeArray : TextureDimension::TextureCube;
                    break;
                default:
                    dimension = image.arrayed ? TextureDimension::Texture2DArray : TextureDimension::Texture2D;
                    break;
            }
        }
        uint64_t blockSize = 0;
        if (type == ResourceType::UniformBuffer || type == ResourceType::StorageBuffer)
            blockSize = compiler.get_declared_struct_size_runtime_array(compiler.get_type(resource.base_type_id), 0);
        const bool written = (type == ResourceType::StorageBuffer || type == ResourceType::StorageImage) &&
                             detail::shaderMayWrite(compiler, resource, type == ResourceType::StorageBuffer);
        result.bindings.push_back({type, set, binding, glName, dimension, depthCompare, imageFormat, blockSize, written});
    };
    for (const auto& r : resources.uniform_buffers) flatten(r, ResourceType::UniformBuffer);
    for (const auto& r : resources.storage_buffers) flatten(r, ResourceType::StorageBuffer);
    for (const auto& r : resources.sampled_images) flatten(r, ResourceType::SampledTexture);
    for (const auto& r : resources.storage_images) flatten(r, ResourceType::StorageImage);

    auto renameByLocation = [&](const spirv_cross::SmallVector<spirv_cross::Resource>& variables, const char* prefix) {
        for (const auto& r : variables) {
            if (!compiler.has_decoration(r.id, spv::DecorationLocation)) continue;
            compiler.set_name(r.id, fmt::format("{}{}", prefix, compiler.get_decoration(r.id, spv::DecorationLocation)));
        }
    };
    if (desc.stage == ShaderStage::Vertex) {
        for (const auto& r : resources.stage_inputs) {
            const auto baseType = compiler.get_type(r.base_type_id).basetype;
            const bool integer = baseType == spirv_cross::SPIRType::Int || baseType == spirv_cross::SPIRType::UInt;
            result.inputs.push_back({compiler.get_decoration(r.id, spv::DecorationLocation), integer});
        }
        renameByLocation(resources.stage_inputs, "janus_attribute");
        renameByLocation(resources.stage_outputs, "janus_varying");
    } else if (desc.stage == ShaderStage::Fragment) {
        renameByLocation(resources.stage_inputs, "janus_varying");
        renameByLocation(resources.stage_outputs, "janus_color");
    }

    if (desc.stage == ShaderStage::Vertex) markPositionInvariant(compiler, resources);

    spirv_cross::CompilerGLSL::Options options = compiler.get_common_options();
    options.version = es ? 300 : 430;
    options.es = es;
    options.vulkan_semantics = false;
    // Our clip depth is [0, 1] (Vulkan's): with clip control GL takes it as it is, without it GL's
    // is [-1, 1] and z is rewritten here. Rows need no flip (see Conventions); the lower-left
    // origin is also what gives Vulkan's fill rule on Mesa (see rhi-gl/README.md).
    options.vertex.fixup_clipspace = !target.zeroToOneClipDepth;
    options.vertex.flip_vert_y = false;
    // ES defaults fragment floats to mediump; every backend must compute in full precision to agree.
    options.fragment.default_float_precision = spirv_cross::CompilerGLSL::Options::Highp;
    options.fragment.default_int_precision = spirv_cross::CompilerGLSL::Options::Highp;
    compiler.set_common_options(options);
    result.source = compiler.compile();
    return result;
}

}  // namespace janus::rhi::gl
