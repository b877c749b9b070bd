// OSMesa: Mesa's off-screen desktop-GL context. It renders into a client buffer; ours is a 1x1
// dummy because every render pass targets a framebuffer object.
//
// libOSMesa is opened with dlopen when the platform is asked for, not linked: it pulls in LLVM,
// and machines with a hardware driver rarely have it, so a link-time dependency would stop
// `janus` from starting at all there (tests/CMakeLists.txt checks that no binary needs it).
#include <dlfcn.h>

#include <fmt/format.h>

#include <array>
#include <type_traits>
#include <utility>

#include "gl_platform.h"
#include "janus/rhi/rhi.h"

namespace janus::rhi::gl {
namespace {

// Values from Mesa's GL/osmesa.h (and GL's tokens for the two it borrows).
constexpr int kOsmesaFormat = 0x22;
constexpr int kOsmesaRgba = 0x1908;   // GL_RGBA
constexpr int kOsmesaDepthBits = 0x30;
constexpr int kOsmesaStencilBits = 0x31;
constexpr int kOsmesaAccumBits = 0x32;
constexpr int kOsmesaProfile = 0x33;
constexpr int kOsmesaCoreProfile = 0x34;
constexpr int kOsmesaContextMajorVersion = 0x36;
constexpr int kOsmesaContextMinorVersion = 0x37;
constexpr unsigned kGLUnsignedByte = 0x1401;   // GL_UNSIGNED_BYTE

class OsmesaPlatform final : public Platform {
public:
    OsmesaPlatform(OsmesaEntryPoints osmesa, bool /*debugContext: OSMesa has no context flags; KHR_debug still works*/)
        : m_osmesa(std::move(osmesa)) {
        const int attribs[] = {
            kOsmesaFormat, kOsmesaRgba,
            kOsmesaDepthBits, 0,
            kOsmesaStencilBits, 0,
            kOsmesaAccumBits, 0,
            kOsmesaProfile, kOsmesaCoreProfile,
            kOsmesaContextMajorVersion, 4,
            kOsmesaContextMinorVersion, 3,
            0,
        };
        m_context = m_osmesa.createContextAttribs(attribs, nullptr);
        if (!m_context)
            throw Error(ErrorCode::BackendUnavailable,
                        fmt::format("OSMesaCreateContextAttribs ({}) could not create an OpenGL 4.3 core "
                                    "context; this OSMesa build lacks it (use --gl-platform egl)",
                                    m_osmesa.libraryName));
        makeCurrent();
    }

    ~OsmesaPlatform() override { m_osmesa.destroyContext(m_context); }

    void makeCurrent() override {
        if (!m_osmesa.makeCurrent(m_context, m_dummyPixel.data(), kGLUnsignedByte, 1, 1))
            throw Error(ErrorCode::DeviceLost, "OSMesaMakeCurrent failed");
    }

    void releaseCurrent() noexcept override {
        if (m_osmesa.getCurrentContext() != m_context) return;
        m_osmesa.makeCurrent(nullptr, nullptr, 0, 0, 0);   // all null: no context on this thread
    }

    void* getProcAddress(const char* name) const override {
        return reinterpret_cast<void*>(m_osmesa.getProcAddress(name));
    }

    std::string describe() const override { return "osmesa"; }

private:
    OsmesaEntryPoints m_osmesa;
    OsmesaContext m_context = nullptr;
    std::array<unsigned char, 4> m_dummyPixel{};
};

}  // namespace

OsmesaEntryPoints loadOsmesa(std::span<const char* const> libraryNames) {
    std::string failures;
    void* library = nullptr;
    OsmesaEntryPoints entryPoints;
    for (const char* name : libraryNames) {
        // RTLD_LOCAL: libOSMesa exports its own gl* symbols, which must not stand in for libEGL's.
        library = dlopen(name, RTLD_NOW | RTLD_LOCAL);
        if (library) {
            entryPoints.libraryName = name;
            break;
        }
        const char* reason = dlerror();
        if (!failures.empty()) failures += "; ";
        failures += reason ? std::string(reason) : fmt::format("{}: not found", name);
    }
    if (!library)
        throw Error(ErrorCode::BackendUnavailable,
                    fmt::format("OSMesa is not installed ({}); install libosmesa6 or use --gl-platform egl", failures));
    // Never dlclose'd: contexts, and the GL entry points they handed out, may be used (and are
    // destroyed) until the process exits. dlopen counts references, so loading again is cheap.

    auto lookUp = [&](auto& entryPoint, const char* symbol) {
        void* address = dlsym(library, symbol);
        if (!address)
            throw Error(ErrorCode::BackendUnavailable,
                        fmt::format("{} does not export {}, so it is no usable OSMesa (Mesa 10 or newer); "
                                    "install libosmesa6 or use --gl-platform egl",
                                    entryPoints.libraryName, symbol));
        entryPoint = reinterpret_cast<std::remove_reference_t<decltype(entryPoint)>>(address);
    };
    lookUp(entryPoints.createContextAttribs, "OSMesaCreateContextAttribs");
    lookUp(entryPoints.destroyContext, "OSMesaDestroyContext");
    lookUp(entryPoints.makeCurrent, "OSMesaMakeCurrent");
    lookUp(entryPoints.getCurrentContext, "OSMesaGetCurrentContext");
    lookUp(entryPoints.getProcAddress, "OSMesaGetProcAddress");
    return entryPoints;
}

std::unique_ptr<Platform> createOsmesaPlatform(GLApi api, bool debugContext) {
    if (api != GLApi::DesktopCore43)
        throw Error(ErrorCode::BackendUnavailable,
                    "OSMesa provides desktop OpenGL only, not OpenGL ES; use the EGL platform for gles");
    return std::make_unique<OsmesaPlatform>(loadOsmesa(kOsmesaLibraryNames), debugContext);
}

}  // namespace janus::rhi::gl
