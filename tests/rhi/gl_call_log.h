// For GL-only tests that log which entry points the backend calls: the fixture skips Vulkan,
// keeps the device's entry points as they were (the log's `original`, which the logging
// replacements call on to), lets the suite replace the ones it watches (watch()), and puts them
// back in TearDown. GL entry points are plain functions, so the replacements find the log of the
// running test through GLCallLogTest::log().
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "backend_test.h"
#include "gl_device.h"
#include "gl_entry_points.h"

namespace janus::rhi::test {

struct GLCallLog {
    std::vector<std::string> calls;
    gl::GLFunctions original;
};

class GLCallLogTest : public BackendTest {
public:
    // The running test's log (only while one runs: replacements are in place only then).
    static GLCallLog& log() { return *s_log; }

protected:
    void SetUp() override {
        BackendTest::SetUp();
        if (IsSkipped() || HasFatalFailure()) return;   // configuration not selected: no device
        if (backend() == Backend::Vulkan) GTEST_SKIP() << "a GL backend test: " << watched();
        gl::GLFunctions& gl = dynamic_cast<gl::Device&>(device()).context().gl;
        s_log = &m_log;
        m_log.original = gl;
        watch(gl, m_overrides);
    }
    void TearDown() override {
        m_overrides.restoreAll();
        s_log = nullptr;
        BackendTest::TearDown();
    }
    // What the suite watches (said when it skips), and the replacements that log it.
    virtual const char* watched() const = 0;
    virtual void watch(gl::GLFunctions& gl, GLEntryPointOverrides& overrides) = 0;

    // The calls logged since the last take.
    std::vector<std::string> takeCalls() { return std::exchange(m_log.calls, {}); }

private:
    static inline GLCallLog* s_log = nullptr;
    GLEntryPointOverrides m_overrides;
    GLCallLog m_log;
};

}  // namespace janus::rhi::test
