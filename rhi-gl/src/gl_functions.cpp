#include "gl_functions.h"

#include <fmt/format.h>

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

#define JANUS_GL_LOAD_OPTIONAL(type, name, esName)                                               \
    name = reinterpret_cast<type>(es ? (esName ? platform.getProcAddress(esName) : nullptr)         \
                                      : platform.getProcAddress(#name));
    JANUS_GL_OPTIONAL_FUNCTIONS(JANUS_GL_LOAD_OPTIONAL)
#undef JANUS_GL_LOAD_OPTIONAL
}

}  // namespace janus::rhi::gl
