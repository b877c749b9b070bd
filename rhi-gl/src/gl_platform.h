// How the GL backend gets a context: a small interface over EGL and OSMesa, so the rest of the
// backend never touches a window-system API.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace janus::rhi::gl {

enum class GLApi { DesktopCore43, ES30 };

class Platform {
public:
    virtual ~Platform() = default;
    // Binds this platform's context to the calling thread. Throws Error(DeviceLost) when the
    // window-system layer refuses (e.g. it was shut down before us at process exit).
    virtual void makeCurrent() = 0;
    // Unbinds this platform's context from the calling thread, where it is current, so that
    // another thread can make it current (a context is current on at most one thread).
    virtual void releaseCurrent() noexcept = 0;
    // Any GL entry point (core or extension), or null when the context does not export it.
    virtual void* getProcAddress(const char* name) const = 0;
    // DeviceInfo::platform: "osmesa", or "egl (<display>)" naming the EGL display it runs on:
    // "egl (surfaceless)", "egl (device 0: /dev/dri/renderD128)", "egl (default display)".
    virtual std::string describe() const = 0;
};

// ---------------------------------------------------------------------------------------------
// EGL

// Which EGL display the context comes from. Automatic tries them in this order and takes the
// first on which a context of the requested API starts:
//  - Surfaceless: Mesa's EGL_MESA_platform_surfaceless (no window system, no GPU needed);
//  - Device: EGL_EXT_device_enumeration + EGL_EXT_platform_device, one display per GPU (what
//    drivers without the Mesa platform offer, e.g. NVIDIA's headless EGL);
//  - Default: eglGetDisplay(EGL_DEFAULT_DISPLAY), used surfaceless.
enum class EglDisplayKind { Automatic, Surfaceless, Device, Default };

struct EglOptions {
    EglDisplayKind display = EglDisplayKind::Automatic;
    // Device only: the index into eglQueryDevicesEXT's list, or else a name of the device (see
    // eglDeviceNamed). Neither: the first device that starts.
    std::optional<uint32_t> deviceIndex;
    std::string deviceName;
};

// JANUS_EGL_PLATFORM (surfaceless | device | default; unset or empty: automatic) and
// JANUS_EGL_DEVICE (an index, or a device's name; implies the device display). Null means unset.
// Throws Error(BackendUnavailable) for a value it does not understand, naming the variable.
EglOptions parseEglOptions(const char* platformVariable, const char* deviceVariable);
EglOptions eglOptionsFromEnvironment();

// The names an EGL device answers to in JANUS_EGL_DEVICE: its DRM device file and render node,
// whole or without their folder ("/dev/dri/card1", "card1", "/dev/dri/renderD128", "renderD128"),
// and "software" for Mesa's software renderer (EGL_MESA_device_software), which has no node.
// Returns the index of the first device in `namesPerDevice` (eglQueryDevicesEXT's order) that has
// `wanted` among its names.
std::optional<uint32_t> eglDeviceNamed(const std::vector<std::vector<std::string>>& namesPerDevice,
                                       std::string_view wanted);

// Throws Error(BackendUnavailable) saying what is missing; with Automatic, what each display said.
std::unique_ptr<Platform> createEglPlatform(GLApi api, bool debugContext, const EglOptions& options);

// ---------------------------------------------------------------------------------------------
// OSMesa

// libOSMesa is loaded at run time (dlopen), so the backend starts without it; these are the
// names tried, in order (the versioned one is what the runtime package installs).
inline constexpr const char* kOsmesaLibraryNames[] = {"libOSMesa.so.8", "libOSMesa.so"};

// The OSMesa entry points the platform calls (signatures of Mesa's GL/osmesa.h, whose ABI has
// not changed since Mesa 10; declared here so the build needs no OSMesa package either), from a
// library that stays loaded until exit: GL entry points handed out by it must stay valid for as
// long as any context might be used, static destructors included.
struct OsmesaContextRecord;   // Mesa's struct osmesa_context, never looked into
using OsmesaContext = OsmesaContextRecord*;
struct OsmesaEntryPoints {
    OsmesaContext (*createContextAttribs)(const int* attribList, OsmesaContext sharedContext) = nullptr;
    void (*destroyContext)(OsmesaContext context) = nullptr;
    unsigned char (*makeCurrent)(OsmesaContext context, void* buffer, unsigned type, int width, int height) = nullptr;
    OsmesaContext (*getCurrentContext)() = nullptr;
    void (*(*getProcAddress)(const char* name))() = nullptr;
    std::string libraryName;   // the name that loaded
};

// Loads the first of `libraryNames` that dlopen finds and looks up the entry points. Throws
// Error(BackendUnavailable): "OSMesa is not installed (<each dlerror>); install libosmesa6 or
// use --gl-platform egl" when none loads, or names the entry point a library lacks.
OsmesaEntryPoints loadOsmesa(std::span<const char* const> libraryNames);

// Throws Error(BackendUnavailable) for GLES (OSMesa is desktop GL only), when OSMesa is not
// installed, or when it cannot create a 4.3 core context.
std::unique_ptr<Platform> createOsmesaPlatform(GLApi api, bool debugContext);

}  // namespace janus::rhi::gl
