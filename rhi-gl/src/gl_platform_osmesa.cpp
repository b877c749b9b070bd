// OSMesa: Mesa's off-screen desktop-GL context. It renders into a client buffer; ours is a 1x1
// dummy because every render pass targets a framebuffer object.
#include <GL/osmesa.h>

#include <fmt/format.h>

#include <array>

#include "gl_platform.h"
#include "janus/rhi/rhi.h"

namespace janus::rhi::gl {
namespace {

class OsmesaPlatform final : public Platform {
public:
    explicit OsmesaPlatform(bool /*debugContext: OSMesa has no context flags; KHR_debug still works*/) {
        const int attribs[] = {
            OSMESA_FORMAT, OSMESA_RGBA,
            OSMESA_DEPTH_BITS, 0,
            OSMESA_STENCIL_BITS, 0,
            OSMESA_ACCUM_BITS, 0,
            OSMESA_PROFILE, OSMESA_CORE_PROFILE,
            OSMESA_CONTEXT_MAJOR_VERSION, 4,
            OSMESA_CONTEXT_MINOR_VERSION, 3,
            0,
        };
        m_context = OSMesaCreateContextAttribs(attribs, nullptr);
        if (!m_context)
            throw Error(ErrorCode::BackendUnavailable,
                        "OSMesaCreateContextAttribs could not create an OpenGL 4.3 core context; "
                        "this OSMesa build lacks it (use --gl-platform egl)");
        makeCurrent();
    }

    ~OsmesaPlatform() override { OSMesaDestroyContext(m_context); }

    void makeCurrent() override {
        if (!OSMesaMakeCurrent(m_context, m_dummyPixel.data(), GL_UNSIGNED_BYTE, 1, 1))
            throw Error(ErrorCode::DeviceLost, "OSMesaMakeCurrent failed");
    }

    void* getProcAddress(const char* name) const override {
        return reinterpret_cast<void*>(OSMesaGetProcAddress(name));
    }

    std::string describe() const override { return "osmesa"; }

private:
    OSMesaContext m_context = nullptr;
    std::array<unsigned char, 4> m_dummyPixel{};
};

}  // namespace

std::unique_ptr<Platform> createOsmesaPlatform(GLApi api, bool debugContext) {
    if (api != GLApi::DesktopCore43)
        throw Error(ErrorCode::BackendUnavailable,
                    "OSMesa provides desktop OpenGL only, not OpenGL ES; use the EGL platform for gles");
    return std::make_unique<OsmesaPlatform>(debugContext);
}

}  // namespace janus::rhi::gl
