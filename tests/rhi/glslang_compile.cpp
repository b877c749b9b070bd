#include "glslang_compile.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <stdexcept>

namespace janus::rhi::test {

std::vector<uint32_t> compileGlsl(const std::string& source, ShaderStage stage, const std::string& debugFileName) {
    static const bool initialised = glslang::InitializeProcess();
    (void)initialised;
    const EShLanguage language = stage == ShaderStage::Vertex     ? EShLangVertex
                                 : stage == ShaderStage::Fragment ? EShLangFragment
                                                                  : EShLangCompute;
    glslang::TShader shader(language);
    const char* text = source.c_str();
    const char* name = debugFileName.c_str();
    const int length = int(source.size());
    shader.setStringsWithLengthsAndNames(&text, &length, &name, 1);
    shader.setEnvInput(glslang::EShSourceGlsl, language, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_5);
    if (!shader.parse(GetDefaultResources(), 450, false, EShMsgDefault))
        throw std::runtime_error(std::string("glslang: ") + shader.getInfoLog() + "\n" + source);
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(EShMsgDefault)) throw std::runtime_error(std::string("glslang link: ") + program.getInfoLog());
    std::vector<uint32_t> spirv;
    glslang::SpvOptions options;
    options.generateDebugInfo = !debugFileName.empty();
    glslang::GlslangToSpv(*program.getIntermediate(language), spirv, &options);
    return spirv;
}

}  // namespace janus::rhi::test
