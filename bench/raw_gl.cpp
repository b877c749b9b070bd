// The raw GL side: its own EGL context (OpenGL 4.3 core or OpenGL ES 3.0) on the display the RHI's
// GL backend would choose (rhi-gl's createEglPlatform: surfaceless, then EGL devices, then the
// default display; JANUS_EGL_PLATFORM / JANUS_EGL_DEVICE apply to both sides alike), and the
// calls a hand-written renderer makes for the same workload: state set once per frame, then
// glBindBufferRange + glDrawArrays (or glDispatchCompute) per operation.
//
// The program is compiled from the GLSL/ESSL the RHI's GL backend produced for the same SPIR-V
// (IShader::translatedSource()), so both sides run the identical shaders.
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>
#include <fmt/format.h>

#include <cstdio>
#include <cstring>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "gl_debug_policy.h"
#include "gl_platform.h"
#include "null_driver.h"
#include "rhi_scene.h"

namespace janus::bench {
namespace {

// The GL entry points this file uses, loaded through EGL from whichever context is current.
struct GLCalls {
#define JANUS_BENCH_GL_CALLS(X)                                                                              \
    X(PFNGLGETERRORPROC, glGetError)                                                                         \
    X(PFNGLGENBUFFERSPROC, glGenBuffers)                                                                     \
    X(PFNGLDELETEBUFFERSPROC, glDeleteBuffers)                                                               \
    X(PFNGLBINDBUFFERPROC, glBindBuffer)                                                                     \
    X(PFNGLBUFFERDATAPROC, glBufferData)                                                                     \
    X(PFNGLBUFFERSUBDATAPROC, glBufferSubData)                                                               \
    X(PFNGLMAPBUFFERRANGEPROC, glMapBufferRange)                                                             \
    X(PFNGLUNMAPBUFFERPROC, glUnmapBuffer)                                                                   \
    X(PFNGLBINDBUFFERRANGEPROC, glBindBufferRange)                                                           \
    X(PFNGLGENVERTEXARRAYSPROC, glGenVertexArrays)                                                           \
    X(PFNGLDELETEVERTEXARRAYSPROC, glDeleteVertexArrays)                                                     \
    X(PFNGLBINDVERTEXARRAYPROC, glBindVertexArray)                                                           \
    X(PFNGLVERTEXATTRIBPOINTERPROC, glVertexAttribPointer)                                                   \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, glEnableVertexAttribArray)                                           \
    X(PFNGLVERTEXATTRIBDIVISORPROC, glVertexAttribDivisor)                                                   \
    X(PFNGLCREATESHADERPROC, glCreateShader)                                                                 \
    X(PFNGLDELETESHADERPROC, glDeleteShader)                                                                 \
    X(PFNGLSHADERSOURCEPROC, glShaderSource)                                                                 \
    X(PFNGLCOMPILESHADERPROC, glCompileShader)                                                               \
    X(PFNGLGETSHADERIVPROC, glGetShaderiv)                                                                   \
    X(PFNGLGETSHADERINFOLOGPROC, glGetShaderInfoLog)                                                         \
    X(PFNGLCREATEPROGRAMPROC, glCreateProgram)                                                               \
    X(PFNGLDELETEPROGRAMPROC, glDeleteProgram)                                                               \
    X(PFNGLATTACHSHADERPROC, glAttachShader)                                                                 \
    X(PFNGLLINKPROGRAMPROC, glLinkProgram)                                                                   \
    X(PFNGLGETPROGRAMIVPROC, glGetProgramiv)                                                                 \
    X(PFNGLGETPROGRAMINFOLOGPROC, glGetProgramInfoLog)                                                       \
    X(PFNGLUSEPROGRAMPROC, glUseProgram)                                                                     \
    X(PFNGLUNIFORMBLOCKBINDINGPROC, glUniformBlockBinding)                                                   \
    X(PFNGLGENTEXTURESPROC, glGenTextures)                                                                   \
    X(PFNGLDELETETEXTURESPROC, glDeleteTextures)                                                             \
    X(PFNGLBINDTEXTUREPROC, glBindTexture)                                                                   \
    X(PFNGLTEXSTORAGE2DPROC, glTexStorage2D)                                                                 \
    X(PFNGLGENFRAMEBUFFERSPROC, glGenFramebuffers)                                                           \
    X(PFNGLDELETEFRAMEBUFFERSPROC, glDeleteFramebuffers)                                                     \
    X(PFNGLBINDFRAMEBUFFERPROC, glBindFramebuffer)                                                           \
    X(PFNGLFRAMEBUFFERTEXTURE2DPROC, glFramebufferTexture2D)                                                 \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, glCheckFramebufferStatus)                                             \
    X(PFNGLVIEWPORTPROC, glViewport)                                                                         \
    X(PFNGLENABLEPROC, glEnable)                                                                             \
    X(PFNGLSCISSORPROC, glScissor)                                                                           \
    X(PFNGLCLEARBUFFERFVPROC, glClearBufferfv)                                                               \
    X(PFNGLDRAWARRAYSPROC, glDrawArrays)                                                                     \
    X(PFNGLREADPIXELSPROC, glReadPixels)                                                                     \
    X(PFNGLFINISHPROC, glFinish)
#define JANUS_BENCH_GL_COMPUTE_CALLS(X)                                                                      \
    X(PFNGLDISPATCHCOMPUTEPROC, glDispatchCompute)                                                           \
    X(PFNGLMEMORYBARRIERPROC, glMemoryBarrier)
#define JANUS_BENCH_DECLARE(type, name) type name = nullptr;
    JANUS_BENCH_GL_CALLS(JANUS_BENCH_DECLARE)
    JANUS_BENCH_GL_COMPUTE_CALLS(JANUS_BENCH_DECLARE)
#undef JANUS_BENCH_DECLARE

    void load(bool withCompute) {
        auto resolve = [](auto& pointer, const char* name) {
            pointer = reinterpret_cast<std::remove_reference_t<decltype(pointer)>>(eglGetProcAddress(name));
            if (!pointer) throw std::runtime_error(fmt::format("raw GL: eglGetProcAddress({}) returned nothing", name));
        };
#define JANUS_BENCH_LOAD(type, name) resolve(name, #name);
        JANUS_BENCH_GL_CALLS(JANUS_BENCH_LOAD)
        if (withCompute) {
            JANUS_BENCH_GL_COMPUTE_CALLS(JANUS_BENCH_LOAD)
        }
#undef JANUS_BENCH_LOAD
    }
};

// The RHI's GL backend remembers which of its contexts is current and skips eglMakeCurrent when
// it believes nothing changed, so the raw side must hand back exactly what was current.
class ContextSwitch {
public:
    // Makes `platform`'s context current; null only saves and restores (around starting one,
    // which makes its context current).
    explicit ContextSwitch(rhi::gl::Platform* platform)
        : m_api(eglQueryAPI()), m_display(eglGetCurrentDisplay()), m_context(eglGetCurrentContext()) {
        if (platform) platform->makeCurrent();
    }
    ~ContextSwitch() {
        eglBindAPI(m_api);
        if (m_context != EGL_NO_CONTEXT) eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, m_context);
    }
    ContextSwitch(const ContextSwitch&) = delete;
    ContextSwitch& operator=(const ContextSwitch&) = delete;

private:
    EGLenum m_api;
    EGLDisplay m_display;
    EGLContext m_context;
};

class RawGL : public Environment {
public:
    explicit RawGL(rhi::Backend backend);
    ~RawGL() override;

    // The raw context is current while the returned object lives.
    ContextSwitch makeCurrent() const { return ContextSwitch(m_platform.get()); }
    // The same, held by whoever keeps the pointer (FrameSide::enter).
    std::shared_ptr<void> currentWhileHeld() const { return std::make_shared<ContextSwitch>(m_platform.get()); }
    GLCalls& calls() { return m_gl; }

    void submitDraws(RawGLDraws how = RawGLDraws::Plain);
    // A paired side's frames: GL binds a range per draw (glBindBufferRange at the slice's offset)
    // whichever way the RHI side gives each draw its slice, so both are the plain frames.
    void submitDraws(DrawSlices) { submitDraws(RawGLDraws::Plain); }
    void submitDispatches();
    void finish() { m_gl.glFinish(); }
    void checkDraws();
    void checkDispatches();
    bool hasCompute() const { return m_computeProgram != 0; }
    // With validation on, the driver's debug output (as the RHI's GL backend classifies it,
    // gl_debug_policy.h): errors fail the check after the frames; performance messages are
    // taken here.
    std::vector<std::string> takePerformanceMessages() { return std::exchange(m_performanceMessages, {}); }

private:
    static void APIENTRY onDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                                        const GLchar* message, const void* self);
    void setUpDebugOutput();
    void checkDebugMessages(const char* when);
    void createContext();
    GLuint compileProgram(const std::vector<std::pair<GLenum, std::string>>& stages);
    // A buffer with `data`, made as the RHI's GL backend makes one (rhi-gl/src/gl_buffer.cpp).
    GLuint createBufferAsRhi(const void* data, size_t size);
    GLuint createVertexArray(GLuint vertices);
    void checkNoError(const char* when);

    rhi::Backend m_backend;
    bool m_es;
    // Before the context: destroying it may still call onDebugMessage, which writes here.
    std::vector<std::string> m_debugMessages, m_performanceMessages;
    std::unique_ptr<rhi::gl::Platform> m_platform;   // the context
    GLCalls m_gl;

    GLuint m_target = 0, m_framebuffer = 0, m_vertices = 0, m_vertexArray = 0, m_drawParameters = 0;
    GLuint m_rhiVertices = 0, m_rhiVertexArray = 0, m_rhiDrawParameters = 0;   // RawGLDraws::RhiBuffers
    GLuint m_drawProgram = 0;
    GLuint m_counters = 0, m_computeProgram = 0;
    uint32_t m_dispatchFrames = 0;
};

RawGL::RawGL(rhi::Backend backend)
    : m_backend(backend), m_es(backend == rhi::Backend::GLES) {
    // The RHI scene comes first: its shaders' translated source is what the raw side compiles.
    RhiScene& scene = rhiScene(backend);
    createContext();
    ContextSwitch current = makeCurrent();
    m_gl.load(!m_es);
    if (validationRequested()) setUpDebugOutput();
    const GLCalls& gl = m_gl;

    gl.glGenTextures(1, &m_target);
    gl.glBindTexture(GL_TEXTURE_2D, m_target);
    gl.glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, kTargetSize, kTargetSize);
    gl.glGenFramebuffers(1, &m_framebuffer);
    gl.glBindFramebuffer(GL_FRAMEBUFFER, m_framebuffer);
    gl.glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, m_target, 0);
    if (gl.glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error("raw GL: the 8x8 RGBA8 framebuffer is incomplete");

    gl.glGenBuffers(1, &m_vertices);
    gl.glBindBuffer(GL_ARRAY_BUFFER, m_vertices);
    gl.glBufferData(GL_ARRAY_BUFFER, sizeof(kTriangle), kTriangle.data(), GL_STATIC_DRAW);
    m_vertexArray = createVertexArray(m_vertices);

    const std::vector<std::byte> parameters = drawParameterData();
    gl.glGenBuffers(1, &m_drawParameters);
    gl.glBindBuffer(GL_UNIFORM_BUFFER, m_drawParameters);
    gl.glBufferData(GL_UNIFORM_BUFFER, GLsizeiptr(parameters.size()), parameters.data(), GL_STATIC_DRAW);
    m_rhiVertices = createBufferAsRhi(kTriangle.data(), sizeof(kTriangle));
    m_rhiVertexArray = createVertexArray(m_rhiVertices);
    m_rhiDrawParameters = createBufferAsRhi(parameters.data(), parameters.size());
    m_drawProgram = compileProgram({{GL_VERTEX_SHADER, scene.vertexShader()->translatedSource()},
                                    {GL_FRAGMENT_SHADER, scene.fragmentShader()->translatedSource()}});
    // ESSL 300 has no binding layout: the shader's only block goes to binding point 0, as the RHI does.
    gl.glUniformBlockBinding(m_drawProgram, 0, 0);

    if (!m_es && scene.hasCompute()) {
        const std::vector<std::byte> zeros(slicedBufferBytes());
        gl.glGenBuffers(1, &m_counters);
        gl.glBindBuffer(GL_SHADER_STORAGE_BUFFER, m_counters);
        gl.glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(zeros.size()), zeros.data(), GL_DYNAMIC_COPY);
        m_computeProgram = compileProgram({{GL_COMPUTE_SHADER, scene.computeShader()->translatedSource()}});
    }
    checkNoError("setting up");

    // One untimed frame of each kind, checked, as on the RHI side.
    for (const RawGLDraws how : {RawGLDraws::Plain, RawGLDraws::RhiBuffers}) {
        submitDraws(how);
        finish();
        checkDraws();
    }
    if (hasCompute()) {
        submitDispatches();
        finish();
        checkDispatches();
    }
}

RawGL::~RawGL() {
    if (!m_platform) return;
    // A destructor must not throw: when the context cannot be made current (the driver's EGL shut
    // down first at exit), its objects are left to eglDestroyContext.
    try {
        ContextSwitch current = makeCurrent();
        const GLCalls& gl = m_gl;
        const GLuint buffers[] = {m_vertices, m_drawParameters, m_counters, m_rhiVertices, m_rhiDrawParameters};
        gl.glDeleteBuffers(GLsizei(std::size(buffers)), buffers);
        const GLuint vertexArrays[] = {m_vertexArray, m_rhiVertexArray};
        gl.glDeleteVertexArrays(GLsizei(std::size(vertexArrays)), vertexArrays);
        gl.glDeleteFramebuffers(1, &m_framebuffer);
        gl.glDeleteTextures(1, &m_target);
        gl.glDeleteProgram(m_drawProgram);
        if (m_computeProgram) gl.glDeleteProgram(m_computeProgram);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "janus_bench_rhi: raw GL objects are left to the driver: %s\n", e.what());
    }
    ContextSwitch restore(nullptr);   // the platform releases its context if it is current
    m_platform.reset();               // (it never terminates the display, which the RHI shares)
}

void RawGL::createContext() {
    ContextSwitch restore(nullptr);
    m_platform = rhi::gl::createEglPlatform(m_es ? rhi::gl::GLApi::ES30 : rhi::gl::GLApi::DesktopCore43,
                                            validationRequested(), rhi::gl::eglOptionsFromEnvironment());
}

void APIENTRY RawGL::onDebugMessage(GLenum, GLenum type, GLuint id, GLenum severity, GLsizei, const GLchar* message,
                                    const void* self) {
    const std::optional<rhi::MessageSeverity> kind = rhi::gl::classifyDebugMessage(type, severity);
    if (!kind) return;
    auto* raw = static_cast<RawGL*>(const_cast<void*>(self));
    try {   // called from inside the driver: nothing may unwind through it
        (*kind == rhi::MessageSeverity::Performance ? raw->m_performanceMessages : raw->m_debugMessages)
            .push_back(fmt::format("GL debug (id {}): {}", id, message));
    } catch (...) {
        std::fprintf(stderr, "janus_bench_rhi: raw GL: a debug message was lost\n");
    }
}

// The RHI's setup (gl_device.cpp, setupDebugOutput): every message, synchronously, through the
// same classification. ES 3.0 has it through KHR_debug, under the KHR-suffixed name.
void RawGL::setUpDebugOutput() {
    auto callback = reinterpret_cast<PFNGLDEBUGMESSAGECALLBACKPROC>(eglGetProcAddress("glDebugMessageCallback"));
    if (!callback && m_es)
        callback = reinterpret_cast<PFNGLDEBUGMESSAGECALLBACKPROC>(eglGetProcAddress("glDebugMessageCallbackKHR"));
    auto enable = reinterpret_cast<PFNGLENABLEPROC>(eglGetProcAddress("glEnable"));
    if (!callback || !enable)
        throw std::runtime_error(fmt::format("raw {}: validation was requested but the context has no debug output "
                                             "(glDebugMessageCallback)", rhi::toString(m_backend)));
    enable(GL_DEBUG_OUTPUT);
    enable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    callback(onDebugMessage, this);
}

void RawGL::checkDebugMessages(const char* when) {
    if (m_debugMessages.empty()) return;
    const std::string first = m_debugMessages.front();
    const size_t count = std::exchange(m_debugMessages, {}).size();
    throw WrongResult(fmt::format("raw {}: {} debug message(s) while {}, the first: {}", rhi::toString(m_backend), count,
                                  when, first));
}

GLuint RawGL::compileProgram(const std::vector<std::pair<GLenum, std::string>>& stages) {
    const GLCalls& gl = m_gl;
    const GLuint program = gl.glCreateProgram();
    for (const auto& [type, source] : stages) {
        const GLuint shader = gl.glCreateShader(type);
        const char* text = source.c_str();
        gl.glShaderSource(shader, 1, &text, nullptr);
        gl.glCompileShader(shader);
        GLint compiled = GL_FALSE;
        gl.glGetShaderiv(shader, GL_COMPILE_STATUS, &compiled);
        if (!compiled) {
            char log[2048] = {};
            gl.glGetShaderInfoLog(shader, sizeof(log), nullptr, log);
            throw std::runtime_error(fmt::format("raw GL: the RHI's translated shader does not compile here: {}", log));
        }
        gl.glAttachShader(program, shader);
        gl.glDeleteShader(shader);   // freed with the program
    }
    gl.glLinkProgram(program);
    GLint linked = GL_FALSE;
    gl.glGetProgramiv(program, GL_LINK_STATUS, &linked);
    if (!linked) {
        char log[2048] = {};
        gl.glGetProgramInfoLog(program, sizeof(log), nullptr, log);
        throw std::runtime_error(fmt::format("raw GL: linking failed: {}", log));
    }
    return program;
}

GLuint RawGL::createBufferAsRhi(const void* data, size_t size) {
    const GLCalls& gl = m_gl;
    const std::vector<std::byte> zeros(size);
    GLuint buffer = 0;
    gl.glGenBuffers(1, &buffer);
    gl.glBindBuffer(GL_COPY_WRITE_BUFFER, buffer);
    gl.glBufferData(GL_COPY_WRITE_BUFFER, GLsizeiptr(size), zeros.data(), GL_DYNAMIC_DRAW);
    gl.glBufferSubData(GL_COPY_WRITE_BUFFER, 0, GLsizeiptr(size), data);
    return buffer;
}

GLuint RawGL::createVertexArray(GLuint vertices) {
    const GLCalls& gl = m_gl;
    GLuint vertexArray = 0;
    gl.glGenVertexArrays(1, &vertexArray);
    gl.glBindVertexArray(vertexArray);
    gl.glBindBuffer(GL_ARRAY_BUFFER, vertices);
    gl.glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(float) * 2, nullptr);
    gl.glEnableVertexAttribArray(0);
    gl.glBindVertexArray(0);
    return vertexArray;
}

void RawGL::checkNoError(const char* when) {
    if (const GLenum error = m_gl.glGetError(); error != GL_NO_ERROR)
        throw WrongResult(fmt::format("raw {}: GL error 0x{:x} while {}", rhi::toString(m_backend), error, when));
}

void RawGL::submitDraws(RawGLDraws how) {
    const GLCalls& gl = m_gl;
    const bool respecifyVertices = how == RawGLDraws::RespecifiedVertices;
    const bool rhiBuffers = how == RawGLDraws::RhiBuffers;
    const GLuint vertices = rhiBuffers ? m_rhiVertices : m_vertices;
    const GLuint drawParameters = rhiBuffers ? m_rhiDrawParameters : m_drawParameters;
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_framebuffer);
    gl.glViewport(0, 0, kTargetSize, kTargetSize);
    // The RHI's GL backend always scissors (to the pass by default); do the same so llvmpipe runs
    // the same fragment-shader variant on both sides.
    gl.glEnable(GL_SCISSOR_TEST);
    gl.glScissor(0, 0, kTargetSize, kTargetSize);
    const float clear[4] = {0, 0, 0, 0};
    gl.glClearBufferfv(GL_COLOR, 0, clear);
    gl.glUseProgram(m_drawProgram);
    gl.glBindVertexArray(rhiBuffers ? m_rhiVertexArray : m_vertexArray);
    const uint32_t ops = opsPerFrame();   // read once: the driver calls could change it, for all the compiler knows
    for (uint32_t i = 0; i < ops; ++i) {
        gl.glBindBufferRange(GL_UNIFORM_BUFFER, 0, drawParameters, GLintptr(i * kSliceBytes), GLsizeiptr(kSliceBytes));
        if (respecifyVertices) {
            gl.glBindBuffer(GL_ARRAY_BUFFER, vertices);
            gl.glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(float) * 2, nullptr);
            gl.glVertexAttribDivisor(0, 0);
        }
        gl.glDrawArrays(GL_TRIANGLES, 0, 3);
    }
}

void RawGL::submitDispatches() {
    const GLCalls& gl = m_gl;
    gl.glUseProgram(m_computeProgram);
    const uint32_t ops = opsPerFrame();
    for (uint32_t i = 0; i < ops; ++i) {
        gl.glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, m_counters, GLintptr(i * kSliceBytes),
                             GLsizeiptr(kSliceBytes));
        gl.glDispatchCompute(1, 1, 1);
    }
    // Each dispatch writes its own counter: one barrier per frame, for whoever reads them next.
    gl.glMemoryBarrier(GL_ALL_BARRIER_BITS);
    ++m_dispatchFrames;
}

void RawGL::checkDraws() {
    const GLCalls& gl = m_gl;
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, m_framebuffer);
    std::array<uint8_t, 4> texel{};
    gl.glReadPixels(0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, texel.data());
    requireLastDrawColor(texel.data(), fmt::format("raw {}", rhi::toString(m_backend)));
    checkNoError("drawing");
    checkDebugMessages("drawing");
}

void RawGL::checkDispatches() {
    const GLCalls& gl = m_gl;
    gl.glBindBuffer(GL_SHADER_STORAGE_BUFFER, m_counters);
    const auto* bytes = static_cast<const std::byte*>(
        gl.glMapBufferRange(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(slicedBufferBytes()), GL_MAP_READ_BIT));
    if (!bytes) throw WrongResult("raw GL: glMapBufferRange on the counters failed");
    std::string problem;
    for (uint32_t i = 0; i < opsPerFrame() && problem.empty(); ++i) {
        uint32_t value = 0;
        std::memcpy(&value, bytes + i * kSliceBytes, sizeof(value));
        if (value != m_dispatchFrames)
            problem = fmt::format("raw gl: counter {} is {} after {} dispatch frames", i, value, m_dispatchFrames);
    }
    gl.glUnmapBuffer(GL_SHADER_STORAGE_BUFFER);
    if (!problem.empty()) throw WrongResult(problem);
    checkNoError("dispatching");
    checkDebugMessages("dispatching");
}

RawGL& rawGL(rhi::Backend backend) {
    if (backend == rhi::Backend::GLES) {
        struct RawGLES : RawGL {   // distinct type: one shared context per API
            RawGLES() : RawGL(rhi::Backend::GLES) {}
        };
        return sharedEnvironment<RawGLES>();
    }
    return sharedEnvironment<RawGL>(rhi::Backend::GL);
}

}  // namespace

void rawGLDraws(benchmark::State& state, rhi::Backend backend, RawGLDraws how) {
    runGuarded(state, [&] {
        RawGL& raw = rawGL(backend);
        ContextSwitch current = raw.makeCurrent();
        auto messages = [&] { return raw.takePerformanceMessages(); };
        if (how == RawGLDraws::NullDriver) {
            {
                const NullGLDriver driver = nullGLDriver(raw.calls().glBindBufferRange, raw.calls().glDrawArrays);
                runFrames(state, [&] { raw.submitDraws(RawGLDraws::Plain); }, [&] { raw.finish(); }, messages);
                driver.requireFrames(uint64_t(state.iterations()), fmt::format("raw {}", rhi::toString(backend)));
            }
            raw.submitDraws(RawGLDraws::Plain);   // and the real driver still draws
            raw.finish();
        } else {
            runFrames(state, [&] { raw.submitDraws(how); }, [&] { raw.finish(); }, messages);
        }
        raw.checkDraws();
    });
}

FrameSide rawGLSide(rhi::Backend backend, Work work) {
    RawGL& raw = work == Work::Dispatches ? requireCompute(rawGL(backend), backend) : rawGL(backend);
    FrameSide frames = frameSideOf(raw, work, [&raw] { raw.finish(); });
    frames.enter = [&raw] { return raw.currentWhileHeld(); };
    return frames;
}

void rawGLDispatches(benchmark::State& state) {
    runGuarded(state, [&] {
        RawGL& raw = requireCompute(rawGL(rhi::Backend::GL), rhi::Backend::GL);
        ContextSwitch current = raw.makeCurrent();
        runFrames(state, [&] { raw.submitDispatches(); }, [&] { raw.finish(); },
                  [&] { return raw.takePerformanceMessages(); });
        raw.checkDispatches();
    });
}

}  // namespace janus::bench
