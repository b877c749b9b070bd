// Shaders (SPIR-V -> GLSL 430 / ESSL 300 with SPIRV-Cross) and pipelines (linked programs plus
// the fixed-function state they apply).
#include <spirv_cross/spirv_cross.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <optional>
#include <regex>
#include <sstream>

#include "gl_device.h"

namespace janus::rhi::gl {

namespace {

GLenum shaderType(ShaderStage stage) {
    switch (stage) {
        case ShaderStage::Vertex: return GL_VERTEX_SHADER;
        case ShaderStage::Fragment: return GL_FRAGMENT_SHADER;
        case ShaderStage::Compute: return GL_COMPUTE_SHADER;
    }
    return GL_VERTEX_SHADER;
}

std::string shaderLabel(const ShaderDesc& desc) {
    return desc.debugName.empty() ? fmt::format("{} shader", toString(desc.stage))
                                  : fmt::format("{} shader '{}'", toString(desc.stage), desc.debugName);
}

}  // namespace

std::string describeCompileFailure(const std::string& log, const std::string& source) {
    std::string message = log;
    // Mesa reports "0:LINE(COLUMN): error: ..."; quote that line of the translated source.
    std::smatch match;
    static const std::regex kLocation(R"((\d+):(\d+)\((\d+)\))");
    if (std::regex_search(log, match, kLocation)) {
        const int lineNumber = std::stoi(match[2].str());
        std::istringstream lines(source);
        std::string line;
        for (int i = 1; std::getline(lines, line); ++i) {
            if (i == lineNumber) {
                message += fmt::format("\nat line {} of the translated source: {}", lineNumber, line);
                break;
            }
        }
    }
    return message;
}

Shader::Shader(ContextPtr context, const ShaderDesc& desc) : m_context(std::move(context)), m_desc(desc) {
    const std::string label = shaderLabel(desc);
    GlslTranslation translation;
    try {
        translation = translateToGlsl(desc, GlslTarget{m_context->isES(), m_context->zeroToOneClipDepth});
    } catch (const spirv_cross::CompilerError& e) {
        throw Error(ErrorCode::ShaderTranslation,
                    fmt::format("SPIRV-Cross cannot express {} in {}: {}", label,
                                m_context->isES() ? "ESSL 300" : "GLSL 430", e.what()));
    }
    m_source = std::move(translation.source);
    m_bindings = std::move(translation.bindings);
    m_inputs = std::move(translation.inputs);

    const GLFunctions& gl = m_context->gl;
    m_name = gl.glCreateShader(shaderType(desc.stage));
    const char* text = m_source.c_str();
    gl.glShaderSource(m_name, 1, &text, nullptr);
    gl.glCompileShader(m_name);
    GLint compiled = GL_FALSE;
    gl.glGetShaderiv(m_name, GL_COMPILE_STATUS, &compiled);
    if (!compiled) {
        GLint length = 0;
        gl.glGetShaderiv(m_name, GL_INFO_LOG_LENGTH, &length);
        std::string log(size_t(std::max(length, 1)), '\0');
        gl.glGetShaderInfoLog(m_name, GLsizei(log.size()), nullptr, log.data());
        log.resize(std::strlen(log.c_str()));
        gl.glDeleteShader(m_name);
        throw Error(ErrorCode::ShaderCompilation,
                    fmt::format("the driver rejected the translated {}: {}", label, describeCompileFailure(log, m_source)));
    }
}

Shader::~Shader() {
    m_context->deleteObjects(GLObjectKind::Shader, std::span(&m_name, 1));
}

// ---------------------------------------------------------------------------------------------
// Pipelines

// The shaders are this device's (checked by Device::create*PipelineImpl, or internal).
Pipeline::Pipeline(ContextPtr context, const GraphicsPipelineDesc& desc)
    : m_context(std::move(context)), m_graphics(desc) {
    switch (desc.topology) {
        case PrimitiveTopology::TriangleList: m_mode = GL_TRIANGLES; break;
        case PrimitiveTopology::TriangleStrip: m_mode = GL_TRIANGLE_STRIP; break;
        case PrimitiveTopology::LineList: m_mode = GL_LINES; break;
        case PrimitiveTopology::PointList: m_mode = GL_POINTS; break;
    }
    link({static_cast<const Shader*>(desc.vertexShader.get()), static_cast<const Shader*>(desc.fragmentShader.get())},
         desc.debugName, desc.dynamicUniformBuffers);
}

Pipeline::Pipeline(ContextPtr context, const ComputePipelineDesc& desc)
    : m_context(std::move(context)), m_compute(true) {
    link({static_cast<const Shader*>(desc.computeShader.get())}, desc.debugName, desc.dynamicUniformBuffers);
}

Pipeline::~Pipeline() {
    m_context->deleteObjects(GLObjectKind::Program, std::span(&m_program, 1));
}

namespace {
// Interned binding signatures: what the binding checks read of a pipeline's bindings. The map only
// grows, so an id is never given to another signature.
uint64_t bindingSignatureId(const std::vector<ShaderBinding>& bindings) {
    using Key = std::vector<std::tuple<uint32_t, uint32_t, int, int, bool, uint32_t, uint64_t, bool, bool>>;
    Key key;
    key.reserve(bindings.size());
    for (const ShaderBinding& b : bindings)
        key.emplace_back(b.set, b.binding, int(b.type), b.dimension ? int(*b.dimension) : -1, b.depthCompare,
                         b.imageFormat, b.blockSize, b.dynamicOffset, b.written);
    static std::mutex mutex;
    static std::map<Key, uint64_t> ids;
    const std::lock_guard lock(mutex);
    return ids.try_emplace(std::move(key), ids.size() + 1).first->second;
}
}  // namespace

void Pipeline::link(const std::vector<const Shader*>& shaders, const std::string& debugName,
                    std::span<const DynamicUniformBuffer> dynamic) {
    const GLFunctions& gl = m_context->gl;
    m_program = gl.glCreateProgram();
    for (const Shader* shader : shaders) gl.glAttachShader(m_program, shader->name());
    gl.glLinkProgram(m_program);
    for (const Shader* shader : shaders) gl.glDetachShader(m_program, shader->name());
    GLint linked = GL_FALSE;
    gl.glGetProgramiv(m_program, GL_LINK_STATUS, &linked);
    if (!linked) {
        GLint length = 0;
        gl.glGetProgramiv(m_program, GL_INFO_LOG_LENGTH, &length);
        std::string log(size_t(std::max(length, 1)), '\0');
        gl.glGetProgramInfoLog(m_program, GLsizei(log.size()), nullptr, log.data());
        log.resize(std::strlen(log.c_str()));
        gl.glDeleteProgram(m_program);
        throw Error(ErrorCode::ShaderCompilation,
                    fmt::format("linking pipeline '{}' failed (do the vertex outputs match the fragment inputs by "
                                "location and type?): {}",
                                debugName, log));
    }

    // Binding points from reflection: the SPIR-V binding number is the GL binding point.
    gl.glUseProgram(m_program);
    for (const Shader* shader : shaders) {
        for (const ShaderBinding& binding : shader->bindings()) {
            switch (binding.type) {
                case ResourceType::UniformBuffer: {
                    const GLuint index = gl.glGetUniformBlockIndex(m_program, binding.glName.c_str());
                    if (index != GL_INVALID_INDEX) gl.glUniformBlockBinding(m_program, index, binding.binding);
                    break;
                }
                case ResourceType::StorageBuffer: {
                    const GLuint index =
                        gl.glGetProgramResourceIndex(m_program, GL_SHADER_STORAGE_BLOCK, binding.glName.c_str());
                    if (index != GL_INVALID_INDEX) gl.glShaderStorageBlockBinding(m_program, index, binding.binding);
                    break;
                }
                case ResourceType::SampledTexture:
                case ResourceType::StorageImage: {
                    const GLint location = gl.glGetUniformLocation(m_program, binding.glName.c_str());
                    if (location >= 0) gl.glUniform1i(location, GLint(binding.binding));
                    break;
                }
            }
            m_bindings.push_back(binding);
            // Validated: each names a uniform block the shaders read.
            m_bindings.back().dynamicOffset = declaresDynamic(dynamic, binding.set, binding.binding);
        }
    }
    m_bindingSignature = bindingSignatureId(m_bindings);
    for (const ShaderBinding& binding : m_bindings) {
        if (binding.set >= kMaxBindingSets)
            m_cacheableBindings = false;
        else if (std::find(m_usedSets.begin(), m_usedSets.end(), binding.set) == m_usedSets.end())
            m_usedSets.push_back(binding.set);
        if (binding.set < kMaxBindingSets) m_setPoints[binding.set] |= bindingPointBit(binding.binding);
    }
    std::sort(m_usedSets.begin(), m_usedSets.end());
    if (m_cacheableBindings && m_usedSets.size() == 1) m_singleSet = m_usedSets[0];
    m_baseInstanceLocation = gl.glGetUniformLocation(m_program, "SPIRV_Cross_BaseInstance");
    m_debugName = debugName;
    if (m_context->checkSamplerUnits) findSamplerUniforms();
    gl.glUseProgram(0);
    if (!debugName.empty() && gl.glObjectLabel && !m_context->isES())
        gl.glObjectLabel(GL_PROGRAM, m_program, GLsizei(debugName.size()), debugName.data());
}

namespace {
struct SamplerType {
    GLenum bindingQuery;
    const char* targetName;
    bool shadow;
};
std::optional<SamplerType> samplerType(GLenum type) {
    switch (type) {
        case GL_SAMPLER_2D: case GL_INT_SAMPLER_2D: case GL_UNSIGNED_INT_SAMPLER_2D:
            return SamplerType{GL_TEXTURE_BINDING_2D, "2D", false};
        case GL_SAMPLER_2D_SHADOW: return SamplerType{GL_TEXTURE_BINDING_2D, "2D", true};
        case GL_SAMPLER_3D: case GL_INT_SAMPLER_3D: case GL_UNSIGNED_INT_SAMPLER_3D:
            return SamplerType{GL_TEXTURE_BINDING_3D, "3D", false};
        case GL_SAMPLER_CUBE: case GL_INT_SAMPLER_CUBE: case GL_UNSIGNED_INT_SAMPLER_CUBE:
            return SamplerType{GL_TEXTURE_BINDING_CUBE_MAP, "cube map", false};
        case GL_SAMPLER_CUBE_SHADOW: return SamplerType{GL_TEXTURE_BINDING_CUBE_MAP, "cube map", true};
        case GL_SAMPLER_2D_ARRAY: case GL_INT_SAMPLER_2D_ARRAY: case GL_UNSIGNED_INT_SAMPLER_2D_ARRAY:
            return SamplerType{GL_TEXTURE_BINDING_2D_ARRAY, "2D array", false};
        case GL_SAMPLER_2D_ARRAY_SHADOW: return SamplerType{GL_TEXTURE_BINDING_2D_ARRAY, "2D array", true};
        case GL_SAMPLER_CUBE_MAP_ARRAY: case GL_INT_SAMPLER_CUBE_MAP_ARRAY: case GL_UNSIGNED_INT_SAMPLER_CUBE_MAP_ARRAY:
            return SamplerType{GL_TEXTURE_BINDING_CUBE_MAP_ARRAY, "cube map array", false};
        case GL_SAMPLER_CUBE_MAP_ARRAY_SHADOW: return SamplerType{GL_TEXTURE_BINDING_CUBE_MAP_ARRAY, "cube map array", true};
        default: return std::nullopt;   // not a sampler (images use image units)
    }
}
}  // namespace

// Called with the program in use, after link() set each sampler's unit.
void Pipeline::findSamplerUniforms() {
    const GLFunctions& gl = m_context->gl;
    GLint count = 0, maxLength = 0;
    gl.glGetProgramiv(m_program, GL_ACTIVE_UNIFORMS, &count);
    gl.glGetProgramiv(m_program, GL_ACTIVE_UNIFORM_MAX_LENGTH, &maxLength);
    std::string name(size_t(std::max(maxLength, 1)), '\0');
    for (GLint i = 0; i < count; ++i) {
        GLint size = 0;
        GLenum type = 0;
        GLsizei length = 0;
        gl.glGetActiveUniform(m_program, GLuint(i), GLsizei(name.size()), &length, &size, &type, name.data());
        const std::optional<SamplerType> sampler = samplerType(type);
        if (!sampler) continue;
        std::string base(name.data(), size_t(length));
        if (base.ends_with("[0]")) base.resize(base.size() - 3);
        for (GLint element = 0; element < size; ++element) {
            const std::string elementName = size > 1 ? fmt::format("{}[{}]", base, element) : base;
            const GLint location = gl.glGetUniformLocation(m_program, elementName.c_str());
            if (location < 0) continue;
            GLint unit = 0;
            gl.glGetUniformiv(m_program, location, &unit);
            m_samplerUniforms.push_back({elementName, unit, sampler->bindingQuery, sampler->targetName, sampler->shadow});
        }
    }
}

namespace {
GLenum toGL(BlendFactor factor) {
    switch (factor) {
        case BlendFactor::Zero: return GL_ZERO;
        case BlendFactor::One: return GL_ONE;
        case BlendFactor::SrcColor: return GL_SRC_COLOR;
        case BlendFactor::OneMinusSrcColor: return GL_ONE_MINUS_SRC_COLOR;
        case BlendFactor::SrcAlpha: return GL_SRC_ALPHA;
        case BlendFactor::OneMinusSrcAlpha: return GL_ONE_MINUS_SRC_ALPHA;
        case BlendFactor::DstColor: return GL_DST_COLOR;
        case BlendFactor::OneMinusDstColor: return GL_ONE_MINUS_DST_COLOR;
        case BlendFactor::DstAlpha: return GL_DST_ALPHA;
        case BlendFactor::OneMinusDstAlpha: return GL_ONE_MINUS_DST_ALPHA;
    }
    return GL_ONE;
}

GLenum toGL(BlendOp op) {
    switch (op) {
        case BlendOp::Add: return GL_FUNC_ADD;
        case BlendOp::Subtract: return GL_FUNC_SUBTRACT;
        case BlendOp::ReverseSubtract: return GL_FUNC_REVERSE_SUBTRACT;
        case BlendOp::Min: return GL_MIN;
        case BlendOp::Max: return GL_MAX;
    }
    return GL_FUNC_ADD;
}
}  // namespace

void Pipeline::applyState() const {
    const GLFunctions& gl = m_context->gl;
    gl.glUseProgram(m_program);   // every time: a list ends with no program in use (Device::execute)
    if (m_compute) return;
    GLStateCache& state = m_context->state;
    const RasterState& raster = m_graphics.raster;
    state.setCulling(raster.cullMode != CullMode::None, raster.cullMode == CullMode::Front ? GL_FRONT : GL_BACK);
    // GL decides facing with y up; our images have row 0 on top, which mirrors the winding.
    state.setFrontFace(raster.frontFace == FrontFace::CounterClockwise ? GL_CW : GL_CCW);
    state.setPolygonOffset(raster.depthBiasEnable, raster.depthBiasSlope, raster.depthBiasConstant);

    const DepthState& depth = m_graphics.depth;
    state.setDepthTest(depth.testEnable, compareFunction(depth.compare));
    state.setDepthMask(depth.writeEnable);
    state.setAlphaToCoverage(m_graphics.alphaToCoverage);

    auto blendOf = [&](size_t i) { return i < m_graphics.blend.size() ? m_graphics.blend[i] : BlendAttachment{}; };
    // ES: one state for all attachments (checked equal at creation).
    const size_t attachments = m_context->isES() ? 1 : std::max<size_t>(m_graphics.colorFormats.size(), 1);
    for (uint32_t i = 0; i < attachments; ++i) {
        const BlendAttachment b = blendOf(i);
        state.setBlend(i, {b.enable, {toGL(b.srcColor), toGL(b.dstColor), toGL(b.srcAlpha), toGL(b.dstAlpha)},
                           {toGL(b.colorOp), toGL(b.alphaOp)}});
        state.setColorMask(i, b.writeMask);
    }
}

}  // namespace janus::rhi::gl
