#include "gl_functions.h"

#include <fmt/format.h>

#include <array>
#include <string>

#include "gl_platform.h"
#include "janus/rhi/rhi.h"

namespace janus::rhi::gl {

void GLFunctions::load(const Platform& platform, bool es) {
#define JANUS_GL_LOAD_REQUIRED(type, name)                                                          \
    name = reinterpret_cast<type>(platform.getProcAddress(#name));                                  \
    if (!name)                                                                                      \
        throw Error(ErrorCode::BackendUnavailable,                                                  \
                    fmt::format("the {} GL context does not export {}, which the GL backend needs", \
                                platform.describe(), #name));
    JANUS_GL_REQUIRED_FUNCTIONS(JANUS_GL_LOAD_REQUIRED)
#undef JANUS_GL_LOAD_REQUIRED

    auto loadOptional = [&](const char* base) -> void* {
        const auto suffixes = es ? std::array{"KHR", "EXT", ""} : std::array{"", "KHR", "EXT"};
        for (const char* suffix : suffixes) {
            if (void* p = platform.getProcAddress((std::string(base) + suffix).c_str())) return p;
        }
        return nullptr;
    };
#define JANUS_GL_LOAD_OPTIONAL(type, name) name = reinterpret_cast<type>(loadOptional(#name));
    JANUS_GL_OPTIONAL_FUNCTIONS(JANUS_GL_LOAD_OPTIONAL)
#undef JANUS_GL_LOAD_OPTIONAL
}

}  // namespace janus::rhi::gl
