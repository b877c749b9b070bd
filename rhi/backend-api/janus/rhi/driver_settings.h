// Settings Janus asks drivers for through their environment variables, before any device starts
// (rhi/src/driver_settings.cpp says which and why).
#pragma once

#include <string>

namespace janus::rhi::detail {

// NVIDIA's GL driver filters textures by its "image settings" (__GL_OpenGLImageSettings).
struct GLImageSettings {
    std::string value;         // what the variable holds for this process's drivers
    bool setByJanus = false;   // false: the environment had it, and it was left alone
};

// What to use given the variable's value at start (null or empty: unset). Pure; for the tests.
GLImageSettings chooseGLImageSettings(const char* environmentValue);

// Once per process, before the first device of any backend starts; later calls return the
// first call's result.
const GLImageSettings& requestDriverSettings();

// DeviceInfo::driverSettings of a GL device whose GL_VENDOR is `vendor`: the image settings on
// NVIDIA, empty elsewhere.
std::string glDriverSettingsNote(const std::string& vendor);

}  // namespace janus::rhi::detail
