#include "glsl_front_end_check.h"

#include <glslang/Include/Types.h>
#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>

#include <algorithm>

#include <fmt/format.h>

namespace janus::rhi::gl {
namespace {

// glslang's process-wide tables, set up once for the whole program.
struct GlslangProcess {
    GlslangProcess() { glslang::InitializeProcess(); }
    ~GlslangProcess() { glslang::FinalizeProcess(); }
};

EShLanguage languageOf(ShaderStage stage) {
    switch (stage) {
        case ShaderStage::Vertex: return EShLangVertex;
        case ShaderStage::Fragment: return EShLangFragment;
        case ShaderStage::Compute: return EShLangCompute;
    }
    return EShLangVertex;
}

std::string logOf(const char* info, const char* debug) {
    std::string log = info ? info : "";
    if (debug && *debug) log += debug;
    return log.empty() ? std::string("glslang rejected the shader without a message") : log;
}

}  // namespace

std::string glslangRejection(const std::string& source, ShaderStage stage) {
    static GlslangProcess process;
    const EShLanguage language = languageOf(stage);
    glslang::TShader shader(language);
    const char* text = source.c_str();
    shader.setStrings(&text, 1);
    // OpenGL GLSL as a GL driver takes it: no client API (glslangValidator without -V/-G).
    shader.setEnvInput(glslang::EShSourceGlsl, language, glslang::EShClientNone, 0);
    if (!shader.parse(GetDefaultResources(), 100, false, EShMsgDefault)) return logOf(shader.getInfoLog(), shader.getInfoDebugLog());
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(EShMsgDefault)) return logOf(program.getInfoLog(), program.getInfoDebugLog());
    // What a driver may refuse only at link time, on a device at the minimums: glslang's default
    // limits are far above them (32 texture units), and it does not count per stage.
    if (!program.buildReflection()) return "glslang could not reflect the linked shader";
    int samplers = 0;
    for (int i = 0; i < program.getNumUniformVariables(); ++i) {
        const glslang::TType* type = program.getUniform(i).getType();
        if (type && type->getBasicType() == glslang::EbtSampler) samplers += std::max(program.getUniform(i).size, 1);
    }
    if (samplers > kMinTextureUnitsPerStage)
        return fmt::format("ERROR: the shader samples {} textures; GL 4.3 and GLES 3.0 guarantee {} per stage "
                           "(GL_MAX_TEXTURE_IMAGE_UNITS): a device at the minimum refuses to link it",
                           samplers, kMinTextureUnitsPerStage);
    if (program.getNumUniformBlocks() > kMinUniformBlocksPerStage)
        return fmt::format("ERROR: the shader reads {} uniform blocks; GL 4.3 and GLES 3.0 guarantee {} per stage "
                           "(GL_MAX_*_UNIFORM_BLOCKS): a device at the minimum refuses to link it",
                           program.getNumUniformBlocks(), kMinUniformBlocksPerStage);
    return {};
}

}  // namespace janus::rhi::gl
