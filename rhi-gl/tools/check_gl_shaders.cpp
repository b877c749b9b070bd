// janus_check_gl_shaders [OUTPUT_DIR]: translates every embedded shader exactly as the GL backends
// do (gl_shader_translation.h) for every context it can meet (GLSL 430 and, unless the shader is
// compute or NO_ES, ESSL 300; vertex shaders with and without clip control) and has glslang parse
// and link each translation. The build runs it (rhi-gl/CMakeLists.txt): any rejection fails the
// build with glslang's log and the offending source. The translations are written to OUTPUT_DIR.
#include <spirv_cross/spirv_cross.hpp>

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "gl_shader_translation.h"
#include "glsl_front_end_check.h"
#include "janus/shaders/shaders.h"

namespace {

using namespace janus;

rhi::ShaderStage stageOf(const shaders::Entry& entry) {
    spirv_cross::Compiler compiler(std::vector<uint32_t>(entry.spirv.begin(), entry.spirv.end()));
    switch (compiler.get_execution_model()) {
        case spv::ExecutionModelFragment: return rhi::ShaderStage::Fragment;
        case spv::ExecutionModelGLCompute: return rhi::ShaderStage::Compute;
        default: return rhi::ShaderStage::Vertex;
    }
}

// SPIRV-Cross reads gl_InstanceIndex's base from GL_ARB_shader_draw_parameters where the context
// has it and from a uniform it declares otherwise (the GL backend sets it). glslang 12 defines the
// extension's macro but declares gl_BaseInstanceARB only from GLSL 450 on, so it cannot parse the
// extension's branch of a 430 shader; it parses the other branch, the one a driver without the
// extension compiles. (The extension's branch is one line SPIRV-Cross writes, the same in every shader.)
std::string withoutDrawParameters(std::string source) {
    const std::string guard = "#ifdef GL_ARB_shader_draw_parameters";
    for (size_t at = source.find(guard); at != std::string::npos; at = source.find(guard, at)) source.replace(at, guard.size(), "#if 0");
    return source;
}

const char* extensionOf(rhi::ShaderStage stage) {
    switch (stage) {
        case rhi::ShaderStage::Vertex: return "vert";
        case rhi::ShaderStage::Fragment: return "frag";
        case rhi::ShaderStage::Compute: return "comp";
    }
    return "glsl";
}

}  // namespace

int main(int argc, char** argv) {
    const std::filesystem::path outputDir = argc > 1 ? argv[1] : "gl-shader-check";
    std::filesystem::create_directories(outputDir);
    size_t translations = 0, shaderCount = 0;
    std::vector<std::string> failures;
    for (const shaders::Entry& entry : shaders::all()) {
        ++shaderCount;
        const rhi::ShaderStage stage = stageOf(entry);
        rhi::ShaderDesc desc;
        desc.setStage(stage).setSpirv(entry.spirv).setDebugName(std::string(entry.name));
        struct Target {
            const char* name;
            rhi::gl::GlslTarget target;
        };
        std::vector<Target> targets = {{"gl430", {false, true}}};
        if (stage == rhi::ShaderStage::Vertex) targets.push_back({"gl430-clipfix", {false, false}});
        if (entry.essl) {
            targets.push_back({"es300", {true, true}});
            if (stage == rhi::ShaderStage::Vertex) targets.push_back({"es300-clipfix", {true, false}});
        }
        for (const Target& target : targets) {
            ++translations;
            const std::string label = fmt::format("{} ({})", entry.name, target.name);
            std::string source;
            try {
                source = rhi::gl::translateToGlsl(desc, target.target).source;
            } catch (const spirv_cross::CompilerError& e) {
                failures.push_back(fmt::format("{}: SPIRV-Cross cannot translate it: {}", label, e.what()));
                continue;
            }
            const std::filesystem::path file = outputDir / fmt::format("{}.{}.{}", entry.name, target.name, extensionOf(stage));
            std::ofstream(file) << source;
            if (const std::string log = rhi::gl::glslangRejection(withoutDrawParameters(source), stage); !log.empty())
                failures.push_back(fmt::format("{}: glslang rejects SPIRV-Cross's output ({}):\n{}", label, file.string(), log));
        }
    }
    if (!failures.empty()) {
        for (const std::string& failure : failures) fmt::print(stderr, "janus_check_gl_shaders: {}\n", failure);
        fmt::print(stderr, "janus_check_gl_shaders: {} of {} GL translations of {} shaders rejected\n", failures.size(), translations,
                   shaderCount);
        return 1;
    }
    fmt::print("janus_check_gl_shaders: glslang accepts all {} GL translations of {} shaders\n", translations, shaderCount);
    return 0;
}
