// SPIR-V of every shader in shaders/, embedded at build time (see cmake/JanusShaders.cmake).
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace janus::shaders {

struct Entry {
    std::string_view name;
    std::span<const uint32_t> spirv;
    // False for compute shaders and those declared NO_ES (janus_add_shader): not for GLES 3.0.
    bool essl = true;
};

std::span<const Entry> all();

// The SPIR-V of shader `name` (the NAME given to janus_add_shader). Throws std::out_of_range
// naming the shader when there is none.
std::span<const uint32_t> get(std::string_view name);

}  // namespace janus::shaders
