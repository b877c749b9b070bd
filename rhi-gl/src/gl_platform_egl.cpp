// EGL on Mesa's surfaceless platform: no window system, no config, no surface. The context
// renders only into our own framebuffer objects.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <fmt/format.h>

#include <string_view>
#include <vector>

#include "gl_platform.h"
#include "janus/rhi/rhi.h"

namespace janus::rhi::gl {
namespace {

bool hasExtension(const char* list, std::string_view name) {
    if (!list) return false;
    std::string_view all(list);
    size_t pos = 0;
    while ((pos = all.find(name, pos)) != std::string_view::npos) {
        size_t end = pos + name.size();
        bool startsWord = pos == 0 || all[pos - 1] == ' ';
        bool endsWord = end == all.size() || all[end] == ' ';
        if (startsWord && endsWord) return true;
        pos = end;
    }
    return false;
}

[[noreturn]] void unavailable(const std::string& what) {
    throw Error(ErrorCode::BackendUnavailable, what);
}

class EglPlatform final : public Platform {
public:
    EglPlatform(GLApi api, bool debugContext) : m_api(api) {
        const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
        if (!hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless"))
            unavailable("EGL does not offer EGL_MESA_platform_surfaceless (needs Mesa's libEGL); "
                        "install libegl-mesa0 or use --gl-platform osmesa");
        auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
            eglGetProcAddress("eglGetPlatformDisplayEXT"));
        if (!getPlatformDisplay)
            unavailable("EGL lacks eglGetPlatformDisplayEXT (EGL_EXT_platform_base)");
        m_display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (m_display == EGL_NO_DISPLAY)
            unavailable(fmt::format("eglGetPlatformDisplayEXT(surfaceless) failed (EGL error 0x{:x})", eglGetError()));
        EGLint major = 0, minor = 0;
        if (!eglInitialize(m_display, &major, &minor))
            unavailable(fmt::format("eglInitialize on the surfaceless display failed (EGL error 0x{:x})", eglGetError()));

        const char* displayExtensions = eglQueryString(m_display, EGL_EXTENSIONS);
        if (!hasExtension(displayExtensions, "EGL_KHR_no_config_context") &&
            !hasExtension(displayExtensions, "EGL_MESA_configless_context"))
            unavailable("the EGL display cannot create a context without a config (EGL_KHR_no_config_context)");
        if (!hasExtension(displayExtensions, "EGL_KHR_surfaceless_context"))
            unavailable("the EGL display cannot make a context current without a surface (EGL_KHR_surfaceless_context)");

        bindApi();
        std::vector<EGLint> attribs;
        if (api == GLApi::DesktopCore43) {
            attribs = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 3,
                       EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT};
        } else {
            attribs = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 0};
        }
        if (debugContext) attribs.insert(attribs.end(), {EGL_CONTEXT_OPENGL_DEBUG, EGL_TRUE});
        attribs.push_back(EGL_NONE);
        m_context = eglCreateContext(m_display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs.data());
        if (m_context == EGL_NO_CONTEXT)
            unavailable(fmt::format("eglCreateContext for {} failed (EGL error 0x{:x}); the driver does not "
                                    "provide that API version",
                                    api == GLApi::DesktopCore43 ? "OpenGL 4.3 core" : "OpenGL ES 3.0",
                                    eglGetError()));
        try {
            makeCurrent();
        } catch (...) {
            eglDestroyContext(m_display, m_context);   // the destructor does not run for a throwing constructor
            throw;
        }
    }

    ~EglPlatform() override {
        // Only release our own context: another device's may be current on this thread (when ours
        // could not be made current at teardown), and that device still counts on it.
        if (eglGetCurrentContext() == m_context)
            eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(m_display, m_context);
        // No eglTerminate: the surfaceless display is shared by every device in the process, and
        // terminating it would destroy the other devices' contexts.
    }

    void makeCurrent() override {
        bindApi();
        if (!eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, m_context))
            throw Error(ErrorCode::DeviceLost,
                        fmt::format("eglMakeCurrent failed (EGL error 0x{:x})", eglGetError()));
    }

    void* getProcAddress(const char* name) const override {
        return reinterpret_cast<void*>(eglGetProcAddress(name));
    }

    std::string describe() const override { return "egl"; }

private:
    void bindApi() const {
        if (!eglBindAPI(m_api == GLApi::DesktopCore43 ? EGL_OPENGL_API : EGL_OPENGL_ES_API))
            unavailable(fmt::format("eglBindAPI({}) failed: this EGL has no {} support",
                                    m_api == GLApi::DesktopCore43 ? "EGL_OPENGL_API" : "EGL_OPENGL_ES_API",
                                    m_api == GLApi::DesktopCore43 ? "desktop OpenGL" : "OpenGL ES"));
    }

    GLApi m_api;
    EGLDisplay m_display = EGL_NO_DISPLAY;
    EGLContext m_context = EGL_NO_CONTEXT;
};

}  // namespace

std::unique_ptr<Platform> createEglPlatform(GLApi api, bool debugContext) {
    return std::make_unique<EglPlatform>(api, debugContext);
}

}  // namespace janus::rhi::gl
