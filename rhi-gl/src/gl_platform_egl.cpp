// EGL without a window system: no config, no surface; the context renders only into our own
// framebuffer objects. Three kinds of display can give such a context (gl_platform.h): Mesa's
// surfaceless platform, an EGL device (EGL_EXT_platform_device), or the default display.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <string_view>
#include <system_error>
#include <vector>

#include "gl_platform.h"
#include "janus/rhi/backends.h"
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

std::string lastEglError() { return fmt::format("EGL error 0x{:x}", eglGetError()); }

const char* clientExtensions() {
    // EGL_EXT_client_extensions: without it this query fails and returns null (no client extensions).
    return eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
}

template <typename Function>
Function requireEntryPoint(const char* name, const char* extension) {
    auto function = reinterpret_cast<Function>(eglGetProcAddress(name));
    if (!function) unavailable(fmt::format("EGL lacks {} ({})", name, extension));
    return function;
}

class EglPlatform final : public Platform {
public:
    // `display` is initialised; the platform never terminates it (see the destructor).
    EglPlatform(EGLDisplay display, std::string description, GLApi api, bool debugContext)
        : m_api(api), m_display(display), m_description(std::move(description)) {
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
            unavailable(fmt::format("eglCreateContext for {} failed ({}); the driver does not provide that API version",
                                    api == GLApi::DesktopCore43 ? "OpenGL 4.3 core" : "OpenGL ES 3.0",
                                    lastEglError()));
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
        // No eglTerminate: a display is one per process for its platform and native display, shared
        // by every device on it, and terminating it would destroy the other devices' contexts.
    }

    void makeCurrent() override {
        bindApi();
        if (!eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, m_context))
            throw Error(ErrorCode::DeviceLost, fmt::format("eglMakeCurrent failed ({})", lastEglError()));
    }

    void releaseCurrent() noexcept override {
        // eglMakeCurrent(EGL_NO_CONTEXT) releases the current context of the bound API.
        if (!eglBindAPI(m_api == GLApi::DesktopCore43 ? EGL_OPENGL_API : EGL_OPENGL_ES_API)) return;
        if (eglGetCurrentContext() == m_context) eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }

    void* getProcAddress(const char* name) const override {
        return reinterpret_cast<void*>(eglGetProcAddress(name));
    }

    std::string describe() const override { return m_description; }

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
    std::string m_description;
};

void initialize(EGLDisplay display, std::string_view which) {
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor))
        unavailable(fmt::format("eglInitialize on the {} failed ({})", which, lastEglError()));
}

// --- Mesa's surfaceless platform ---------------------------------------------------------------

std::unique_ptr<Platform> startSurfaceless(GLApi api, bool debugContext) {
    const char* client = clientExtensions();
    if (!hasExtension(client, "EGL_MESA_platform_surfaceless"))
        unavailable("EGL does not offer EGL_MESA_platform_surfaceless (Mesa's libEGL has it: install libegl-mesa0)");
    auto getPlatformDisplay =
        requireEntryPoint<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT", "EGL_EXT_platform_base");
    EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY)
        unavailable(fmt::format("eglGetPlatformDisplayEXT(surfaceless) failed ({})", lastEglError()));
    initialize(display, "surfaceless display");
    return std::make_unique<EglPlatform>(display, "egl (surfaceless)", api, debugContext);
}

// --- EGL devices ---------------------------------------------------------------------------------

// What `janus info` calls the device: its DRM node where it has one, else the display's vendor.
std::string deviceLabel(EGLDeviceEXT device, EGLDisplay display, PFNEGLQUERYDEVICESTRINGEXTPROC queryDeviceString) {
    const char* deviceExtensions = queryDeviceString(device, EGL_EXTENSIONS);
    if (hasExtension(deviceExtensions, "EGL_EXT_device_drm"))
        if (const char* file = queryDeviceString(device, EGL_DRM_DEVICE_FILE_EXT)) return file;
    // Mesa's software device lists the render-node extension but has no node (null).
    if (hasExtension(deviceExtensions, "EGL_EXT_device_drm_render_node"))
        if (const char* node = queryDeviceString(device, EGL_DRM_RENDER_NODE_FILE_EXT)) return node;
    const char* vendor = eglQueryString(display, EGL_VENDOR);
    std::string label = vendor && *vendor ? vendor : "unknown vendor";
    if (hasExtension(deviceExtensions, "EGL_MESA_device_software")) label += " software renderer";
    return label;
}

// What JANUS_EGL_DEVICE may call the device (eglDeviceNamed).
std::vector<std::string> deviceNames(EGLDeviceEXT device, PFNEGLQUERYDEVICESTRINGEXTPROC queryDeviceString) {
    std::vector<std::string> names;
    const char* deviceExtensions = queryDeviceString(device, EGL_EXTENSIONS);
    auto addFile = [&](const char* file) {
        if (!file || !*file) return;
        const std::string path = file;
        names.push_back(path);
        if (const size_t slash = path.rfind('/'); slash != std::string::npos && slash + 1 < path.size())
            names.push_back(path.substr(slash + 1));
    };
    if (hasExtension(deviceExtensions, "EGL_EXT_device_drm")) addFile(queryDeviceString(device, EGL_DRM_DEVICE_FILE_EXT));
    if (hasExtension(deviceExtensions, "EGL_EXT_device_drm_render_node"))
        addFile(queryDeviceString(device, EGL_DRM_RENDER_NODE_FILE_EXT));
    if (hasExtension(deviceExtensions, "EGL_MESA_device_software")) names.emplace_back("software");
    return names;
}

// "0 (/dev/dri/card0, /dev/dri/renderD128), 1 (software)": the list a failed choice by name shows
// (each path once; its file name alone also matches).
std::string describeDeviceNames(const std::vector<std::vector<std::string>>& namesPerDevice) {
    std::string text;
    for (size_t i = 0; i < namesPerDevice.size(); ++i) {
        std::string names;
        for (const std::string& name : namesPerDevice[i]) {
            if (name.find('/') == std::string::npos && !names.empty()) continue;   // a path's short form
            names += fmt::format("{}{}", names.empty() ? "" : ", ", name);
        }
        text += fmt::format("{}{} ({})", i == 0 ? "" : ", ", i, names.empty() ? "no name: use the index" : names);
    }
    return text;
}

// The devices EGL can open displays on, in eglQueryDevicesEXT's order. Throws BackendUnavailable
// saying what EGL lacks.
struct EglDevices {
    std::vector<EGLDeviceEXT> devices;
    PFNEGLQUERYDEVICESTRINGEXTPROC queryDeviceString = nullptr;
};
EglDevices enumerateDevices() {
    const char* client = clientExtensions();
    const bool enumeration =
        hasExtension(client, "EGL_EXT_device_enumeration") || hasExtension(client, "EGL_EXT_device_base");
    if (!enumeration || !hasExtension(client, "EGL_EXT_platform_device"))
        unavailable("EGL does not offer EGL device displays (EGL_EXT_device_enumeration and EGL_EXT_platform_device)");
    auto queryDevices = requireEntryPoint<PFNEGLQUERYDEVICESEXTPROC>("eglQueryDevicesEXT", "EGL_EXT_device_enumeration");
    EglDevices result;
    result.queryDeviceString =
        requireEntryPoint<PFNEGLQUERYDEVICESTRINGEXTPROC>("eglQueryDeviceStringEXT", "EGL_EXT_device_query");
    EGLint count = 0;
    if (!queryDevices(0, nullptr, &count))
        unavailable(fmt::format("eglQueryDevicesEXT failed ({})", lastEglError()));
    result.devices.resize(size_t(std::max(count, 0)));
    if (count > 0 && !queryDevices(count, result.devices.data(), &count))
        unavailable(fmt::format("eglQueryDevicesEXT failed ({})", lastEglError()));
    result.devices.resize(size_t(std::max(count, 0)));
    return result;
}

std::unique_ptr<Platform> startOnDevice(GLApi api, bool debugContext, std::optional<uint32_t> deviceIndex,
                                        const std::string& deviceName = {}) {
    const EglDevices found = enumerateDevices();
    const std::vector<EGLDeviceEXT>& devices = found.devices;
    const PFNEGLQUERYDEVICESTRINGEXTPROC queryDeviceString = found.queryDeviceString;
    auto getPlatformDisplay =
        requireEntryPoint<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT", "EGL_EXT_platform_base");
    if (devices.empty()) unavailable("EGL lists no devices (eglQueryDevicesEXT)");
    if (!deviceName.empty()) {
        std::vector<std::vector<std::string>> names;
        for (EGLDeviceEXT device : devices) names.push_back(deviceNames(device, queryDeviceString));
        deviceIndex = eglDeviceNamed(names, deviceName);
        if (!deviceIndex)
            unavailable(fmt::format("JANUS_EGL_DEVICE='{}' names no EGL device; EGL lists {} device{}, by index "
                                    "and names: {}",
                                    deviceName, names.size(), names.size() == 1 ? "" : "s", describeDeviceNames(names)));
    }
    if (deviceIndex && *deviceIndex >= devices.size())
        unavailable(fmt::format("JANUS_EGL_DEVICE={} but EGL lists {} device{} (indices 0..{})", *deviceIndex,
                                devices.size(), devices.size() == 1 ? "" : "s", devices.size() - 1));

    auto startOn = [&](uint32_t index) -> std::unique_ptr<Platform> {
        EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[index], nullptr);
        if (display == EGL_NO_DISPLAY)
            unavailable(fmt::format("eglGetPlatformDisplayEXT(device {}) failed ({})", index, lastEglError()));
        initialize(display, fmt::format("display of EGL device {}", index));
        return std::make_unique<EglPlatform>(
            display, fmt::format("egl (device {}: {})", index, deviceLabel(devices[index], display, queryDeviceString)),
            api, debugContext);
    };
    if (deviceIndex) return startOn(*deviceIndex);

    // No index asked for: the first device that gives a context (a machine may list a device
    // whose driver cannot do this API, e.g. a display-only one).
    std::string failures;
    for (uint32_t index = 0; index < devices.size(); ++index) {
        try {
            return startOn(index);
        } catch (const Error& e) {
            failures += fmt::format("{}device {}: {}", failures.empty() ? "" : "; ", index, e.what());
        }
    }
    unavailable(fmt::format("no EGL device gave a context ({})", failures));
}

// --- the default display -------------------------------------------------------------------------

std::unique_ptr<Platform> startOnDefaultDisplay(GLApi api, bool debugContext) {
    EGLDisplay display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    if (display == EGL_NO_DISPLAY) unavailable(fmt::format("eglGetDisplay(EGL_DEFAULT_DISPLAY) failed ({})", lastEglError()));
    initialize(display, "default display");
    return std::make_unique<EglPlatform>(display, "egl (default display)", api, debugContext);
}

}  // namespace

EglOptions parseEglOptions(const char* platformVariable, const char* deviceVariable) {
    EglOptions options;
    const std::string_view platform = platformVariable ? platformVariable : "";
    if (platform == "surfaceless") options.display = EglDisplayKind::Surfaceless;
    else if (platform == "device") options.display = EglDisplayKind::Device;
    else if (platform == "default") options.display = EglDisplayKind::Default;
    else if (!platform.empty())
        unavailable(fmt::format("JANUS_EGL_PLATFORM='{}' is not an EGL platform; use surfaceless, device or "
                                "default, or unset it to try them in that order",
                                platform));

    const std::string_view device = deviceVariable ? deviceVariable : "";
    if (device.empty()) return options;
    if (options.display != EglDisplayKind::Automatic && options.display != EglDisplayKind::Device)
        unavailable(fmt::format("JANUS_EGL_DEVICE={} picks an EGL device, but JANUS_EGL_PLATFORM={} asks for "
                                "another display; unset one of them",
                                device, platform));
    options.display = EglDisplayKind::Device;
    const bool digits = std::all_of(device.begin(), device.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (!digits) {
        options.deviceName = device;   // whether a device has it, only the device list can say
        return options;
    }
    uint32_t index = 0;
    const auto [end, error] = std::from_chars(device.data(), device.data() + device.size(), index);
    if (error != std::errc() || end != device.data() + device.size())
        unavailable(fmt::format("JANUS_EGL_DEVICE='{}' is not a device index (0, 1, ...)", device));
    options.deviceIndex = index;
    return options;
}

std::vector<EglDeviceListing> listEglDevices() {
    std::vector<EglDeviceListing> listing;
    try {
        const EglDevices found = enumerateDevices();
        for (size_t i = 0; i < found.devices.size(); ++i)
            listing.push_back({uint32_t(i), deviceNames(found.devices[i], found.queryDeviceString)});
    } catch (const Error&) {
        return {};   // no device enumeration: nothing to choose from
    }
    return listing;
}

std::optional<uint32_t> eglDeviceNamed(const std::vector<std::vector<std::string>>& namesPerDevice,
                                       std::string_view wanted) {
    for (size_t i = 0; i < namesPerDevice.size(); ++i)
        for (const std::string& name : namesPerDevice[i])
            if (name == wanted) return uint32_t(i);
    return std::nullopt;
}

EglOptions eglOptionsFromEnvironment() {
    return parseEglOptions(std::getenv("JANUS_EGL_PLATFORM"), std::getenv("JANUS_EGL_DEVICE"));
}

std::unique_ptr<Platform> createEglPlatform(GLApi api, bool debugContext, const EglOptions& options) {
    switch (options.display) {
        case EglDisplayKind::Surfaceless: return startSurfaceless(api, debugContext);
        case EglDisplayKind::Device: return startOnDevice(api, debugContext, options.deviceIndex, options.deviceName);
        case EglDisplayKind::Default: return startOnDefaultDisplay(api, debugContext);
        case EglDisplayKind::Automatic: break;
    }
    // Surfaceless first: on Mesa it is what has always been used, and it needs no GPU.
    std::string failures;
    auto attempt = [&](const char* which, auto start) -> std::unique_ptr<Platform> {
        try {
            return start(api, debugContext);
        } catch (const Error& e) {
            failures += fmt::format("{}{}: {}", failures.empty() ? "" : "; ", which, e.what());
            return nullptr;
        }
    };
    if (auto platform = attempt("surfaceless", startSurfaceless)) return platform;
    if (auto platform = attempt("device", [](GLApi a, bool d) { return startOnDevice(a, d, std::nullopt); }))
        return platform;
    if (auto platform = attempt("default display", startOnDefaultDisplay)) return platform;
    unavailable(fmt::format("no EGL display gave a context ({}); or use --gl-platform osmesa", failures));
}

}  // namespace janus::rhi::gl
