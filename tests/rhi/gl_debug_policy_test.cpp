// The GL debug message policy, entry by entry: which KHR_debug messages the GL backend collects
// (and so fail the suites) and which it drops. The table cannot be driven through a real driver:
// llvmpipe sends no low-severity messages at all (over the whole GL suite, the only messages
// below medium are the notifications echoing our own debug groups).
#include <GL/glcorearb.h>
#include <gtest/gtest.h>

#include <optional>

#include "gl_debug_policy.h"

namespace janus::rhi::gl {
namespace {

constexpr unsigned kTypes[] = {GL_DEBUG_TYPE_ERROR,       GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR, GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR,
                               GL_DEBUG_TYPE_PORTABILITY, GL_DEBUG_TYPE_PERFORMANCE,         GL_DEBUG_TYPE_OTHER,
                               GL_DEBUG_TYPE_MARKER,      GL_DEBUG_TYPE_PUSH_GROUP,          GL_DEBUG_TYPE_POP_GROUP};
constexpr unsigned kSeverities[] = {GL_DEBUG_SEVERITY_HIGH, GL_DEBUG_SEVERITY_MEDIUM, GL_DEBUG_SEVERITY_LOW,
                                    GL_DEBUG_SEVERITY_NOTIFICATION};

TEST(GLDebugPolicy, ErrorsAndUndefinedBehaviourAreErrorsAtEverySeverity) {
    for (unsigned severity : kSeverities) {
        EXPECT_EQ(classifyDebugMessage(GL_DEBUG_TYPE_ERROR, severity), MessageSeverity::Error) << std::hex << severity;
        EXPECT_EQ(classifyDebugMessage(GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR, severity), MessageSeverity::Error)
            << std::hex << severity;
    }
}

// Counted apart, never a failure by itself (issue 10: NVIDIA's buffer-migration and recompile notes).
TEST(GLDebugPolicy, PerformanceMessagesArePerformanceAtEverySeverityButNotification) {
    for (unsigned severity : {GL_DEBUG_SEVERITY_HIGH, GL_DEBUG_SEVERITY_MEDIUM, GL_DEBUG_SEVERITY_LOW})
        EXPECT_EQ(classifyDebugMessage(GL_DEBUG_TYPE_PERFORMANCE, severity), MessageSeverity::Performance) << std::hex << severity;
    EXPECT_EQ(classifyDebugMessage(GL_DEBUG_TYPE_PERFORMANCE, GL_DEBUG_SEVERITY_NOTIFICATION), std::nullopt);
}

TEST(GLDebugPolicy, EveryOtherTypeIsAWarningAtHighAndMediumSeverity) {
    for (unsigned type : kTypes) {
        if (type == GL_DEBUG_TYPE_ERROR || type == GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR || type == GL_DEBUG_TYPE_PERFORMANCE) continue;
        EXPECT_EQ(classifyDebugMessage(type, GL_DEBUG_SEVERITY_HIGH), MessageSeverity::Warning) << std::hex << type;
        EXPECT_EQ(classifyDebugMessage(type, GL_DEBUG_SEVERITY_MEDIUM), MessageSeverity::Warning) << std::hex << type;
    }
}

// A deprecated or non-portable call is our mistake whatever severity the driver gives it.
TEST(GLDebugPolicy, DeprecatedAndNonPortableUseAreWarningsAtLowSeverity) {
    EXPECT_EQ(classifyDebugMessage(GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR, GL_DEBUG_SEVERITY_LOW), MessageSeverity::Warning);
    EXPECT_EQ(classifyDebugMessage(GL_DEBUG_TYPE_PORTABILITY, GL_DEBUG_SEVERITY_LOW), MessageSeverity::Warning);
}

TEST(GLDebugPolicy, LowSeverityHintsAndNotificationsAreDropped) {
    for (unsigned type : {GL_DEBUG_TYPE_OTHER, GL_DEBUG_TYPE_MARKER, GL_DEBUG_TYPE_PUSH_GROUP, GL_DEBUG_TYPE_POP_GROUP})
        EXPECT_EQ(classifyDebugMessage(type, GL_DEBUG_SEVERITY_LOW), std::nullopt) << std::hex << type;
    for (unsigned type : kTypes) {
        if (type == GL_DEBUG_TYPE_ERROR || type == GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR) continue;
        EXPECT_EQ(classifyDebugMessage(type, GL_DEBUG_SEVERITY_NOTIFICATION), std::nullopt) << std::hex << type;
    }
}

}  // namespace
}  // namespace janus::rhi::gl
