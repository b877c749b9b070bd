// The GL device: context start-up, capabilities, debug output, execution and immediate transfers.
#include "gl_device.h"
#include "gl_debug_policy.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstring>
#include <utility>
#include <glm/gtc/packing.hpp>

#include "janus/rhi/backends.h"
#include "janus/rhi/driver_settings.h"

namespace janus::rhi::gl {

namespace {
// The context current on this thread, if one of ours is. Released when the thread exits, so a
// worker thread that used a device and ended leaves it free for the next thread.
struct CurrentContext {
    std::shared_ptr<ContextBinding> binding;
    ~CurrentContext() { release(); }
    void release() noexcept {
        if (!binding) return;
        binding->platform->releaseCurrent();
        binding->thread.store(std::thread::id(), std::memory_order_release);
        binding.reset();
    }
};
thread_local CurrentContext t_current;

// GL_EXT_disjoint_timer_query's token; glcorearb.h lacks it.
constexpr GLenum kGpuDisjointEXT = 0x8FBB;

const char* framebufferStatusName(GLenum status) {
    switch (status) {
        case GL_FRAMEBUFFER_UNDEFINED: return "GL_FRAMEBUFFER_UNDEFINED";
        case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT: return "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
        case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT: return "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
        case GL_FRAMEBUFFER_UNSUPPORTED: return "GL_FRAMEBUFFER_UNSUPPORTED";
        case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE: return "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
        case GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS: return "GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS";
        default: return "unknown framebuffer status";
    }
}

void APIENTRY onDebugMessage(GLenum /*source*/, GLenum type, GLuint id, GLenum severity, GLsizei /*length*/,
                               const GLchar* message, const void* userParam) {
    const std::optional<MessageSeverity> ours = classifyDebugMessage(type, severity);
    if (!ours) return;
    auto* context = static_cast<Context*>(const_cast<void*>(userParam));
    // Called from inside the driver (any GL call, glDelete* in destructors too): nothing may
    // unwind through it.
    try {
        context->collectDebugMessage(
            {*ours, context->replayPipeline
                        ? fmt::format("GL debug (id {}): {} (replaying a command list; last pipeline bound: '{}')", id,
                                      message, *context->replayPipeline)
                        : fmt::format("GL debug (id {}): {}", id, message)});
    } catch (const std::exception& e) {
        std::fprintf(stderr, "janus: gl: the debug message callback threw (%s); the message is still collected\n",
                     e.what());
    } catch (...) {
        std::fprintf(stderr, "janus: gl: the debug message callback threw; the message is still collected\n");
    }
}

template <typename T, typename Interface>
const T& ownResource(const std::shared_ptr<Interface>& handle, const Context& context, const char* what,
                     const char* kind) {
    auto* resource = dynamic_cast<const T*>(handle.get());
    if (!resource)
        throw Error(ErrorCode::InvalidUsage, fmt::format("{}: the {} is null or from another backend", what, kind));
    // GL names mean nothing in another context.
    if (resource->owner() != &context)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("{}: the {} was created by another device; use resources of this device", what, kind));
    return *resource;
}
}  // namespace

// ---------------------------------------------------------------------------------------------
// Context

Context::Context(std::unique_ptr<Platform> platform, bool es)
    : state(gl, es), m_binding(std::make_shared<ContextBinding>()), m_es(es), m_platformName(platform->describe()) {
    m_binding->platform = std::move(platform);
    // Creating the platform made its context current here, replacing whichever of ours was.
    t_current.release();
    m_binding->thread.store(std::this_thread::get_id(), std::memory_order_relaxed);
    t_current.binding = m_binding;
    gl.load(*m_binding->platform, es);
}

Context::~Context() {
    if (makeCurrentForTeardown()) {   // which also deletes what other threads released
        for (auto& [key, fbo] : m_framebuffers) gl.glDeleteFramebuffers(1, &fbo);
        if (vertexArray) gl.glDeleteVertexArrays(1, &vertexArray);
        t_current.release();
    }
    // The binding goes next, and with it the platform (unless a thread that holds the context
    // still references it: that thread destroys it when it lets go). Neither throws.
}

bool Context::currentHere() const { return t_current.binding.get() == m_binding.get(); }

void Context::makeCurrent() {
    if (!currentHere()) [[unlikely]] acquire();
    if (m_hasDeferred.load(std::memory_order_acquire)) [[unlikely]] deleteDeferred();
}

void Context::acquire() {
    std::thread::id none;
    if (!m_binding->thread.compare_exchange_strong(none, std::this_thread::get_id(), std::memory_order_acquire))
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("the {} device's context ({}) is current on another thread: a GL device is used by one "
                                "thread at a time (no Capability::ConcurrentDeviceCalls); call detachFromThread() on "
                                "that thread when it is done with the device, or let it exit",
                                m_es ? "gles" : "gl", m_platformName));
    // Another context of ours current here is let go first: EGL keeps one current context per
    // client API, so a GL context would otherwise stay bound here beside a GLES one.
    t_current.release();
    try {
        m_binding->platform->makeCurrent();
    } catch (...) {
        m_binding->thread.store(none, std::memory_order_release);
        throw;
    }
    t_current.binding = m_binding;
}

void Context::releaseFromThread() noexcept {
    if (!currentHere()) return;
    deleteDeferred();
    gl.glFlush();   // what this thread issued reaches the GPU before another thread's work
    t_current.release();
}

void Context::deleteObjects(GLObjectKind kind, std::span<const GLuint> names) noexcept {
    if (currentHere()) return deleteNow(kind, names);
    try {
        const std::lock_guard lock(m_deferredMutex);
        for (GLuint name : names) m_deferred.emplace_back(kind, name);
        m_hasDeferred.store(true, std::memory_order_release);
    } catch (...) {
        // Out of memory: the objects stay until the context is destroyed, which frees them all.
    }
}

void Context::deleteNow(GLObjectKind kind, std::span<const GLuint> names) {
    const auto count = GLsizei(names.size());
    switch (kind) {
        case GLObjectKind::Buffer: gl.glDeleteBuffers(count, names.data()); break;
        case GLObjectKind::Texture:
            for (GLuint name : names) forgetTexture(name);
            gl.glDeleteTextures(count, names.data());
            break;
        case GLObjectKind::Renderbuffer:
            for (GLuint name : names) forgetTexture(name, true);
            gl.glDeleteRenderbuffers(count, names.data());
            break;
        case GLObjectKind::Sampler: gl.glDeleteSamplers(count, names.data()); break;
        case GLObjectKind::Shader:
            for (GLuint name : names) gl.glDeleteShader(name);
            break;
        case GLObjectKind::Program:
            for (GLuint name : names) gl.glDeleteProgram(name);
            break;
        case GLObjectKind::Query: gl.glDeleteQueries(count, names.data()); break;
    }
}

void Context::deleteDeferred() {
    std::vector<std::pair<GLObjectKind, GLuint>> deferred;
    {
        const std::lock_guard lock(m_deferredMutex);
        deferred.swap(m_deferred);
        m_hasDeferred.store(false, std::memory_order_relaxed);
    }
    for (const auto& [kind, name] : deferred) deleteNow(kind, std::span(&name, 1));
}

bool Context::makeCurrentForTeardown() noexcept {
    if (m_unreachableAtTeardown) return false;
    try {
        makeCurrent();
        return true;
    } catch (const std::exception& e) {
        m_unreachableAtTeardown = true;
        std::fprintf(stderr,
                     "janus: gl: the %s context could not be made current at teardown (%s); GL objects are left "
                     "to the driver\n",
                     m_platformName.c_str(), e.what());
    } catch (...) {
        m_unreachableAtTeardown = true;
        std::fprintf(stderr,
                     "janus: gl: the %s context could not be made current at teardown; GL objects are left to "
                     "the driver\n",
                     m_platformName.c_str());
    }
    return false;
}

GLuint Context::framebuffer(const FramebufferKey& key, const std::vector<const Texture*>& colorTextures,
                              const Texture* depthTexture) {
    if (auto it = m_framebuffers.find(key); it != m_framebuffers.end()) return it->second;

    GLuint fbo = 0;
    gl.glGenFramebuffers(1, &fbo);
    gl.glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    std::vector<GLenum> drawBuffers;
    for (size_t i = 0; i < colorTextures.size(); ++i) {
        colorTextures[i]->attach(GL_FRAMEBUFFER, GLenum(GL_COLOR_ATTACHMENT0 + i), key.colors[i].mipLevel,
                                 key.colors[i].layer);
        drawBuffers.push_back(GLenum(GL_COLOR_ATTACHMENT0 + i));
    }
    if (depthTexture) depthTexture->attach(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, key.depth.mipLevel, key.depth.layer);
    if (drawBuffers.empty()) {
        GLenum none = GL_NONE;
        gl.glDrawBuffers(1, &none);
        gl.glReadBuffer(GL_NONE);
    } else {
        gl.glDrawBuffers(GLsizei(drawBuffers.size()), drawBuffers.data());
        gl.glReadBuffer(GL_COLOR_ATTACHMENT0);
    }
    GLenum status = gl.glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        gl.glBindFramebuffer(GL_FRAMEBUFFER, 0);
        gl.glDeleteFramebuffers(1, &fbo);
        std::string formats;
        for (const Texture* t : colorTextures) formats += fmt::format("{} ", toString(t->desc().format));
        if (depthTexture) formats += fmt::format("depth {}", toString(depthTexture->desc().format));
        throw Error(ErrorCode::UnsupportedCapability,
                    fmt::format("the driver cannot render to this attachment combination ({}): {}; "
                                "use other formats or fewer attachments",
                                formats, framebufferStatusName(status)));
    }
    m_framebuffers.emplace(key, fbo);
    return fbo;
}

// Called by ~Texture with the context current.
void Context::forgetTexture(GLuint texture, bool renderbuffer) {
    auto names = [&](const AttachmentKey& a) { return a.texture == texture && a.renderbuffer == renderbuffer; };
    for (auto it = m_framebuffers.begin(); it != m_framebuffers.end();) {
        const FramebufferKey& key = it->first;
        bool uses = names(key.depth) || std::any_of(key.colors.begin(), key.colors.end(), names);
        if (uses) {
            gl.glDeleteFramebuffers(1, &it->second);
            it = m_framebuffers.erase(it);
        } else {
            ++it;
        }
    }
}

void Context::collectDebugMessage(DebugMessage message) {
    // Kept before the callback sees it, so a throwing callback loses nothing.
    (message.severity == MessageSeverity::Performance ? m_performanceMessages : m_debugMessages).push_back(message);
    if (messageCallback) messageCallback(message);
}

std::vector<DebugMessage> Context::takeDebugMessages() { return std::exchange(m_debugMessages, {}); }
std::vector<DebugMessage> Context::takePerformanceMessages() { return std::exchange(m_performanceMessages, {}); }

// ---------------------------------------------------------------------------------------------
// Device creation

namespace {
std::unique_ptr<Platform> createPlatform(const DeviceDesc& desc) {
    const GLApi api = desc.backend == Backend::GLES ? GLApi::ES30 : GLApi::DesktopCore43;
    if (desc.glPlatform == rhi::GLPlatform::OSMesa) return createOsmesaPlatform(api, desc.enableValidation);
    return createEglPlatform(api, desc.enableValidation, eglOptionsFromEnvironment());
}
}  // namespace

Device::Device(const DeviceDesc& desc) : Device(desc, createPlatform(desc)) {}

Device::Device(const DeviceDesc& desc, std::unique_ptr<Platform> platform) {
    const bool es = desc.backend == Backend::GLES;
    m_context = std::make_shared<Context>(std::move(platform), es);
    m_es = es;
    m_context->messageCallback = desc.messageCallback;
    const GLFunctions& f = gl();

    GLint major = 0, minor = 0;
    f.glGetIntegerv(GL_MAJOR_VERSION, &major);
    f.glGetIntegerv(GL_MINOR_VERSION, &minor);
    if (es ? major < 3 : (major < 4 || (major == 4 && minor < 3)))
        throw Error(ErrorCode::BackendUnavailable,
                    fmt::format("the driver gave a {}.{} context but the {} backend needs {}", major, minor,
                                es ? "gles" : "gl", es ? "OpenGL ES 3.0" : "OpenGL 4.3 core"));

    GLint extensionCount = 0;
    f.glGetIntegerv(GL_NUM_EXTENSIONS, &extensionCount);
    for (GLint i = 0; i < extensionCount; ++i)
        m_extensions.emplace_back(reinterpret_cast<const char*>(f.glGetStringi(GL_EXTENSIONS, GLuint(i))));

    auto glString = [&](GLenum name) {
        const GLubyte* s = f.glGetString(name);
        return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
    };
    DeviceProperties properties;
    DeviceInfo& info = properties.info;
    info.backend = desc.backend;
    info.apiVersion = glString(GL_VERSION);
    if (!es && info.apiVersion.rfind("OpenGL", 0) != 0) info.apiVersion = "OpenGL " + info.apiVersion;
    info.deviceName = glString(GL_RENDERER);
    // llvmpipe takes a timestamp in every screen tile as it rasterises them and keeps each
    // thread's last: one binned with a pass's draws reads as the pass's last tile (timestamp()).
    m_timestampsPerTile = info.deviceName.find("llvmpipe") != std::string::npos;
    info.driverInfo = glString(GL_VENDOR);
    info.platform = m_context->platformName();
    info.shadingLanguage = es ? "ESSL 300" : "GLSL 430";
    info.driverSettings = detail::glDriverSettingsNote(info.driverInfo);

    properties.capabilities = detectCapabilities();
    properties.formats = queryFormatCapabilities(properties.capabilities);
    properties.validation = desc.enableValidation;
    setProperties(std::move(properties));
    if (desc.enableValidation) {
        setupDebugOutput();
        m_context->checkSamplerUnits = true;
        m_drawChecks |= kCheckSamplerUnits;
    }
    setupDefaultState();
}

Device::~Device() {
    // Resources may outlive the device; they keep the context alive. Only drop replay state.
    if (m_context->makeCurrentForTeardown()) m_context->gl.glFinish();
}

bool Device::hasExtension(std::string_view name) const {
    return std::find(m_extensions.begin(), m_extensions.end(), name) != m_extensions.end();
}

Capabilities Device::detectCapabilities() {
    Capabilities caps;
    // A context is current on one thread at a time (Context::makeCurrent).
    caps.concurrentDeviceCalls = false;
    const GLFunctions& f = gl();
    auto integer = [&](GLenum name) {
        GLint v = 0;
        f.glGetIntegerv(name, &v);
        return uint32_t(std::max(v, 0));
    };
    Limits& limits = caps.limits;
    limits.maxTextureSize2D = integer(GL_MAX_TEXTURE_SIZE);
    limits.maxTextureSize3D = integer(GL_MAX_3D_TEXTURE_SIZE);
    limits.maxTextureSizeCube = integer(GL_MAX_CUBE_MAP_TEXTURE_SIZE);
    limits.maxTextureArrayLayers = integer(GL_MAX_ARRAY_TEXTURE_LAYERS);
    limits.maxColorAttachments = std::min(integer(GL_MAX_COLOR_ATTACHMENTS), integer(GL_MAX_DRAW_BUFFERS));
    limits.maxUniformBufferRange = integer(GL_MAX_UNIFORM_BLOCK_SIZE);
    limits.uniformBufferOffsetAlignment = integer(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT);
    // Far beyond any buffer a test or scene needs, and below where GL sizes (GLsizeiptr) or
    // llvmpipe allocations get questionable; larger requests are almost certainly a size computed wrong.
    limits.maxBufferSize = uint64_t(1) << 31;
    // Attribute locations double as our vertex buffer slots' upper bound; the backend tracks 16.
    limits.maxVertexAttributes = std::min(integer(GL_MAX_VERTEX_ATTRIBS), 16u);
    limits.maxVertexBuffers = limits.maxVertexAttributes;

    caps.renderToVolumeSlice = true;   // glFramebufferTextureLayer on 3D textures: GL 3.0 / ES 3.0
    caps.renderToCubeFaceMip = true;   // immutable storage keeps every face and mip complete
    GLint major = 0, minor = 0;
    f.glGetIntegerv(GL_MAJOR_VERSION, &major);
    f.glGetIntegerv(GL_MINOR_VERSION, &minor);
    auto desktopAtLeast = [&](GLint wantMajor, GLint wantMinor) {
        return !isES() && (major > wantMajor || (major == wantMajor && minor >= wantMinor));
    };
    // With clip control the driver takes [0, 1] clip depth natively (no z' = 2z - w rounding).
    const bool clipControl = desktopAtLeast(4, 5) || hasExtension(isES() ? "GL_EXT_clip_control" : "GL_ARB_clip_control");
    m_context->zeroToOneClipDepth = clipControl && f.glClipControl;
    m_context->clearTexImage = (desktopAtLeast(4, 4) || hasExtension(isES() ? "GL_EXT_clear_texture" : "GL_ARB_clear_texture")) &&
                               f.glClearTexImage;
    caps.conventions.nativeClipDepthZeroToOne = m_context->zeroToOneClipDepth;
    // Even with an upper-left clip origin, GL addresses rows (viewport, scissor, readback) bottom-up.
    caps.conventions.nativeFramebufferOriginTopLeft = false;

    if (!isES()) {
        caps.compute = caps.storageBuffers = caps.storageImages = true;
        caps.floatRenderTargets = caps.floatBlend = caps.timestampQueries = true;
        GLint64 ssboSize = 0;
        f.glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &ssboSize);
        limits.maxStorageBufferRange = uint64_t(ssboSize);
        limits.storageBufferOffsetAlignment = integer(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT);
        for (GLuint i = 0; i < 3; ++i) {
            GLint count = 0, size = 0;
            f.glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, i, &count);
            f.glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_SIZE, i, &size);
            limits.maxComputeWorkGroupCount[i] = uint32_t(count);
            limits.maxComputeWorkGroupSize[i] = uint32_t(size);
        }
        limits.maxComputeWorkGroupInvocations = integer(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS);
        m_anisotropy = hasExtension("GL_ARB_texture_filter_anisotropic") ||
                       hasExtension("GL_EXT_texture_filter_anisotropic");
        caps.independentBlend = true;   // glBlendFuncSeparatei / glColorMaski (GL 4.0)
        caps.cubeArrays = true;   // GL 4.0 core
        // glTextureView: GL 4.3 core (which we require) or ARB_texture_view.
        caps.textureViews = (desktopAtLeast(4, 3) || hasExtension("GL_ARB_texture_view")) && f.glTextureView;
    } else {
        // ES 3.0 has neither cube-map arrays nor texture views. Drivers that offer ES 3.2 or
        // EXT_texture_cube_map_array still cannot be used for cube arrays here: every shader is
        // translated to ESSL 300, which has no samplerCubeArray, and ES programs cannot link
        // stages of different versions. Sampled mip ranges are emulated (BASE/MAX_LEVEL).
        caps.cubeArrays = false;
        caps.textureViews = false;
        // GLES stands in for compute-less devices: even when the driver offers ES 3.1+, compute,
        // SSBOs and image load/store stay off.
        caps.floatRenderTargets = hasExtension("GL_EXT_color_buffer_float");
        caps.floatBlend = caps.floatRenderTargets && hasExtension("GL_EXT_float_blend");
        caps.timestampQueries = hasExtension("GL_EXT_disjoint_timer_query") && gl().glQueryCounter &&
                                  gl().glGetQueryObjectui64v;
        limits.storageBufferOffsetAlignment = 0;
        m_anisotropy = hasExtension("GL_EXT_texture_filter_anisotropic");
        m_readDepthNV = hasExtension("GL_NV_read_depth");
    }
    // GL 4.4 / ES 3.1 report the stride limit; before, 2048 is what Vulkan guarantees too.
    limits.maxVertexStride = desktopAtLeast(4, 4) ? integer(GL_MAX_VERTEX_ATTRIB_STRIDE) : 2048;
    GLint viewportDims[2] = {0, 0};
    f.glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewportDims);
    limits.maxViewportSize = uint32_t(std::max(std::min(viewportDims[0], viewportDims[1]), 0));
    // GL 4.1 reports the bounds range; before (ES 3.0) the range Vulkan guarantees for this size,
    // which keeps the backend's float-to-GLint conversion of the viewport in range.
    if (desktopAtLeast(4, 1)) {
        GLfloat bounds[2] = {0.0f, 0.0f};
        f.glGetFloatv(GL_VIEWPORT_BOUNDS_RANGE, bounds);
        limits.viewportBoundsRange = {bounds[0], bounds[1]};
    } else {
        const float most = float(limits.maxViewportSize);
        limits.viewportBoundsRange = {-2.0f * most, 2.0f * most - 1.0f};
    }
    if (m_anisotropy) {
        constexpr GLenum kMaxTextureMaxAnisotropy = 0x84FF;   // EXT/ARB_texture_filter_anisotropic
        GLfloat most = 1.0f;
        f.glGetFloatv(kMaxTextureMaxAnisotropy, &most);
        limits.maxSamplerAnisotropy = std::max(most, 1.0f);
    }
    return caps;
}

// The format table. Desktop GL 4.3: the core spec's rules narrowed by glGetInternalformativ
// (ARB_internalformat_query2). Its answers are not taken alone: llvmpipe reports
// GL_FRAMEBUFFER_BLEND for integer and depth formats (which never blend) and GL_READ_PIXELS
// as unsupported for formats it reads fine. ES 3.0: the spec's format table (ES 3.0.6 tables
// 3.13 and 4.x) plus the extensions that widen it.
std::vector<FormatCapabilities> Device::queryFormatCapabilities(const Capabilities& caps) const {
    const GLFunctions& f = gl();
    std::vector<FormatCapabilities> table(allFormats().size() + 1);
    const bool colorBufferFloat = hasExtension("GL_EXT_color_buffer_float");
    const bool colorBufferHalfFloat = colorBufferFloat || hasExtension("GL_EXT_color_buffer_half_float");
    const bool floatLinear = hasExtension("GL_OES_texture_float_linear");
    const bool floatBlend = hasExtension("GL_EXT_float_blend");
    for (const FormatInfo& info : allFormats()) {
        const Format format = info.format;
        const bool depth = info.kind == FormatKind::Depth;
        const bool integer = info.kind == FormatKind::UInt;
        const bool float32 = info.kind == FormatKind::Float && info.bytesPerPixel / info.channels == 4;
        FormatCapabilities& c = table[size_t(format)];
        bool sampled = true, filterable = !integer, renderable = true, blendable = !integer && !depth;
        bool storage = caps.storageImages && !info.srgb && !depth;
        bool copyable = true;
        if (isES()) {
            if (info.kind == FormatKind::Float) {
                // 16-bit and packed floats filter in core ES 3.0; 32-bit ones need OES_texture_float_linear.
                filterable = !float32 || floatLinear;
                renderable = format == Format::RGBA16_FLOAT ? colorBufferHalfFloat : colorBufferFloat;
                blendable = renderable && (!float32 || floatBlend);
            }
            // ES 3.0 filters depth only through comparison (without it a linear depth texture is incomplete).
            if (depth) filterable = false;
            // Colour readback and texture copies go through framebuffers: only renderable formats.
            // Depth reads back with NV_read_depth or by drawing into r32f.
            copyable = depth ? hasExtension("GL_NV_read_depth") || colorBufferFloat : renderable;
        } else if (f.glGetInternalformativ) {
            auto query = [&](GLenum pname) {
                GLint value = GL_NONE;
                f.glGetInternalformativ(GL_TEXTURE_2D, glFormat(format).internalFormat, pname, 1, &value);
                return value;
            };
            if (query(GL_INTERNALFORMAT_SUPPORTED) != GL_TRUE) sampled = renderable = copyable = storage = false;
            filterable = filterable && query(GL_FILTER) != GL_NONE;
            renderable = renderable && query(GL_FRAMEBUFFER_RENDERABLE) != GL_NONE;
            blendable = blendable && renderable && query(GL_FRAMEBUFFER_BLEND) != GL_NONE;
            storage = storage && query(GL_SHADER_IMAGE_LOAD) != GL_NONE && query(GL_SHADER_IMAGE_STORE) != GL_NONE;
            // GL_READ_PIXELS is not consulted (see above); readback uses glReadPixels on every format.
        }
        c.set(FormatCapability::Sampled, sampled);
        c.set(FormatCapability::Filterable, sampled && filterable);
        // Comparison (sampler2DShadow) filters depth linearly on GL 4.3 and ES 3.0 alike.
        c.set(FormatCapability::CompareFilterable, sampled && depth);
        c.set(FormatCapability::RenderTarget, renderable);
        c.set(FormatCapability::Blendable, blendable);
        c.set(FormatCapability::Storage, storage);
        c.set(FormatCapability::Copyable, copyable);
        // glGenerateMipmap: colour-renderable and filterable formats only.
        c.set(FormatCapability::GenerateMips, !depth && renderable && sampled && filterable);
        // Multisampling: the counts a renderbuffer of the format takes (GL 4.3 and ES 3.0 both
        // answer for GL_RENDERBUFFER), below GL_MAX_SAMPLES. Integer formats stay single-sampled,
        // as on Vulkan (ES 3.0 has no multisampled integer renderbuffers; their resolve is no average).
        c.sampleCounts = 1;
        if (renderable && !integer) {
            GLint maxSamples = 0, counts = 0;
            f.glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
            const GLenum internalFormat = glFormat(format).internalFormat;
            f.glGetInternalformativ(GL_RENDERBUFFER, internalFormat, GL_NUM_SAMPLE_COUNTS, 1, &counts);
            std::vector<GLint> samples(size_t(std::clamp(counts, 0, 64)));
            if (!samples.empty())
                f.glGetInternalformativ(GL_RENDERBUFFER, internalFormat, GL_SAMPLES, GLsizei(samples.size()), samples.data());
            for (GLint n : samples)
                if (n > 1 && n <= std::min(maxSamples, 16) && std::has_single_bit(uint32_t(n))) c.sampleCounts |= uint32_t(n);
        }
    }
    return table;
}

void Device::setupDebugOutput() {
    const GLFunctions& f = gl();
    bool available = !isES() || hasExtension("GL_KHR_debug");
    if (!available || !f.glDebugMessageCallback || !f.glDebugMessageControl)
        throw Error(ErrorCode::BackendUnavailable,
                    "validation was requested but the context has no KHR_debug; create the device with "
                    "enableValidation = false");
    f.glEnable(GL_DEBUG_OUTPUT);
    // Synchronous, so the message arrives inside the call that caused it.
    f.glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    // Every message reaches the callback; classifyDebugMessage (gl_debug_policy.cpp) decides.
    f.glDebugMessageCallback(onDebugMessage, m_context.get());
}

void Device::setupDefaultState() {
    const GLFunctions& f = gl();
    f.glPixelStorei(GL_PACK_ALIGNMENT, 1);
    f.glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    f.glGenVertexArrays(1, &m_context->vertexArray);
    f.glBindVertexArray(m_context->vertexArray);
    f.glEnable(GL_SCISSOR_TEST);
    // The origin stays lower-left: GL's bottom row is our row 0 in memory, and Mesa rasterises
    // framebuffer objects with Vulkan's tie-break only then (GL_UPPER_LEFT flips its edge rule).
    if (m_context->zeroToOneClipDepth) f.glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    if (!isES()) {
        // ES always filters cube maps seamlessly and encodes to sRGB attachments; desktop GL does
        // both only when asked (global state, so once).
        f.glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
        f.glEnable(GL_FRAMEBUFFER_SRGB);
        // Vulkan and ES take the point size from the shader; desktop GL only when this is on.
        f.glEnable(GL_PROGRAM_POINT_SIZE);
    }
}

std::unique_ptr<IDevice> createDevice(const DeviceDesc& desc) {
    if (desc.backend != Backend::GL && desc.backend != Backend::GLES)
        throw Error(ErrorCode::InvalidDescription,
                    fmt::format("the GL backend serves backends gl and gles, not {}", toString(desc.backend)));
    return std::make_unique<Device>(desc);
}

// ---------------------------------------------------------------------------------------------
// Resource creation. Descriptions arrive validated (rhi/src/validation.cpp); what is left is that
// the objects they name belong to this device's context.

BufferHandle Device::createBufferImpl(const BufferDesc& desc) {
    m_context->makeCurrent();
    return std::make_shared<Buffer>(m_context, desc);
}

TextureHandle Device::createTextureImpl(const TextureDesc& desc) {
    m_context->makeCurrent();
    return std::make_shared<Texture>(m_context, desc);
}

SamplerHandle Device::createSamplerImpl(const SamplerDesc& desc) {
    m_context->makeCurrent();
    return std::make_shared<Sampler>(m_context, desc, m_anisotropy);
}

ShaderHandle Device::createShaderImpl(const ShaderDesc& desc) {
    m_context->makeCurrent();
    return std::make_shared<Shader>(m_context, desc);
}

PipelineHandle Device::createGraphicsPipelineImpl(const GraphicsPipelineDesc& desc) {
    m_context->makeCurrent();
    const std::string name = desc.debugName.empty() ? std::string("graphics pipeline")
                                                    : fmt::format("graphics pipeline '{}'", desc.debugName);
    ownResource<Shader>(desc.vertexShader, *m_context, name.c_str(), "vertex shader");
    ownResource<Shader>(desc.fragmentShader, *m_context, name.c_str(), "fragment shader");
    return std::make_shared<Pipeline>(m_context, desc);
}

PipelineHandle Device::createComputePipelineImpl(const ComputePipelineDesc& desc) {
    m_context->makeCurrent();
    ownResource<Shader>(desc.computeShader, *m_context, "compute pipeline", "compute shader");
    return std::make_shared<Pipeline>(m_context, desc);
}

BindingSetHandle Device::createBindingSetImpl(const BindingSetDesc& desc) {
    for (const BindingItem& item : desc.items) {
        const auto where = fmt::format("binding {}", item.binding);
        if (item.buffer) ownResource<Buffer>(item.buffer, *m_context, where.c_str(), "buffer");
        if (item.texture) ownResource<Texture>(item.texture, *m_context, where.c_str(), "texture");
        if (item.sampler) ownResource<Sampler>(item.sampler, *m_context, where.c_str(), "sampler");
    }
    return std::make_shared<BindingSet>(context(), desc);
}

TimerQueryHandle Device::createTimerQueryImpl() {
    m_context->makeCurrent();
    return std::make_shared<TimerQuery>(m_context);
}

CommandListHandle Device::createCommandListImpl() { return std::make_shared<CommandList>(m_context); }

// ---------------------------------------------------------------------------------------------
// Execution

void Device::executeImpl(const CommandListHandle& commandList) {
    auto* list = dynamic_cast<CommandList*>(commandList.get());
    if (!list) throw Error(ErrorCode::InvalidUsage, "execute() was given a command list from another backend or none");
    if (list->owner() != m_context.get())
        throw Error(ErrorCode::InvalidUsage, "execute(): the command list was created by another device; record it with "
                                             "a command list of this device");
    m_context->makeCurrent();
    m_drawCalls = {gl().glBindBufferRange, gl().glDrawArrays};
    // Replay state never carries over between lists: what it points at is only kept alive by the
    // list that set it (and each list must set its own pipeline and buffers anyway).
    m_pipeline = nullptr;
    m_listSets = {};
    m_setPoints = {};
    m_takenPoints = {};
    m_boundSets = {};
    m_exclusivePoints = {};
    m_drawChecks &= uint8_t(~kRestoreTakenPoints);
    m_vertexBuffers.clear();
    m_indexBuffer = 0;
    markVertexStateDirty();
    m_boundIndexBuffer = 0;
    struct ForgetReplayPipeline {
        Context& context;
        ~ForgetReplayPipeline() { context.replayPipeline = nullptr; }
    } forget{*m_context};
    list->replay(*this);
    // No program stays in use after the list: NVIDIA checks the program in use for undefined
    // sampling on later calls that draw nothing (a texture read back or uploaded), and by then a
    // texture it sampled may be gone (id 131222, seen after cube captures). The next list binds
    // its own pipeline anyway.
    if (m_pipeline) gl().glUseProgram(0);
    m_pipeline = nullptr;
}

void Device::waitIdle() {
    m_context->makeCurrent();
    gl().glFinish();
}

std::vector<DebugMessage> Device::takeDebugMessages() { return m_context->takeDebugMessages(); }
void Device::collectFrontMessage(const DebugMessage& message) { m_context->collectDebugMessage(message); }

std::vector<DebugMessage> Device::takePerformanceMessages() { return m_context->takePerformanceMessages(); }

void Device::insertPerformanceMessageForTesting(const std::string& text) {
    m_context->makeCurrent();
    if (gl().glDebugMessageInsert)
        gl().glDebugMessageInsert(GL_DEBUG_SOURCE_APPLICATION, GL_DEBUG_TYPE_PERFORMANCE, 1, GL_DEBUG_SEVERITY_MEDIUM, -1, text.c_str());
}

void Device::provokeValidationErrorForTesting() {
    m_context->makeCurrent();
    // GL_INVALID_ENUM on every GL and ES version: 0 is not a capability.
    gl().glEnable(0);
    gl().glGetError();   // the debug callback has reported it; clear the sticky flag
}

// ---------------------------------------------------------------------------------------------
// Immediate transfers (arguments validated by rhi/src/validation.cpp)

void Device::bufferSubData(const Buffer& buffer, const void* data, uint64_t size, uint64_t offset) {
    gl().glBindBuffer(GL_COPY_WRITE_BUFFER, buffer.name());
    gl().glBufferSubData(GL_COPY_WRITE_BUFFER, GLintptr(offset), GLsizeiptr(size), data);
}

void Device::writeBufferImpl(const BufferHandle& handle, const void* data, uint64_t size, uint64_t offset) {
    const Buffer& buffer = ownResource<Buffer>(handle, *m_context, "writeBuffer", "buffer");
    m_context->makeCurrent();
    bufferSubData(buffer, data, size, offset);
}

std::vector<std::byte> Device::readBufferImpl(const BufferHandle& handle, uint64_t offset, uint64_t size) {
    const Buffer& buffer = ownResource<Buffer>(handle, *m_context, "readBuffer", "buffer");
    m_context->makeCurrent();
    const GLFunctions& f = gl();
    // Read through a staging buffer whose usage hint says the host reads it (GL_STREAM_READ):
    // mapping the buffer itself made NVIDIA's driver move it from video to host memory ("usage
    // hint GL_DYNAMIC_DRAW ... being copied/moved from VIDEO memory to HOST memory", issue 10),
    // and the GPU would then use it from there.
    GLuint staging = 0;
    f.glGenBuffers(1, &staging);
    f.glBindBuffer(GL_COPY_READ_BUFFER, buffer.name());
    f.glBindBuffer(GL_COPY_WRITE_BUFFER, staging);
    f.glBufferData(GL_COPY_WRITE_BUFFER, GLsizeiptr(size), nullptr, GL_STREAM_READ);
    f.glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, GLintptr(offset), 0, GLsizeiptr(size));
    const void* mapped = f.glMapBufferRange(GL_COPY_WRITE_BUFFER, 0, GLsizeiptr(size), GL_MAP_READ_BIT);
    if (!mapped) {
        f.glDeleteBuffers(1, &staging);
        throw Error(ErrorCode::OutOfMemory, fmt::format("readBuffer: mapping {} bytes read from buffer '{}' failed", size,
                                                        buffer.desc().debugName));
    }
    std::vector<std::byte> result(size);
    std::memcpy(result.data(), mapped, size);
    f.glUnmapBuffer(GL_COPY_WRITE_BUFFER);
    f.glDeleteBuffers(1, &staging);
    return result;
}

void Device::writeTextureImpl(const TextureHandle& handle, TextureSubresource sub, const void* data, uint64_t size) {
    const Texture& texture = ownResource<Texture>(handle, *m_context, "writeTexture", "texture");
    m_context->makeCurrent();
    gl().glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    uploadTexture(texture, sub, data);
}

std::vector<std::byte> Device::readTextureImpl(const TextureHandle& handle, TextureSubresource sub) {
    const Texture& texture = ownResource<Texture>(handle, *m_context, "readTexture", "texture");
    m_context->makeCurrent();
    return downloadTexture(texture, sub);
}

std::vector<std::byte> Device::downloadTexture(const Texture& texture, TextureSubresource sub) {
    const GLFunctions& f = gl();
    const uint32_t width = texture.width(sub.mipLevel), height = texture.height(sub.mipLevel);
    const size_t pixels = size_t(width) * height;
    const Format format = texture.desc().format;
    std::vector<std::byte> result(texture.subresourceSize(sub.mipLevel));

    FramebufferKey key;
    const AttachmentKey attachment{texture.name(), sub.mipLevel, sub.layer};
    GLuint fbo = 0;
    if (isDepthFormat(format)) {
        key.depth = attachment;
        fbo = m_context->framebuffer(key, {}, &texture);
    } else {
        key.colors.push_back(attachment);
        fbo = m_context->framebuffer(key, {&texture}, nullptr);
    }
    f.glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    f.glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);

    if (!isES() || format == Format::RGBA8_UNORM || format == Format::RGBA8_SRGB || format == Format::RGBA32_FLOAT ||
        format == Format::RGBA32_UINT) {
        // Desktop GL converts to any format/type; ES reads these formats exactly as stored.
        const GLFormat& gf = texture.format();
        f.glReadPixels(0, 0, GLsizei(width), GLsizei(height), gf.uploadFormat, gf.uploadType, result.data());
        return result;
    }
    if (format == Format::D32_FLOAT) {
        if (!m_readDepthNV) return readDepthThroughColor(texture, sub);
        f.glReadPixels(0, 0, GLsizei(width), GLsizei(height), GL_DEPTH_COMPONENT, GL_FLOAT, result.data());
        return result;
    }
    // ES 3.0 reads colour only as RGBA/UNSIGNED_BYTE, RGBA/FLOAT or RGBA_INTEGER/UNSIGNED_INT:
    // read the wide form and repack on the CPU (the stored values are exactly representable).
    if (format == Format::R32_UINT) {
        std::vector<uint32_t> rgba(pixels * 4);
        f.glReadPixels(0, 0, GLsizei(width), GLsizei(height), GL_RGBA_INTEGER, GL_UNSIGNED_INT, rgba.data());
        auto* out = reinterpret_cast<uint32_t*>(result.data());
        for (size_t i = 0; i < pixels; ++i) out[i] = rgba[i * 4];
        return result;
    }
    std::vector<float> rgba(pixels * 4);
    f.glReadPixels(0, 0, GLsizei(width), GLsizei(height), GL_RGBA, GL_FLOAT, rgba.data());
    for (size_t i = 0; i < pixels; ++i) {
        const float* p = &rgba[i * 4];
        switch (format) {
            case Format::R32_FLOAT: std::memcpy(result.data() + i * 4, p, 4); break;
            case Format::RGBA16_FLOAT: {
                const glm::uint64 packed = glm::packHalf4x16(glm::vec4(p[0], p[1], p[2], p[3]));
                std::memcpy(result.data() + i * 8, &packed, 8);
                break;
            }
            case Format::R11G11B10_FLOAT: {
                const glm::uint32 packed = glm::packF2x11_1x10(glm::vec3(p[0], p[1], p[2]));
                std::memcpy(result.data() + i * 4, &packed, 4);
                break;
            }
            default: break;
        }
    }
    return result;
}

std::optional<double> Device::timerSeconds(const TimerQueryHandle& handle) {
    const auto* timer = &ownResource<TimerQuery>(handle, *m_context, "timerSeconds", "timer");
    if (!timer->begun || !timer->ended) return std::nullopt;
    m_context->makeCurrent();
    const GLFunctions& f = gl();
    if (isES()) {
        // EXT_disjoint_timer_query: reading GPU_DISJOINT clears it; a disjoint result is invalid.
        GLint disjoint = 0;
        f.glGetIntegerv(kGpuDisjointEXT, &disjoint);
        if (disjoint) return std::nullopt;
    }
    GLuint64 begin = 0, end = 0;
    f.glGetQueryObjectui64v(timer->beginQuery(), GL_QUERY_RESULT, &begin);
    f.glGetQueryObjectui64v(timer->endQuery(), GL_QUERY_RESULT, &end);
    return end >= begin ? double(end - begin) * 1e-9 : 0.0;
}

}  // namespace janus::rhi::gl
