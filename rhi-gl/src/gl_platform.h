// How the GL backend gets a context: a small interface over EGL (surfaceless) and OSMesa, so the
// rest of the backend never touches a window-system API.
#pragma once

#include <memory>
#include <string>

namespace janus::rhi::gl {

enum class GLApi { DesktopCore43, ES30 };

class Platform {
public:
    virtual ~Platform() = default;
    // Binds this platform's context to the calling thread.
    virtual void makeCurrent() = 0;
    // Any GL entry point (core or extension), or null when the context does not export it.
    virtual void* getProcAddress(const char* name) const = 0;
    // "egl" or "osmesa" (DeviceInfo::platform).
    virtual std::string describe() const = 0;
};

// Both throw Error(BackendUnavailable) saying what is missing.
std::unique_ptr<Platform> createEglPlatform(GLApi api, bool debugContext);
std::unique_ptr<Platform> createOsmesaPlatform(GLApi api, bool debugContext);

}  // namespace janus::rhi::gl
