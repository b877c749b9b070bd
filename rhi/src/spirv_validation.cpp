#include "janus/rhi/spirv_validation.h"

#include <spirv-tools/libspirv.hpp>

namespace janus::rhi {

std::string spirvModuleProblem(std::span<const uint32_t> spirv) {
    spvtools::SpirvTools tools(SPV_ENV_UNIVERSAL_1_6);
    std::string first;
    tools.SetMessageConsumer([&first](spv_message_level_t, const char*, const spv_position_t& position, const char* message) {
        if (first.empty()) first = std::string(message) + " (word " + std::to_string(position.index) + ")";
    });
    if (tools.Validate(spirv.data(), spirv.size())) return {};
    return first.empty() ? "the SPIR-V validator rejects it" : first;
}

}  // namespace janus::rhi
