#include "janus/shaders/shaders.h"

#include <stdexcept>
#include <string>

namespace janus::shaders {

std::span<const uint32_t> get(std::string_view name) {
    for (const Entry& e : all())
        if (e.name == name) return e.spirv;
    throw std::out_of_range("no embedded shader named '" + std::string(name) + "' (see shaders/shader_list.cmake)");
}

}  // namespace janus::shaders
