#include "janus/shaders/derivative_lint.h"

#include <fmt/format.h>

#include <map>
#include <set>
#include <stdexcept>
#include <unordered_map>

namespace janus::shaders {
namespace {

// SPIR-V opcodes (SPIR-V specification, 3.52); only those the check reads.
enum Op : uint32_t {
    OpName = 5,
    OpEntryPoint = 15,
    OpFunction = 54,
    OpFunctionEnd = 56,
    OpFunctionCall = 57,
    OpLoad = 61,
    OpAccessChain = 65,
    OpInBoundsAccessChain = 66,
    OpSampledImage = 86,
    OpImageSampleImplicitLod = 87,
    OpImageSampleDrefImplicitLod = 89,
    OpImageSampleProjImplicitLod = 91,
    OpImageSampleProjDrefImplicitLod = 93,
    OpImageQueryLod = 105,
    OpDPdx = 207,
    OpFwidthCoarse = 215,
    OpLabel = 248,
    OpBranch = 249,
    OpBranchConditional = 250,
    OpSwitch = 251,
    OpKill = 252,
    OpImageSparseSampleImplicitLod = 305,
    OpImageSparseSampleDrefImplicitLod = 307,
    OpImageSparseSampleProjImplicitLod = 309,
    OpImageSparseSampleProjDrefImplicitLod = 311,
    OpTerminateInvocation = 4416,
};
constexpr uint32_t kSpirvMagic = 0x07230203;
constexpr uint32_t kExecutionModelFragment = 4;

bool isImplicitLodSample(uint32_t op) {
    switch (op) {
        case OpImageSampleImplicitLod:
        case OpImageSampleDrefImplicitLod:
        case OpImageSampleProjImplicitLod:
        case OpImageSampleProjDrefImplicitLod:
        case OpImageSparseSampleImplicitLod:
        case OpImageSparseSampleDrefImplicitLod:
        case OpImageSparseSampleProjImplicitLod:
        case OpImageSparseSampleProjDrefImplicitLod:
        case OpImageQueryLod: return true;
        default: return false;
    }
}
bool isDerivative(uint32_t op) { return op >= OpDPdx && op <= OpFwidthCoarse; }
bool isKill(uint32_t op) { return op == OpKill || op == OpTerminateInvocation; }

struct Instruction {
    uint32_t op = 0;
    std::span<const uint32_t> words;   // the whole instruction, opcode word included
};

struct Block {
    uint32_t label = 0;
    std::vector<Instruction> body;   // the terminator last
    std::vector<uint32_t> successors;
};

struct Function {
    uint32_t id = 0;
    std::vector<Block> blocks;
};

struct Module {
    std::unordered_map<uint32_t, std::string> names;
    std::unordered_map<uint32_t, Instruction> definitions;   // result id -> instruction (those the check follows)
    std::vector<Function> functions;
    bool fragment = false;
};

std::string literalString(std::span<const uint32_t> words) {
    std::string text;
    for (uint32_t word : words) {
        for (int byte = 0; byte < 4; ++byte) {
            const char c = char((word >> (8 * byte)) & 0xFF);
            if (c == '\0') return text;
            text += c;
        }
    }
    return text;
}

Module parse(std::span<const uint32_t> spirv) {
    if (spirv.size() < 5 || spirv[0] != kSpirvMagic)
        throw std::invalid_argument("derivativesAfterDiscard: not a SPIR-V module (no magic number 0x07230203 in its first word)");
    Module module;
    Function* function = nullptr;
    Block* block = nullptr;
    for (size_t at = 5; at < spirv.size();) {
        const uint32_t op = spirv[at] & 0xFFFF, count = spirv[at] >> 16;
        if (count == 0 || at + count > spirv.size())
            throw std::invalid_argument(fmt::format("derivativesAfterDiscard: SPIR-V instruction at word {} runs past the module's end", at));
        const Instruction instruction{op, spirv.subspan(at, count)};
        at += count;
        switch (op) {
            case OpName:
                if (count >= 3) module.names[instruction.words[1]] = literalString(instruction.words.subspan(2));
                continue;
            case OpEntryPoint:
                if (count >= 2 && instruction.words[1] == kExecutionModelFragment) module.fragment = true;
                continue;
            case OpFunction:
                function = &module.functions.emplace_back();
                function->id = count >= 3 ? instruction.words[2] : 0;
                continue;
            case OpFunctionEnd:
                function = nullptr;
                block = nullptr;
                continue;
            case OpLabel:
                if (function) {
                    block = &function->blocks.emplace_back();
                    block->label = instruction.words[1];
                }
                continue;
            case OpLoad:
            case OpAccessChain:
            case OpInBoundsAccessChain:
            case OpSampledImage:
                if (count >= 4) module.definitions[instruction.words[2]] = instruction;
                break;
            default: break;
        }
        if (block) block->body.push_back(instruction);
    }
    // Successors: every operand of a branch that names a block of the same function (an OpSwitch's
    // literals could collide with a label id; an extra edge only makes the check more cautious).
    for (Function& f : module.functions) {
        std::set<uint32_t> labels;
        for (const Block& b : f.blocks) labels.insert(b.label);
        for (Block& b : f.blocks) {
            if (b.body.empty()) continue;
            const Instruction& terminator = b.body.back();
            if (terminator.op != OpBranch && terminator.op != OpBranchConditional && terminator.op != OpSwitch) continue;
            for (size_t w = 1; w < terminator.words.size(); ++w)
                if (labels.count(terminator.words[w])) b.successors.push_back(terminator.words[w]);
        }
    }
    return module;
}

// What an implicit-LOD lookup samples: the name of the variable its image comes from.
std::string sampledName(const Module& module, uint32_t id) {
    for (int hops = 0; hops < 8; ++hops) {
        if (auto name = module.names.find(id); name != module.names.end() && !name->second.empty()) return "'" + name->second + "'";
        auto definition = module.definitions.find(id);
        if (definition == module.definitions.end()) break;
        id = definition->second.words[3];   // OpLoad's pointer, an access chain's base, OpSampledImage's image
    }
    return "an unnamed image";
}

std::string functionName(const Module& module, uint32_t id) {
    auto name = module.names.find(id);
    if (name == module.names.end()) return fmt::format("%{}", id);
    return name->second.substr(0, name->second.find('('));   // glslang mangles parameters into the name
}

std::string describe(const Module& module, const Instruction& instruction) {
    if (isDerivative(instruction.op)) return "a derivative (dFdx/dFdy/fwidth)";
    const char* what = instruction.op == OpImageQueryLod ? "a level-of-detail query" : "an implicit-LOD texture lookup";
    return fmt::format("{} of {}", what, sampledName(module, instruction.words.size() > 3 ? instruction.words[3] : 0));
}

class Checker {
public:
    explicit Checker(const Module& module) : m_module(module) {
        for (const Function& f : module.functions) m_functions[f.id] = &f;
    }

    std::vector<std::string> run() {
        for (const Function& f : m_module.functions) checkFunction(f);
        return std::move(m_findings);
    }

private:
    // Whether calling `id` may discard, and what implicit derivatives it (or a callee) takes.
    bool discards(uint32_t id) {
        if (auto known = m_discards.find(id); known != m_discards.end()) return known->second;
        m_discards[id] = false;   // SPIR-V forbids recursion; this only guards against malformed input
        bool result = false;
        if (auto f = m_functions.find(id); f != m_functions.end())
            for (const Block& b : f->second->blocks)
                for (const Instruction& i : b.body)
                    if (isKill(i.op) || (i.op == OpFunctionCall && i.words.size() > 3 && discards(i.words[3]))) result = true;
        return m_discards[id] = result;
    }
    const std::vector<std::string>& derivativesIn(uint32_t id) {
        if (auto known = m_derivatives.find(id); known != m_derivatives.end()) return known->second;
        m_derivatives[id];   // recursion guard, as above
        std::vector<std::string> found;
        if (auto f = m_functions.find(id); f != m_functions.end()) {
            for (const Block& b : f->second->blocks) {
                for (const Instruction& i : b.body) {
                    if (isImplicitLodSample(i.op) || isDerivative(i.op)) found.push_back(describe(m_module, i));
                    if (i.op == OpFunctionCall && i.words.size() > 3)
                        for (const std::string& inner : derivativesIn(i.words[3])) found.push_back(inner);
                }
            }
        }
        return m_derivatives[id] = std::move(found);
    }

    void checkFunction(const Function& f) {
        std::unordered_map<uint32_t, const Block*> byLabel;
        for (const Block& b : f.blocks) byLabel[b.label] = &b;
        std::unordered_map<uint32_t, std::vector<uint32_t>> predecessors;
        for (const Block& b : f.blocks)
            for (uint32_t s : b.successors) predecessors[s].push_back(b.label);

        // Blocks reachable in one or more steps from `from`.
        auto reachableFrom = [&](uint32_t from) {
            std::set<uint32_t> seen;
            std::vector<uint32_t> stack(byLabel.at(from)->successors);
            while (!stack.empty()) {
                const uint32_t label = stack.back();
                stack.pop_back();
                if (!seen.insert(label).second) continue;
                for (uint32_t s : byLabel.at(label)->successors) stack.push_back(s);
            }
            return seen;
        };

        // "After" each discard: for a block ending in OpKill, all that its predecessors reach but
        // itself (the lanes that did not discard go on there); for a call to a discarding function,
        // the rest of its block and all that the block reaches.
        std::map<uint32_t, std::string> afterBlocks;                 // label -> what it follows
        std::map<std::pair<uint32_t, size_t>, std::string> afterInBlock;   // (label, first instruction) -> what
        const std::string where = functionName(m_module, f.id);
        for (const Block& b : f.blocks) {
            if (b.body.empty()) continue;
            if (isKill(b.body.back().op)) {
                for (uint32_t p : predecessors[b.label])
                    for (uint32_t label : reachableFrom(p))
                        if (label != b.label) afterBlocks.emplace(label, fmt::format("a discard in '{}'", where));
            }
            for (size_t i = 0; i < b.body.size(); ++i) {
                const Instruction& call = b.body[i];
                if (call.op != OpFunctionCall || call.words.size() <= 3 || !discards(call.words[3])) continue;
                const std::string what = fmt::format("a call to '{}', which may discard", functionName(m_module, call.words[3]));
                afterInBlock.emplace(std::pair{b.label, i + 1}, what);
                for (uint32_t label : reachableFrom(b.label)) afterBlocks.emplace(label, what);
                break;   // later calls in this block are after this one anyway
            }
        }
        if (afterBlocks.empty() && afterInBlock.empty()) return;

        for (const Block& b : f.blocks) {
            const std::string* follows = nullptr;
            size_t first = b.body.size();
            if (auto after = afterBlocks.find(b.label); after != afterBlocks.end()) {
                follows = &after->second;
                first = 0;
            } else {
                for (const auto& [key, what] : afterInBlock)
                    if (key.first == b.label) follows = &what, first = key.second;
            }
            if (!follows) continue;
            for (size_t i = first; i < b.body.size(); ++i) {
                const Instruction& instruction = b.body[i];
                if (isImplicitLodSample(instruction.op) || isDerivative(instruction.op)) {
                    report(describe(m_module, instruction), where, *follows);
                } else if (instruction.op == OpFunctionCall && instruction.words.size() > 3) {
                    for (const std::string& inner : derivativesIn(instruction.words[3]))
                        report(fmt::format("{} (in '{}')", inner, functionName(m_module, instruction.words[3])), where, *follows);
                }
            }
        }
    }

    void report(const std::string& what, const std::string& function, const std::string& follows) {
        m_findings.push_back(fmt::format(
            "{} in '{}' may run after {}: a discarded neighbour leaves the quad's derivatives undefined; take it before the discard, "
            "or use textureLod/textureGrad",
            what, function, follows));
    }

    const Module& m_module;
    std::unordered_map<uint32_t, const Function*> m_functions;
    std::unordered_map<uint32_t, bool> m_discards;
    std::unordered_map<uint32_t, std::vector<std::string>> m_derivatives;
    std::vector<std::string> m_findings;
};

}  // namespace

std::vector<std::string> derivativesAfterDiscard(std::span<const uint32_t> spirv) {
    const Module module = parse(spirv);
    if (!module.fragment) return {};
    return Checker(module).run();
}

}  // namespace janus::shaders
