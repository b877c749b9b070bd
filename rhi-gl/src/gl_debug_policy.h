// Which GL debug messages the device collects (and the test suites fail on), and as what.
#pragma once

#include <optional>

#include "janus/rhi/rhi.h"

namespace janus::rhi::gl {

// `type` and `severity` are the GL_DEBUG_TYPE_* / GL_DEBUG_SEVERITY_* of a KHR_debug message;
// nullopt: the message is dropped. No GL header here, so tests can check the table directly.
std::optional<MessageSeverity> classifyDebugMessage(unsigned type, unsigned severity);

}  // namespace janus::rhi::gl
