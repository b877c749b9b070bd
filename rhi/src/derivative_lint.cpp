#include "janus/rhi/derivative_lint.h"

// The opcode and enum names, and which instructions have a result (HasResultAndType).
#define SPV_ENABLE_UTILITY_CODE
#include <spirv_cross/spirv.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

namespace janus::rhi {
namespace {

constexpr uint32_t kSpirvMagic = 0x07230203;

bool isImplicitLodSample(spv::Op op) {
    switch (op) {
        case spv::OpImageSampleImplicitLod:
        case spv::OpImageSampleDrefImplicitLod:
        case spv::OpImageSampleProjImplicitLod:
        case spv::OpImageSampleProjDrefImplicitLod:
        case spv::OpImageSparseSampleImplicitLod:
        case spv::OpImageSparseSampleDrefImplicitLod:
        case spv::OpImageSparseSampleProjImplicitLod:
        case spv::OpImageSparseSampleProjDrefImplicitLod:
        case spv::OpImageQueryLod: return true;
        default: return false;
    }
}
bool isDerivative(spv::Op op) { return op >= spv::OpDPdx && op <= spv::OpFwidthCoarse; }
bool takesDerivatives(spv::Op op) { return isImplicitLodSample(op) || isDerivative(op); }
bool isKill(spv::Op op) { return op == spv::OpKill || op == spv::OpTerminateInvocation; }
// Leaves the function: the lanes that did are gone from the rest of it. (A discard does too; the
// discard check reports what follows one, so the divergence check leaves it out rather than
// report the same lookup twice.)
bool returns(spv::Op op) { return op == spv::OpReturn || op == spv::OpReturnValue || op == spv::OpUnreachable; }

struct Instruction {
    spv::Op op = spv::OpNop;
    std::span<const uint32_t> words;   // the whole instruction, opcode word included
    uint32_t result = 0;               // 0: none
    size_t firstOperand = 1;           // index in `words` of the first operand after the result
    uint32_t file = 0, line = 0;       // the OpLine in effect (a module with debug info), 0: none
};

struct Block {
    uint32_t label = 0;
    std::vector<Instruction> body;   // the terminator last
    std::vector<uint32_t> successors;
    uint32_t merge = 0;              // OpSelectionMerge / OpLoopMerge's merge block, 0 when none
    uint32_t continueTarget = 0;     // a loop header's continue block (OpLoopMerge), else 0
    bool loopHeader = false;
};

struct Function {
    uint32_t id = 0;
    std::vector<uint32_t> parameters;   // OpFunctionParameter ids, in order
    std::vector<Block> blocks;
    std::unordered_map<uint32_t, size_t> indexOf;   // label -> index in blocks
};

struct Module {
    std::unordered_map<uint32_t, std::string> names;
    std::unordered_map<uint32_t, std::string> strings;        // OpString: source file names
    std::unordered_map<uint32_t, Instruction> definitions;   // result id -> instruction
    std::unordered_map<uint32_t, uint32_t> storageClass;     // variable -> storage class
    std::unordered_set<uint32_t> quadUniformInputs;          // flat inputs and per-primitive built-ins
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
        throw std::invalid_argument("derivative lint: not a SPIR-V module (no magic number 0x07230203 in its first word)");
    Module module;
    Function* function = nullptr;
    Block* block = nullptr;
    uint32_t pendingMerge = 0, pendingContinue = 0;
    bool pendingLoop = false;
    uint32_t lineFile = 0, line = 0;
    for (size_t at = 5; at < spirv.size();) {
        const uint32_t count = spirv[at] >> 16;
        if (count == 0 || at + count > spirv.size())
            throw std::invalid_argument(fmt::format("derivative lint: SPIR-V instruction at word {} runs past the module's end", at));
        Instruction instruction{spv::Op(spirv[at] & 0xFFFF), spirv.subspan(at, count)};
        at += count;
        bool hasResult = false, hasType = false;
        spv::HasResultAndType(instruction.op, &hasResult, &hasType);
        instruction.firstOperand = 1 + (hasType ? 1 : 0) + (hasResult ? 1 : 0);
        if (hasResult && count > (hasType ? 2u : 1u)) {
            instruction.result = instruction.words[hasType ? 2 : 1];
            module.definitions[instruction.result] = instruction;
        }
        const std::span<const uint32_t>& w = instruction.words;
        instruction.file = lineFile;
        instruction.line = line;
        switch (instruction.op) {
            case spv::OpString:
                if (count >= 3) module.strings[w[1]] = literalString(w.subspan(2));
                continue;
            case spv::OpLine:
                lineFile = count >= 3 ? w[1] : 0;
                line = count >= 3 ? w[2] : 0;
                continue;
            case spv::OpNoLine:
                lineFile = line = 0;
                continue;
            case spv::OpName:
                if (count >= 3) module.names[w[1]] = literalString(w.subspan(2));
                continue;
            case spv::OpEntryPoint:
                if (count >= 2 && w[1] == spv::ExecutionModelFragment) module.fragment = true;
                continue;
            case spv::OpDecorate:
                // A quad never spans two primitives, so what is constant per primitive is the same
                // in all four of its fragments.
                if (count >= 3 && w[2] == spv::DecorationFlat) module.quadUniformInputs.insert(w[1]);
                if (count >= 4 && w[2] == spv::DecorationBuiltIn &&
                    (w[3] == spv::BuiltInFrontFacing || w[3] == spv::BuiltInPrimitiveId || w[3] == spv::BuiltInLayer ||
                     w[3] == spv::BuiltInViewIndex))
                    module.quadUniformInputs.insert(w[1]);
                continue;
            case spv::OpVariable:
                if (count >= 4) module.storageClass[w[2]] = w[3];
                break;
            case spv::OpFunction:
                function = &module.functions.emplace_back();
                function->id = instruction.result;
                continue;
            case spv::OpFunctionParameter:
                if (function && instruction.result) function->parameters.push_back(instruction.result);
                continue;
            case spv::OpFunctionEnd:
                function = nullptr;
                block = nullptr;
                lineFile = line = 0;   // an OpLine ends with its block
                continue;
            case spv::OpLabel:
                lineFile = line = 0;
                if (count < 2) throw std::invalid_argument(fmt::format("derivative lint: OpLabel without a result id at word {}", at - count));
                if (function) {
                    function->indexOf[w[1]] = function->blocks.size();
                    block = &function->blocks.emplace_back();
                    block->label = w[1];
                }
                continue;
            case spv::OpSelectionMerge:
            case spv::OpLoopMerge:
                pendingMerge = count >= 2 ? w[1] : 0;
                pendingLoop = instruction.op == spv::OpLoopMerge;
                pendingContinue = pendingLoop && count >= 3 ? w[2] : 0;
                continue;
            default: break;
        }
        if (!block) continue;
        block->body.push_back(instruction);
        switch (instruction.op) {
            case spv::OpBranch:
            case spv::OpBranchConditional:
            case spv::OpSwitch:
                block->merge = pendingMerge;
                block->loopHeader = pendingLoop;
                block->continueTarget = pendingContinue;
                pendingMerge = pendingContinue = 0;
                pendingLoop = false;
                break;
            default: break;
        }
    }
    // Successors: every operand of a branch that names a block of the same function (an OpSwitch's
    // literals could collide with a label id; an extra edge only makes the check more cautious).
    for (Function& f : module.functions) {
        for (Block& b : f.blocks) {
            if (b.body.empty()) continue;
            const Instruction& terminator = b.body.back();
            if (terminator.op != spv::OpBranch && terminator.op != spv::OpBranchConditional && terminator.op != spv::OpSwitch) continue;
            const size_t first = terminator.op == spv::OpBranch ? 1 : 2;   // past the condition / selector
            for (size_t w = first; w < terminator.words.size(); ++w)
                if (f.indexOf.count(terminator.words[w])) b.successors.push_back(terminator.words[w]);
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
        const Instruction& d = definition->second;
        if (d.op != spv::OpLoad && d.op != spv::OpSampledImage && d.op != spv::OpAccessChain && d.op != spv::OpInBoundsAccessChain) break;
        if (d.words.size() < 4) break;
        id = d.words[3];   // OpLoad's pointer, an access chain's base, OpSampledImage's image
    }
    return "an unnamed image";
}

std::string functionName(const Module& module, uint32_t id) {
    auto name = module.names.find(id);
    if (name == module.names.end()) return fmt::format("%{}", id);
    return name->second.substr(0, name->second.find('('));   // glslang mangles parameters into the name
}

// " at file:line" from the module's debug info (glslangValidator -g), else nothing.
std::string sourceLocation(const Module& module, const Instruction& instruction) {
    if (instruction.line == 0) return {};
    auto file = module.strings.find(instruction.file);
    const std::string name = file == module.strings.end() || file->second.empty() ? "line" : file->second;
    return fmt::format(" at {}:{}", name, instruction.line);
}

std::string describe(const Module& module, const Instruction& instruction) {
    if (isDerivative(instruction.op)) return "a derivative (dFdx/dFdy/fwidth)" + sourceLocation(module, instruction);
    const char* what = instruction.op == spv::OpImageQueryLod ? "a level-of-detail query" : "an implicit-LOD texture lookup";
    return fmt::format("{} of {}{}", what, sampledName(module, instruction.words.size() > 3 ? instruction.words[3] : 0),
                       sourceLocation(module, instruction));
}

constexpr const char* kAdvice = "take it before, or use textureLod/textureGrad with derivatives taken before";

class Checker {
public:
    explicit Checker(const Module& module) : m_module(module) {
        for (const Function& f : module.functions) m_functions[f.id] = &f;
    }

    std::vector<std::string> afterDiscard() {
        for (const Function& f : m_module.functions) checkAfterDiscard(f);
        return std::move(m_findings);
    }

    std::vector<std::string> inDivergentFlow() {
        findDivergence();
        for (const Function& f : m_module.functions) {
            const std::set<uint32_t>& divergent = m_divergent[f.id];
            const std::string where = functionName(m_module, f.id);
            for (const Block& b : f.blocks) {
                if (!divergent.count(b.label)) continue;
                for (const Instruction& i : b.body)
                    forEachDerivative(i, [&](const std::string& what) { reportDivergent(what, where); });
            }
        }
        return std::move(m_findings);
    }

private:
    // Calls `report` with each implicit derivative `i` takes, described: `i` itself, or for a call,
    // those of the function it calls (and of the functions that one calls).
    template <class Report>
    void forEachDerivative(const Instruction& i, Report&& report) {
        if (takesDerivatives(i.op)) {
            report(describe(m_module, i));
        } else if (i.op == spv::OpFunctionCall && i.words.size() > 3) {
            for (const std::string& inner : derivativesIn(i.words[3]))
                report(fmt::format("{} (in '{}')", inner, functionName(m_module, i.words[3])));
        }
    }

    // --- discards ----------------------------------------------------------------------------

    // Whether calling `id` may discard (itself or in a function it calls).
    bool discards(uint32_t id) {
        if (auto known = m_discards.find(id); known != m_discards.end()) return known->second;
        m_discards[id] = false;   // SPIR-V forbids recursion; this only guards against malformed input
        bool result = false;
        if (auto f = m_functions.find(id); f != m_functions.end())
            for (const Block& b : f->second->blocks)
                for (const Instruction& i : b.body)
                    if (isKill(i.op) || (i.op == spv::OpFunctionCall && i.words.size() > 3 && discards(i.words[3]))) result = true;
        return m_discards[id] = result;
    }
    // The implicit derivatives `id` (or a function it calls) takes, described.
    const std::vector<std::string>& derivativesIn(uint32_t id) {
        if (auto known = m_derivatives.find(id); known != m_derivatives.end()) return known->second;
        m_derivatives[id];   // recursion guard, as above
        std::vector<std::string> found;
        if (auto f = m_functions.find(id); f != m_functions.end()) {
            for (const Block& b : f->second->blocks) {
                for (const Instruction& i : b.body) {
                    if (takesDerivatives(i.op)) found.push_back(describe(m_module, i));
                    if (i.op == spv::OpFunctionCall && i.words.size() > 3)
                        for (const std::string& inner : derivativesIn(i.words[3])) found.push_back(inner);
                }
            }
        }
        return m_derivatives[id] = std::move(found);
    }

    // Blocks reachable in one or more steps from `from`, not entering any of `stops` (0s ignored).
    static std::set<uint32_t> reachableFrom(const Function& f, uint32_t from, std::initializer_list<uint32_t> stops = {}) {
        std::set<uint32_t> seen;
        std::vector<uint32_t> stack(f.blocks[f.indexOf.at(from)].successors);
        while (!stack.empty()) {
            const uint32_t label = stack.back();
            stack.pop_back();
            if (std::find(stops.begin(), stops.end(), label) != stops.end() || !seen.insert(label).second) continue;
            for (uint32_t s : f.blocks[f.indexOf.at(label)].successors) stack.push_back(s);
        }
        return seen;
    }

    void checkAfterDiscard(const Function& f) {
        std::unordered_map<uint32_t, std::vector<uint32_t>> predecessors;
        for (const Block& b : f.blocks)
            for (uint32_t s : b.successors) predecessors[s].push_back(b.label);

        // "After" each discard: for a block ending in OpKill, all that its predecessors reach but
        // itself (the lanes that did not discard go on there); for a call to a discarding function,
        // the rest of its block and all that the block reaches.
        std::map<uint32_t, std::string> afterBlocks;                       // label -> what it follows
        std::map<uint32_t, std::pair<size_t, std::string>> afterInBlock;   // label -> (first instruction, what)
        const std::string where = functionName(m_module, f.id);
        for (const Block& b : f.blocks) {
            if (b.body.empty()) continue;
            if (isKill(b.body.back().op)) {
                for (uint32_t p : predecessors[b.label])
                    for (uint32_t label : reachableFrom(f, p))
                        if (label != b.label) afterBlocks.emplace(label, fmt::format("a discard in '{}'", where));
            }
            for (size_t i = 0; i < b.body.size(); ++i) {
                const Instruction& call = b.body[i];
                if (call.op != spv::OpFunctionCall || call.words.size() <= 3 || !discards(call.words[3])) continue;
                const std::string what = fmt::format("a call to '{}', which may discard", functionName(m_module, call.words[3]));
                afterInBlock.emplace(b.label, std::pair{i + 1, what});
                for (uint32_t label : reachableFrom(f, b.label)) afterBlocks.emplace(label, what);
                break;   // later calls in this block are after this one anyway
            }
        }
        for (const Block& b : f.blocks) {
            const std::string* follows = nullptr;
            size_t first = b.body.size();
            if (auto after = afterBlocks.find(b.label); after != afterBlocks.end()) {
                follows = &after->second;
                first = 0;
            } else if (auto inBlock = afterInBlock.find(b.label); inBlock != afterInBlock.end()) {
                first = inBlock->second.first;
                follows = &inBlock->second.second;
            }
            if (!follows) continue;
            for (size_t i = first; i < b.body.size(); ++i)
                forEachDerivative(b.body[i], [&](const std::string& what) { reportAfterDiscard(what, where, *follows); });
        }
    }

    // --- divergence --------------------------------------------------------------------------

    // The variable (or function parameter) a pointer points into.
    uint32_t rootOf(uint32_t pointer) const {
        for (int hops = 0; hops < 16; ++hops) {
            auto d = m_module.definitions.find(pointer);
            if (d == m_module.definitions.end()) break;
            const spv::Op op = d->second.op;
            if (op != spv::OpAccessChain && op != spv::OpInBoundsAccessChain && op != spv::OpPtrAccessChain) break;
            if (d->second.words.size() < 4) break;
            pointer = d->second.words[3];
        }
        return pointer;
    }

    bool isVarying(uint32_t id) const { return m_varying.count(id) > 0; }
    bool markVarying(uint32_t id) { return id != 0 && m_varying.insert(id).second; }

    struct Loop {
        uint32_t merge = 0, continueTarget = 0;
    };
    // Records, for every block of `f` inside a loop, its innermost loop: the smallest body (the
    // blocks a header reaches before its merge) that holds it. The control flow does not change
    // while the divergence is found, so this is done once.
    void findLoops(const Function& f) {
        std::unordered_map<uint32_t, size_t> smallest;
        for (const Block& header : f.blocks) {
            if (!header.loopHeader) continue;
            std::set<uint32_t> body = reachableFrom(f, header.label, {header.merge});
            body.insert(header.label);
            for (uint32_t label : body) {
                auto [size, first] = smallest.try_emplace(label, body.size());
                if (!first && size->second <= body.size()) continue;
                size->second = body.size();
                m_innermostLoop[label] = {header.merge, header.continueTarget};
            }
        }
    }
    // The innermost loop containing `label` (merge 0: none).
    Loop enclosingLoop(uint32_t label) const {
        auto loop = m_innermostLoop.find(label);
        return loop == m_innermostLoop.end() ? Loop{} : loop->second;
    }

    // The blocks of `f` where the lanes of a quad may disagree about being there, given m_varying:
    // those a branch on a per-fragment value leads to before its lanes meet again (its merge block,
    // or for a break or continue without one, the enclosing loop's merge); where lanes left the
    // loop iteration inside such a branch (break, continue), the rest of the loop; and where they
    // left the function (return), everything from the meeting point on.
    std::set<uint32_t> divergentBlocks(const Function& f) const {
        std::set<uint32_t> divergent;
        for (const Block& b : f.blocks) {
            if (b.body.empty()) continue;
            const Instruction& terminator = b.body.back();
            const bool conditional = terminator.op == spv::OpBranchConditional || terminator.op == spv::OpSwitch;
            if (!conditional || terminator.words.size() < 2 || !isVarying(terminator.words[1])) continue;
            const Loop loop = enclosingLoop(b.label);
            const uint32_t meet = b.merge ? b.merge : loop.merge;
            const std::set<uint32_t> region = reachableFrom(f, b.label, {meet, loop.merge});
            divergent.insert(region.begin(), region.end());
            bool leftIteration = false, leftFunction = false;
            for (uint32_t label : region) {
                const Block& r = f.blocks[f.indexOf.at(label)];
                if (!r.body.empty() && returns(r.body.back().op)) leftFunction = true;
                for (uint32_t s : r.successors)
                    if (meet != loop.merge && (s == loop.merge || s == loop.continueTarget)) leftIteration = true;
            }
            if (!meet) continue;
            if (leftFunction) {
                divergent.insert(meet);
                const std::set<uint32_t> rest = reachableFrom(f, meet);
                divergent.insert(rest.begin(), rest.end());
            } else if (leftIteration) {
                divergent.insert(meet);
                const std::set<uint32_t> rest = reachableFrom(f, meet, {loop.merge});
                divergent.insert(rest.begin(), rest.end());
            }
        }
        return divergent;
    }

    // Which values may differ between the fragments of a quad: inputs that are not constant per
    // primitive, and all that depends on them, by data, by where it was stored, and through calls.
    // Calls are summarised per function, not per call site: a parameter varies when any call passes
    // a varying argument, a call's result when the function may return a varying value (or one
    // chosen in divergent flow), and a variable passed to a parameter the function stores to
    // varies after the call when that parameter does.
    void findDivergence() {
        for (const auto& [id, storage] : m_module.storageClass)
            if (storage == spv::StorageClassInput && !m_module.quadUniformInputs.count(id)) markVarying(id);
        for (const auto& [id, instruction] : m_module.definitions)
            if ((instruction.op >= spv::OpAtomicLoad && instruction.op <= spv::OpAtomicXor) || instruction.op == spv::OpIsHelperInvocationEXT)
                markVarying(id);
        for (const Function& f : m_module.functions) {
            findLoops(f);
            for (const Block& b : f.blocks)
                for (const Instruction& i : b.body)
                    if ((i.op == spv::OpStore || i.op == spv::OpCopyMemory) && i.words.size() >= 3) m_storedTo.insert(rootOf(i.words[1]));
        }
        for (bool changed = true; changed;) {
            changed = false;
            for (const Function& f : m_module.functions) {
                std::set<uint32_t>& divergent = m_divergent[f.id];
                divergent = divergentBlocks(f);
                for (const Block& b : f.blocks) {
                    const bool inDivergentFlow = divergent.count(b.label) > 0;
                    for (const Instruction& i : b.body) changed |= propagate(f, i, inDivergentFlow, divergent);
                }
            }
        }
    }

    bool propagateCall(const Instruction& call) {
        if (call.words.size() < 4) return false;
        auto callee = m_functions.find(call.words[3]);
        if (callee == m_functions.end()) return markVarying(call.result);   // not in the module: assume the worst
        bool changed = false;
        const std::vector<uint32_t>& parameters = callee->second->parameters;
        for (size_t k = 0; k < parameters.size() && 4 + k < call.words.size(); ++k) {
            const uint32_t argument = call.words[4 + k];
            if (isVarying(argument) || isVarying(rootOf(argument))) changed |= markVarying(parameters[k]);
            // An out or inout parameter the function stores to: the caller's variable holds what it stored.
            if (isVarying(parameters[k]) && m_storedTo.count(parameters[k])) {
                auto storage = m_module.storageClass.find(rootOf(argument));
                if (storage != m_module.storageClass.end() &&
                    (storage->second == spv::StorageClassFunction || storage->second == spv::StorageClassPrivate))
                    changed |= markVarying(storage->first);
            }
        }
        if (m_returnsVarying.count(callee->first)) changed |= markVarying(call.result);
        return changed;
    }

    bool propagate(const Function& f, const Instruction& i, bool inDivergentFlow, const std::set<uint32_t>& divergent) {
        const std::span<const uint32_t> operands = i.words.subspan(std::min(i.firstOperand, i.words.size()));
        switch (i.op) {
            case spv::OpStore:
            case spv::OpCopyMemory:
                // A store in divergent flow, or of a varying value, leaves a varying variable.
                if (i.words.size() >= 3 && (inDivergentFlow || isVarying(i.words[2]) || isVarying(rootOf(i.words[2]))))   // value, or copied-from pointer
                    return markVarying(rootOf(i.words[1]));
                return false;
            case spv::OpFunctionCall: return propagateCall(i);
            case spv::OpReturnValue:
                if (i.words.size() >= 2 && (isVarying(i.words[1]) || inDivergentFlow)) return m_returnsVarying.insert(f.id).second;
                return false;
            case spv::OpPhi:
                // (value, parent block) pairs: a value that differs, or one chosen by a divergent path.
                for (size_t w = 0; w + 1 < operands.size(); w += 2)
                    if (isVarying(operands[w]) || divergent.count(operands[w + 1])) return markVarying(i.result);
                return false;
            case spv::OpVariable: return false;   // a function variable's pointer: its stores decide
            default:
                if (i.result == 0 || isVarying(i.result)) return false;
                for (uint32_t operand : operands)
                    if (isVarying(operand)) return markVarying(i.result);
                return false;
        }
    }

    void reportAfterDiscard(const std::string& what, const std::string& function, const std::string& follows) {
        m_findings.push_back(fmt::format(
            "{} in '{}' may run after {}: a discarded neighbour leaves the quad's derivatives undefined; {} the discard", what,
            function, follows, kAdvice));
    }
    void reportDivergent(const std::string& what, const std::string& function) {
        m_findings.push_back(fmt::format(
            "{} in '{}' runs where a branch on a per-fragment value decides whether it runs: the quad's other fragments may "
            "not run it, which leaves its derivatives undefined; {} the branch",
            what, function, kAdvice));
    }

    const Module& m_module;
    std::unordered_map<uint32_t, const Function*> m_functions;
    std::unordered_map<uint32_t, bool> m_discards;
    std::unordered_map<uint32_t, std::vector<std::string>> m_derivatives;
    std::unordered_set<uint32_t> m_varying;
    std::unordered_set<uint32_t> m_returnsVarying;   // functions that may return a varying value
    std::unordered_set<uint32_t> m_storedTo;         // variables and parameters some store writes
    std::unordered_map<uint32_t, std::set<uint32_t>> m_divergent;   // function -> its divergent blocks
    std::unordered_map<uint32_t, Loop> m_innermostLoop;              // block -> its innermost loop (findLoops)
    std::vector<std::string> m_findings;
};

}  // namespace

std::vector<std::string> derivativesAfterDiscard(std::span<const uint32_t> spirv) {
    const Module module = parse(spirv);
    if (!module.fragment) return {};
    return Checker(module).afterDiscard();
}

std::vector<std::string> derivativesInDivergentFlow(std::span<const uint32_t> spirv) {
    const Module module = parse(spirv);
    if (!module.fragment) return {};
    return Checker(module).inDivergentFlow();
}

std::vector<std::string> derivativeHazards(std::span<const uint32_t> spirv) {
    std::vector<std::string> found = derivativesAfterDiscard(spirv);
    for (std::string& divergent : derivativesInDivergentFlow(spirv)) found.push_back(std::move(divergent));
    return found;
}

}  // namespace janus::rhi
