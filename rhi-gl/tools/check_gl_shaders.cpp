// janus_check_gl_shaders: translates shaders exactly as the GL backends do (gl_shader_translation.h)
// for every context they can meet (GLSL 430 and, unless the shader is compute or left out of ES,
// ESSL 300; vertex shaders with and without clip control) and has glslang parse and link each
// translation: a second front end beside the driver's, so output one driver would reject fails a
// build here rather than on a user's machine (issue 10: NVIDIA rejected output Mesa took).
//
//   janus_check_gl_shaders [OUTPUT_DIR]
//       every shader Janus embeds; the build runs this (rhi-gl/CMakeLists.txt)
//   janus_check_gl_shaders --out DIR [--no-es] FILE.spv...
//       your own SPIR-V modules; janus_embed_shaders() runs this for every shader it embeds
//       (cmake/JanusEmbedShaders.cmake). Fragment shaders also get the derivative check that
//       createShader runs with validation on (janus/rhi/derivative_lint.h), as warnings.
//
// The translations are written to the output folder. Exit 0: all accepted; 1: a translation was
// rejected; 2: bad arguments or an unreadable or invalid module (SPIRV-Tools' validator decides).
#include <spirv_cross/spirv_cross.hpp>

#include <fmt/format.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gl_shader_translation.h"
#include "glsl_front_end_check.h"
#include "janus/rhi/derivative_lint.h"
#include "janus/rhi/spirv_validation.h"
#include "janus/shaders/shaders.h"

namespace {

using namespace janus;

constexpr const char* kTool = "janus_check_gl_shaders";

// The RHI's stage of a module, or nullopt for an execution model it does not take.
std::optional<rhi::ShaderStage> stageOf(std::span<const uint32_t> spirv) {
    spirv_cross::Compiler compiler(std::vector<uint32_t>(spirv.begin(), spirv.end()));
    switch (compiler.get_execution_model()) {
        case spv::ExecutionModelVertex: return rhi::ShaderStage::Vertex;
        case spv::ExecutionModelFragment: return rhi::ShaderStage::Fragment;
        case spv::ExecutionModelGLCompute: return rhi::ShaderStage::Compute;
        default: return std::nullopt;
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

struct Check {
    std::filesystem::path outputDir;
    size_t shaders = 0, translations = 0;
    std::vector<std::string> failures;

    // Every GL translation of one module; `es`: also ESSL 300 (never for compute: ES 3.0 has none).
    void shader(std::string_view name, std::span<const uint32_t> spirv, rhi::ShaderStage stage, bool es) {
        ++shaders;
        rhi::ShaderDesc desc;
        desc.setStage(stage).setSpirv(spirv).setDebugName(std::string(name));
        struct Target {
            const char* name;
            rhi::gl::GlslTarget target;
        };
        std::vector<Target> targets = {{"gl430", {false, true}}};
        if (stage == rhi::ShaderStage::Vertex) targets.push_back({"gl430-clipfix", {false, false}});
        if (es && stage != rhi::ShaderStage::Compute) {
            targets.push_back({"es300", {true, true}});
            if (stage == rhi::ShaderStage::Vertex) targets.push_back({"es300-clipfix", {true, false}});
        }
        for (const Target& target : targets) {
            ++translations;
            const std::string label = fmt::format("{} ({})", name, target.name);
            std::string source;
            try {
                source = rhi::gl::translateToGlsl(desc, target.target).source;
            } catch (const spirv_cross::CompilerError& e) {
                failures.push_back(fmt::format("{}: SPIRV-Cross cannot translate it: {}", label, e.what()));
                continue;
            }
            const std::filesystem::path file = outputDir / fmt::format("{}.{}.{}", name, target.name, extensionOf(stage));
            std::ofstream(file) << source;
            if (const std::string log = rhi::gl::glslangRejection(withoutDrawParameters(source), stage); !log.empty())
                failures.push_back(fmt::format("{}: glslang rejects SPIRV-Cross's output ({}):\n{}", label, file.string(), log));
        }
    }

    int finish() const {
        if (!failures.empty()) {
            for (const std::string& failure : failures) fmt::print(stderr, "{}: {}\n", kTool, failure);
            fmt::print(stderr, "{}: {} of {} GL translations of {} shader{} rejected\n", kTool, failures.size(), translations,
                       shaders, shaders == 1 ? "" : "s");
            return 1;
        }
        fmt::print("{}: glslang accepts all {} GL translations of {} shader{}\n", kTool, translations, shaders,
                   shaders == 1 ? "" : "s");
        return 0;
    }
};

int usage(std::string_view problem) {
    fmt::print(stderr,
               "{}: {}\nusage: {} [OUTPUT_DIR]                          every shader Janus embeds\n"
               "       {} --out DIR [--no-es] FILE.spv...     your own SPIR-V modules\n",
               kTool, problem, kTool, kTool);
    return 2;
}

// A SPIR-V module from `path`, or nullopt (and a message on stderr) when it cannot be one.
std::optional<std::vector<uint32_t>> readModule(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        fmt::print(stderr, "{}: cannot read '{}'\n", kTool, path.string());
        return std::nullopt;
    }
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.size() < 20 || bytes.size() % 4 != 0) {
        fmt::print(stderr, "{}: '{}' is not a SPIR-V module ({} bytes; a module is a whole number of 4-byte words, "
                           "at least 5)\n", kTool, path.string(), bytes.size());
        return std::nullopt;
    }
    std::vector<uint32_t> words(bytes.size() / 4);
    std::memcpy(words.data(), bytes.data(), bytes.size());
    if (words[0] != 0x07230203u) {
        fmt::print(stderr, "{}: '{}' is not a SPIR-V module (its first word is 0x{:08x}, not SPIR-V's magic number "
                           "0x07230203; compile GLSL with glslangValidator -V first)\n", kTool, path.string(), words[0]);
        return std::nullopt;
    }
    // SPIRV-Cross assumes a valid module: a damaged one could crash it.
    if (const std::string problem = rhi::spirvModuleProblem(words); !problem.empty()) {
        fmt::print(stderr, "{}: '{}' is not a valid SPIR-V module: {}\n", kTool, path.string(), problem);
        return std::nullopt;
    }
    return words;
}

// The user's modules: --out DIR [--no-es] FILE.spv...
int checkFiles(int argc, char** argv) {
    Check check;
    bool es = true;
    std::vector<std::filesystem::path> files;
    for (int i = 1; i < argc; ++i) {
        const std::string_view argument = argv[i];
        if (argument == "--out") {
            if (++i == argc) return usage("--out needs a folder");
            check.outputDir = argv[i];
        } else if (argument == "--no-es") {
            es = false;
        } else if (argument.starts_with("--")) {
            return usage(fmt::format("unknown option '{}'", argument));
        } else {
            files.emplace_back(argument);
        }
    }
    if (check.outputDir.empty()) return usage("--out DIR is missing");
    if (files.empty()) return usage("no SPIR-V file given");
    std::filesystem::create_directories(check.outputDir);
    for (const std::filesystem::path& file : files) {
        const std::optional<std::vector<uint32_t>> spirv = readModule(file);
        if (!spirv) return 2;
        std::optional<rhi::ShaderStage> stage;
        try {
            stage = stageOf(*spirv);
        } catch (const spirv_cross::CompilerError& e) {
            fmt::print(stderr, "{}: '{}' cannot be read as SPIR-V: {}\n", kTool, file.string(), e.what());
            return 2;
        }
        if (!stage) {
            fmt::print(stderr, "{}: '{}' is not a vertex, fragment or compute shader, the only stages the RHI takes\n", kTool,
                       file.string());
            return 2;
        }
        std::string name = file.filename().string();
        if (name.ends_with(".spv")) name.resize(name.size() - 4);
        if (*stage == rhi::ShaderStage::Fragment)
            for (const std::string& finding : rhi::derivativeHazards(*spirv))
                fmt::print(stderr, "{}: warning: {}: {}\n", kTool, file.string(), finding);
        check.shader(name, *spirv, *stage, es);
    }
    return check.finish();
}

}  // namespace

int main(int argc, char** argv) {
    if (argc > 1 && std::string_view(argv[1]).starts_with("--")) return checkFiles(argc, argv);
    if (argc > 2) return usage("one output folder at most (your own shaders: --out DIR FILE.spv...)");
    Check check;
    check.outputDir = argc > 1 ? argv[1] : "gl-shader-check";
    std::filesystem::create_directories(check.outputDir);
    for (const shaders::Entry& entry : shaders::all()) {
        const std::optional<rhi::ShaderStage> stage = stageOf(entry.spirv);
        if (!stage) {
            fmt::print(stderr, "{}: embedded shader {} is not a vertex, fragment or compute shader\n", kTool, entry.name);
            return 2;
        }
        check.shader(entry.name, entry.spirv, *stage, entry.essl);
    }
    return check.finish();
}
