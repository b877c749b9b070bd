// Shader modules, SPIR-V reflection (SPIRV-Cross), pipeline layouts and pipelines.
#include <fmt/format.h>
#include <spirv_cross/spirv_cross.hpp>

#include <algorithm>
#include <cstring>

#include "janus/rhi/shader_writes.h"
#include "vulkan_backend.h"

namespace janus::rhi::vulkan {
namespace {

VkShaderStageFlagBits toVkStage(ShaderStage stage) {
    switch (stage) {
        case ShaderStage::Vertex: return VK_SHADER_STAGE_VERTEX_BIT;
        case ShaderStage::Fragment: return VK_SHADER_STAGE_FRAGMENT_BIT;
        case ShaderStage::Compute: return VK_SHADER_STAGE_COMPUTE_BIT;
    }
    return VK_SHADER_STAGE_VERTEX_BIT;
}

spv::ExecutionModel toExecutionModel(ShaderStage stage) {
    switch (stage) {
        case ShaderStage::Vertex: return spv::ExecutionModelVertex;
        case ShaderStage::Fragment: return spv::ExecutionModelFragment;
        case ShaderStage::Compute: return spv::ExecutionModelGLCompute;
    }
    return spv::ExecutionModelVertex;
}

VkImageViewType viewTypeOf(const spirv_cross::SPIRType& type) {
    switch (type.image.dim) {
        case spv::Dim3D: return VK_IMAGE_VIEW_TYPE_3D;
        case spv::DimCube: return type.image.arrayed ? VK_IMAGE_VIEW_TYPE_CUBE_ARRAY : VK_IMAGE_VIEW_TYPE_CUBE;
        default: return type.image.arrayed ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
    }
}

// Reads set/binding/type of every resource the shader statically uses. The validation layer has
// checked the module (entry point, binding model) already.
void reflect(const ShaderDesc& desc, VkShaderStageFlagBits stage, std::vector<ReflectedBinding>& bindings) {
    try {
        spirv_cross::Compiler compiler(desc.spirv);
        compiler.set_entry_point(desc.entryPoint, toExecutionModel(desc.stage));
        auto active = compiler.get_active_interface_variables();
        spirv_cross::ShaderResources resources = compiler.get_shader_resources(active);

        auto add = [&](const spirv_cross::Resource& r, VkDescriptorType type) {
            const auto& spirType = compiler.get_type(r.type_id);
            ReflectedBinding b;
            b.set = compiler.get_decoration(r.id, spv::DecorationDescriptorSet);
            b.binding = compiler.get_decoration(r.id, spv::DecorationBinding);
            b.type = type;
            b.count = 1;   // arrays of descriptors are rejected by validation
            b.stages = stage;
            b.viewType = viewTypeOf(spirType);
            b.depthCompare = type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER && spirType.image.depth;
            if (type == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE) b.imageFormat = uint32_t(spirType.image.format);
            if (type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER || type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER)
                b.blockSize = compiler.get_declared_struct_size_runtime_array(compiler.get_type(r.base_type_id), 0);
            if (type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER || type == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE)
                b.written = detail::shaderMayWrite(compiler, r, type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
            b.name = r.name;
            bindings.push_back(b);
        };
        for (const auto& r : resources.uniform_buffers) add(r, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER);
        for (const auto& r : resources.storage_buffers) add(r, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
        for (const auto& r : resources.sampled_images) add(r, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
        for (const auto& r : resources.storage_images) add(r, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
    } catch (const spirv_cross::CompilerError& e) {
        throw Error(ErrorCode::ShaderCompilation,
                    fmt::format("shader '{}' is malformed SPIR-V (SPIRV-Cross cannot parse it: {}); recompile it "
                                "with glslang", desc.debugName, e.what()));
    }
}

VkFormat toVkVertexFormat(VertexFormat f) {
    switch (f) {
        case VertexFormat::Float1: return VK_FORMAT_R32_SFLOAT;
        case VertexFormat::Float2: return VK_FORMAT_R32G32_SFLOAT;
        case VertexFormat::Float3: return VK_FORMAT_R32G32B32_SFLOAT;
        case VertexFormat::Float4: return VK_FORMAT_R32G32B32A32_SFLOAT;
        case VertexFormat::UByte4Norm: return VK_FORMAT_R8G8B8A8_UNORM;
        case VertexFormat::UInt1: return VK_FORMAT_R32_UINT;
    }
    return VK_FORMAT_UNDEFINED;
}

VkPrimitiveTopology toVkTopology(PrimitiveTopology t) {
    switch (t) {
        case PrimitiveTopology::TriangleList: return VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
        case PrimitiveTopology::TriangleStrip: return VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP;
        case PrimitiveTopology::LineList: return VK_PRIMITIVE_TOPOLOGY_LINE_LIST;
        case PrimitiveTopology::PointList: return VK_PRIMITIVE_TOPOLOGY_POINT_LIST;
    }
    return VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
}

VkCullModeFlags toVkCull(CullMode m) {
    switch (m) {
        case CullMode::None: return VK_CULL_MODE_NONE;
        case CullMode::Front: return VK_CULL_MODE_FRONT_BIT;
        case CullMode::Back: return VK_CULL_MODE_BACK_BIT;
    }
    return VK_CULL_MODE_NONE;
}

VkBlendFactor toVkBlendFactor(BlendFactor f) {
    switch (f) {
        case BlendFactor::Zero: return VK_BLEND_FACTOR_ZERO;
        case BlendFactor::One: return VK_BLEND_FACTOR_ONE;
        case BlendFactor::SrcColor: return VK_BLEND_FACTOR_SRC_COLOR;
        case BlendFactor::OneMinusSrcColor: return VK_BLEND_FACTOR_ONE_MINUS_SRC_COLOR;
        case BlendFactor::SrcAlpha: return VK_BLEND_FACTOR_SRC_ALPHA;
        case BlendFactor::OneMinusSrcAlpha: return VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
        case BlendFactor::DstColor: return VK_BLEND_FACTOR_DST_COLOR;
        case BlendFactor::OneMinusDstColor: return VK_BLEND_FACTOR_ONE_MINUS_DST_COLOR;
        case BlendFactor::DstAlpha: return VK_BLEND_FACTOR_DST_ALPHA;
        case BlendFactor::OneMinusDstAlpha: return VK_BLEND_FACTOR_ONE_MINUS_DST_ALPHA;
    }
    return VK_BLEND_FACTOR_ONE;
}

VkBlendOp toVkBlendOp(BlendOp op) {
    switch (op) {
        case BlendOp::Add: return VK_BLEND_OP_ADD;
        case BlendOp::Subtract: return VK_BLEND_OP_SUBTRACT;
        case BlendOp::ReverseSubtract: return VK_BLEND_OP_REVERSE_SUBTRACT;
        case BlendOp::Min: return VK_BLEND_OP_MIN;
        case BlendOp::Max: return VK_BLEND_OP_MAX;
    }
    return VK_BLEND_OP_ADD;
}

const Shader& shaderOf(const ShaderHandle& handle, std::string_view field, const std::string& pipelineName,
                       const Context* owner) {
    return *native<Shader>(handle, fmt::format("pipeline '{}': {}", pipelineName, field), owner);
}

}  // namespace

Shader::Shader(ContextPtr context, const ShaderDesc& desc) : m_context(std::move(context)), m_desc(desc) {
    stage = toVkStage(desc.stage);
    reflect(m_desc, stage, bindings);

    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = desc.spirv.size() * sizeof(uint32_t);
    info.pCode = desc.spirv.data();
    check(vkCreateShaderModule(m_context->device, &info, nullptr, &module), ErrorCode::ShaderCompilation,
          fmt::format("vkCreateShaderModule for '{}'", desc.debugName));
    m_context->setObjectName(VK_OBJECT_TYPE_SHADER_MODULE, uint64_t(module), desc.debugName);
}

Shader::~Shader() { vkDestroyShaderModule(m_context->device, module, nullptr); }

// Merges the shaders' bindings per set (validation made binding numbers unique across sets and
// shared bindings declared alike in every stage).
void Pipeline::createLayout(const std::vector<const Shader*>& shaders, std::span<const DynamicUniformBuffer> dynamic) {
    std::array<std::vector<ReflectedBinding>, kMaxSets> perSet;
    for (const Shader* shader : shaders) {
        for (const ReflectedBinding& b : shader->bindings) {
            bool merged = false;
            for (auto& set : perSet) {
                for (ReflectedBinding& existing : set) {
                    if (existing.binding != b.binding) continue;
                    existing.stages |= b.stages;
                    existing.written = existing.written || b.written;
                    merged = true;
                }
            }
            if (!merged) perSet[b.set].push_back(b);
        }
    }
    std::array<VkDescriptorSetLayout, kMaxSets> layouts{};
    for (uint32_t s = 0; s < kMaxSets; ++s) {
        std::sort(perSet[s].begin(), perSet[s].end(),
                  [](const ReflectedBinding& a, const ReflectedBinding& b) { return a.binding < b.binding; });
        for (ReflectedBinding& b : perSet[s])   // validated: each names a uniform block of set s
            if (declaresDynamic(dynamic, s, b.binding)) b.type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC;
        sets[s] = &m_context->descriptorSetLayout(perSet[s]);
        layouts[s] = sets[s]->layout;
        if (!perSet[s].empty()) usedSets |= 1u << s;
    }
    VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    info.setLayoutCount = kMaxSets;
    info.pSetLayouts = layouts.data();
    check(vkCreatePipelineLayout(m_context->device, &info, nullptr, &layout), ErrorCode::InvalidDescription,
          fmt::format("vkCreatePipelineLayout for '{}'", debugName));
}

Pipeline::Pipeline(ContextPtr context, const GraphicsPipelineDesc& desc)
    : graphicsDesc(desc), debugName(desc.debugName), m_context(std::move(context)) {
    // `desc` is validated (rhi/src/validation.cpp): formats, blend, vertex input and bindings.
    std::vector<const Shader*> shaders{&shaderOf(desc.vertexShader, "vertexShader", debugName, m_context.get()),
                                       &shaderOf(desc.fragmentShader, "fragmentShader", debugName, m_context.get())};
    m_shaders = {desc.vertexShader, desc.fragmentShader};

    std::vector<VkFormat> colorFormats;
    std::vector<VkPipelineColorBlendAttachmentState> blends;
    for (size_t i = 0; i < desc.colorFormats.size(); ++i) {
        const Format format = desc.colorFormats[i];
        const BlendAttachment blend = i < desc.blend.size() ? desc.blend[i] : BlendAttachment{};
        VkPipelineColorBlendAttachmentState state{};
        state.blendEnable = blend.enable;
        state.srcColorBlendFactor = toVkBlendFactor(blend.srcColor);
        state.dstColorBlendFactor = toVkBlendFactor(blend.dstColor);
        state.colorBlendOp = toVkBlendOp(blend.colorOp);
        state.srcAlphaBlendFactor = toVkBlendFactor(blend.srcAlpha);
        state.dstAlphaBlendFactor = toVkBlendFactor(blend.dstAlpha);
        state.alphaBlendOp = toVkBlendOp(blend.alphaOp);
        state.colorWriteMask = blend.writeMask & 0xF;
        colorFormats.push_back(toVkFormat(format));
        blends.push_back(state);
    }

    std::vector<VkVertexInputBindingDescription> vertexBindings;
    for (const auto& vb : desc.vertexBuffers) {
        vertexBindings.push_back(
            {vb.slot, vb.stride, vb.perInstance ? VK_VERTEX_INPUT_RATE_INSTANCE : VK_VERTEX_INPUT_RATE_VERTEX});
    }
    std::vector<VkVertexInputAttributeDescription> attributes;
    for (const auto& a : desc.vertexAttributes)
        attributes.push_back({a.location, a.bufferSlot, toVkVertexFormat(a.format), a.offset});

    createLayout(shaders, desc.dynamicUniformBuffers);

    std::vector<VkPipelineShaderStageCreateInfo> stages;
    for (const Shader* shader : shaders) {
        VkPipelineShaderStageCreateInfo stage{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
        stage.stage = shader->stage;
        stage.module = shader->module;
        stage.pName = shader->desc().entryPoint.c_str();
        stages.push_back(stage);
    }
    VkPipelineVertexInputStateCreateInfo vertexInput{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    vertexInput.vertexBindingDescriptionCount = uint32_t(vertexBindings.size());
    vertexInput.pVertexBindingDescriptions = vertexBindings.data();
    vertexInput.vertexAttributeDescriptionCount = uint32_t(attributes.size());
    vertexInput.pVertexAttributeDescriptions = attributes.data();
    VkPipelineInputAssemblyStateCreateInfo inputAssembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    inputAssembly.topology = toVkTopology(desc.topology);
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = toVkCull(desc.raster.cullMode);
    // rhi.h defines winding as seen with row 0 on top, which is how Vulkan computes facing.
    raster.frontFace = desc.raster.frontFace == FrontFace::CounterClockwise ? VK_FRONT_FACE_COUNTER_CLOCKWISE
                                                                           : VK_FRONT_FACE_CLOCKWISE;
    raster.depthBiasEnable = desc.raster.depthBiasEnable;
    raster.depthBiasConstantFactor = desc.raster.depthBiasConstant;
    raster.depthBiasSlopeFactor = desc.raster.depthBiasSlope;
    raster.lineWidth = 1.0f;
    VkPipelineRasterizationLineStateCreateInfoEXT lineState{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_LINE_STATE_CREATE_INFO_EXT};
    lineState.lineRasterizationMode = VK_LINE_RASTERIZATION_MODE_BRESENHAM_EXT;
    if (desc.topology == PrimitiveTopology::LineList && m_context->bresenhamLines) raster.pNext = &lineState;
    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = VkSampleCountFlagBits(desc.sampleCount);   // validated against the formats
    multisample.alphaToCoverageEnable = desc.alphaToCoverage ? VK_TRUE : VK_FALSE;
    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    const bool hasDepth = desc.depthFormat != Format::Unknown;
    depth.depthTestEnable = desc.depth.testEnable;
    depth.depthWriteEnable = desc.depth.writeEnable;
    depth.depthCompareOp = toVkCompareOp(desc.depth.compare);
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = uint32_t(blends.size());
    blend.pAttachments = blends.data();
    const VkDynamicState dynamicStates[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dynamic.dynamicStateCount = 2;
    dynamic.pDynamicStates = dynamicStates;
    VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    rendering.colorAttachmentCount = uint32_t(colorFormats.size());
    rendering.pColorAttachmentFormats = colorFormats.data();
    rendering.depthAttachmentFormat = hasDepth ? toVkFormat(desc.depthFormat) : VK_FORMAT_UNDEFINED;

    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    info.pNext = &rendering;
    info.stageCount = uint32_t(stages.size());
    info.pStages = stages.data();
    info.pVertexInputState = &vertexInput;
    info.pInputAssemblyState = &inputAssembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = layout;
    VkResult result = vkCreateGraphicsPipelines(m_context->device, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline);
    if (result != VK_SUCCESS) {
        vkDestroyPipelineLayout(m_context->device, layout, nullptr);
        check(result, ErrorCode::ShaderCompilation, fmt::format("vkCreateGraphicsPipelines for '{}'", debugName));
    }
    m_context->setObjectName(VK_OBJECT_TYPE_PIPELINE, uint64_t(pipeline), debugName);
}

Pipeline::Pipeline(ContextPtr context, const ComputePipelineDesc& desc)
    : debugName(desc.debugName), m_context(std::move(context)), m_compute(true) {
    const Shader& shader = shaderOf(desc.computeShader, "computeShader", debugName, m_context.get());
    m_shaders = {desc.computeShader};
    createLayout({&shader}, desc.dynamicUniformBuffers);
    VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = shader.module;
    info.stage.pName = shader.desc().entryPoint.c_str();
    info.layout = layout;
    VkResult result = vkCreateComputePipelines(m_context->device, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline);
    if (result != VK_SUCCESS) {
        vkDestroyPipelineLayout(m_context->device, layout, nullptr);
        check(result, ErrorCode::ShaderCompilation, fmt::format("vkCreateComputePipelines for '{}'", debugName));
    }
    m_context->setObjectName(VK_OBJECT_TYPE_PIPELINE, uint64_t(pipeline), debugName);
}

Pipeline::~Pipeline() {
    vkDestroyPipeline(m_context->device, pipeline, nullptr);
    vkDestroyPipelineLayout(m_context->device, layout, nullptr);
}

}  // namespace janus::rhi::vulkan
