// The GL debug message policy (docs/TESTING.md, "GL debug messages").
#include "gl_debug_policy.h"

#include <GL/glcorearb.h>

namespace janus::rhi::gl {

// Errors and undefined behaviour fail at any severity. Performance messages, at any severity but
// notification, are Performance: collected apart and counted, not failures (NVIDIA reports
// buffer migrations and state-based recompiles as medium-severity performance messages). Anything
// else fails at high or medium severity, and deprecated or non-portable use even at low severity
// (ES is the compute-less stand-in: a portability hint there is a real problem). Dropped:
// notifications (on Mesa only the echoes of our own debug groups) and low-severity "other" hints,
// which do not say anything is wrong.
std::optional<MessageSeverity> classifyDebugMessage(unsigned type, unsigned severity) {
    if (type == GL_DEBUG_TYPE_ERROR || type == GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR) return MessageSeverity::Error;
    if (type == GL_DEBUG_TYPE_PERFORMANCE)
        return severity == GL_DEBUG_SEVERITY_NOTIFICATION ? std::nullopt : std::optional(MessageSeverity::Performance);
    if (severity == GL_DEBUG_SEVERITY_HIGH || severity == GL_DEBUG_SEVERITY_MEDIUM) return MessageSeverity::Warning;
    if (severity == GL_DEBUG_SEVERITY_LOW && (type == GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR || type == GL_DEBUG_TYPE_PORTABILITY))
        return MessageSeverity::Warning;
    return std::nullopt;
}

}  // namespace janus::rhi::gl
