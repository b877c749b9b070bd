// For GL-only tests that watch or break what the backend calls: replaces entry points in a
// device's GLFunctions and puts each back (restoreAll, or on destruction), latest first.
#pragma once

#include <functional>
#include <vector>

namespace janus::rhi::test {

class GLEntryPointOverrides {
public:
    GLEntryPointOverrides() = default;
    GLEntryPointOverrides(const GLEntryPointOverrides&) = delete;
    GLEntryPointOverrides& operator=(const GLEntryPointOverrides&) = delete;
    ~GLEntryPointOverrides() { restoreAll(); }

    // Points `slot` at `replacement`; returns what it pointed at, for the replacement to call.
    template <class Function>
    Function replace(Function& slot, Function replacement) {
        const Function original = slot;
        m_restore.push_back([&slot, original] { slot = original; });
        slot = replacement;
        return original;
    }
    void restoreAll() {
        for (auto it = m_restore.rbegin(); it != m_restore.rend(); ++it) (*it)();
        m_restore.clear();
    }

private:
    std::vector<std::function<void()>> m_restore;
};

}  // namespace janus::rhi::test
