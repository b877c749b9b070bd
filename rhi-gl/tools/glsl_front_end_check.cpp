#include "glsl_front_end_check.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>

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
    return {};
}

}  // namespace janus::rhi::gl
