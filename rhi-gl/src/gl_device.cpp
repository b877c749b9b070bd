// The GL device: context start-up, capabilities, debug output, execution and immediate transfers.
#include "gl_device.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <utility>
#include <glm/gtc/packing.hpp>

#include "janus/rhi/backends.h"

namespace janus::rhi::gl {

namespace {
thread_local Context* t_currentContext = nullptr;

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
    MessageSeverity ours;
    if (type == GL_DEBUG_TYPE_ERROR)
        ours = MessageSeverity::Error;
    else if (severity == GL_DEBUG_SEVERITY_HIGH || severity == GL_DEBUG_SEVERITY_MEDIUM)
        ours = MessageSeverity::Warning;
    else
        return;   // notifications and low-severity hints are not problems
    auto* context = static_cast<Context*>(const_cast<void*>(userParam));
    context->collectDebugMessage({ours, fmt::format("GL debug (id {}): {}", id, message)});
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
    : m_platform(std::move(platform)), m_es(es), m_platformName(m_platform->describe()) {
    // Creating the platform made its context current, replacing whichever was.
    t_currentContext = nullptr;
    gl.load(*m_platform, es);
    t_currentContext = this;
}

Context::~Context() {
    makeCurrent();
    for (auto& [key, fbo] : m_framebuffers) gl.glDeleteFramebuffers(1, &fbo);
    if (vertexArray) gl.glDeleteVertexArrays(1, &vertexArray);
    if (t_currentContext == this) t_currentContext = nullptr;
}

void Context::makeCurrent() {
    if (t_currentContext == this) return;
    m_platform->makeCurrent();
    t_currentContext = this;
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

void Context::forgetTexture(GLuint texture) {
    makeCurrent();
    for (auto it = m_framebuffers.begin(); it != m_framebuffers.end();) {
        const FramebufferKey& key = it->first;
        bool uses = key.depth.texture == texture ||
                    std::any_of(key.colors.begin(), key.colors.end(),
                                [&](const AttachmentKey& a) { return a.texture == texture; });
        if (uses) {
            gl.glDeleteFramebuffers(1, &it->second);
            it = m_framebuffers.erase(it);
        } else {
            ++it;
        }
    }
}

void Context::collectDebugMessage(DebugMessage message) {
    if (messageCallback) messageCallback(message);
    m_debugMessages.push_back(std::move(message));
}

std::vector<DebugMessage> Context::takeDebugMessages() { return std::exchange(m_debugMessages, {}); }

// ---------------------------------------------------------------------------------------------
// Device creation

Device::Device(const DeviceDesc& desc) {
    const bool es = desc.backend == Backend::GLES;
    const GLApi api = es ? GLApi::ES30 : GLApi::DesktopCore43;
    std::unique_ptr<Platform> platform = desc.glPlatform == rhi::GLPlatform::OSMesa
                                               ? createOsmesaPlatform(api, desc.enableValidation)
                                               : createEglPlatform(api, desc.enableValidation);
    m_context = std::make_shared<Context>(std::move(platform), es);
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
    m_info.backend = desc.backend;
    m_info.apiVersion = glString(GL_VERSION);
    if (!es && m_info.apiVersion.rfind("OpenGL", 0) != 0) m_info.apiVersion = "OpenGL " + m_info.apiVersion;
    m_info.deviceName = glString(GL_RENDERER);
    m_info.driverInfo = glString(GL_VENDOR);
    m_info.platform = m_context->platformName();
    m_info.shadingLanguage = es ? "ESSL 300" : "GLSL 430";

    detectCapabilities();
    if (desc.enableValidation) setupDebugOutput();
    setupDefaultState();
}

Device::~Device() {
    // Resources may outlive the device; they keep the context alive. Only drop replay state.
    m_context->makeCurrent();
    m_context->gl.glFinish();
}

bool Device::hasExtension(std::string_view name) const {
    return std::find(m_extensions.begin(), m_extensions.end(), name) != m_extensions.end();
}

void Device::detectCapabilities() {
    const GLFunctions& f = gl();
    auto integer = [&](GLenum name) {
        GLint v = 0;
        f.glGetIntegerv(name, &v);
        return uint32_t(std::max(v, 0));
    };
    Limits& limits = m_caps.limits;
    limits.maxTextureSize2D = integer(GL_MAX_TEXTURE_SIZE);
    limits.maxTextureSize3D = integer(GL_MAX_3D_TEXTURE_SIZE);
    limits.maxTextureSizeCube = integer(GL_MAX_CUBE_MAP_TEXTURE_SIZE);
    limits.maxTextureArrayLayers = integer(GL_MAX_ARRAY_TEXTURE_LAYERS);
    limits.maxColorAttachments = std::min(integer(GL_MAX_COLOR_ATTACHMENTS), integer(GL_MAX_DRAW_BUFFERS));
    limits.maxUniformBufferRange = integer(GL_MAX_UNIFORM_BLOCK_SIZE);
    limits.uniformBufferOffsetAlignment = integer(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT);

    m_caps.renderToVolumeSlice = true;   // glFramebufferTextureLayer on 3D textures: GL 3.0 / ES 3.0
    m_caps.renderToCubeFaceMip = true;   // immutable storage keeps every face and mip complete
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
    m_caps.conventions.nativeClipDepthZeroToOne = m_context->zeroToOneClipDepth;
    // Even with an upper-left clip origin, GL addresses rows (viewport, scissor, readback) bottom-up.
    m_caps.conventions.nativeFramebufferOriginTopLeft = false;

    if (!isES()) {
        m_caps.compute = m_caps.storageBuffers = m_caps.storageImages = true;
        m_caps.floatRenderTargets = m_caps.floatBlend = m_caps.timestampQueries = true;
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
        m_caps.cubeArrays = true;   // GL 4.0 core
        // glTextureView: GL 4.3 core (which we require) or ARB_texture_view.
        m_caps.textureViews = (desktopAtLeast(4, 3) || hasExtension("GL_ARB_texture_view")) && f.glTextureView;
    } else {
        // ES 3.0 has neither cube-map arrays nor texture views. Drivers that offer ES 3.2 or
        // EXT_texture_cube_map_array still cannot be used for cube arrays here: every shader is
        // translated to ESSL 300, which has no samplerCubeArray, and ES programs cannot link
        // stages of different versions. Sampled mip ranges are emulated (BASE/MAX_LEVEL).
        m_caps.cubeArrays = false;
        m_caps.textureViews = false;
        // GLES stands in for compute-less devices: even when the driver offers ES 3.1+, compute,
        // SSBOs and image load/store stay off.
        m_caps.floatRenderTargets = hasExtension("GL_EXT_color_buffer_float");
        m_caps.floatBlend = m_caps.floatRenderTargets && hasExtension("GL_EXT_float_blend");
        m_caps.timestampQueries = hasExtension("GL_EXT_disjoint_timer_query") && gl().glQueryCounter &&
                                  gl().glGetQueryObjectui64v;
        limits.storageBufferOffsetAlignment = 0;
        m_floatLinearFilterable = hasExtension("GL_OES_texture_float_linear");
        m_anisotropy = hasExtension("GL_EXT_texture_filter_anisotropic");
        m_readDepthNV = hasExtension("GL_NV_read_depth");
    }
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
    f.glDebugMessageCallback(onDebugMessage, m_context.get());
    f.glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_NOTIFICATION, 0, nullptr, GL_FALSE);
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
// Resource creation (validation lives with each resource's constructor)

BufferHandle Device::createBuffer(const BufferDesc& desc) {
    m_context->makeCurrent();
    if (any(desc.usage, BufferUsage::Storage)) require(Capability::StorageBuffers, "BufferUsage::Storage");
    return std::make_shared<Buffer>(m_context, desc);
}

TextureHandle Device::createTexture(const TextureDesc& desc) {
    m_context->makeCurrent();
    const std::string name = desc.debugName.empty() ? std::string("texture") : fmt::format("texture '{}'", desc.debugName);
    if (desc.format == Format::Unknown)
        throw Error(ErrorCode::InvalidDescription, fmt::format("{}: TextureDesc::format is Unknown; pick a format", name));
    if (desc.width == 0 || desc.height == 0 || desc.depth == 0)
        throw Error(ErrorCode::InvalidDescription,
                    fmt::format("{}: TextureDesc size {}x{}x{} has a zero extent; every extent must be >= 1",
                                name, desc.width, desc.height, desc.depth));
    const Limits& limits = m_caps.limits;
    uint32_t maxSize = limits.maxTextureSize2D;
    switch (desc.dimension) {
        case TextureDimension::Texture2D:
            if (desc.depth != 1)
                throw Error(ErrorCode::InvalidDescription,
                            fmt::format("{}: TextureDesc::depth is {} but a 2D texture has depth 1", name, desc.depth));
            break;
        case TextureDimension::TextureCube:
            maxSize = limits.maxTextureSizeCube;
            if (desc.width != desc.height)
                throw Error(ErrorCode::InvalidDescription,
                            fmt::format("{}: cube map faces must be square but TextureDesc width {} != height {}",
                                        name, desc.width, desc.height));
            if (desc.depth != 1)
                throw Error(ErrorCode::InvalidDescription,
                            fmt::format("{}: TextureDesc::depth is {} but a cube map has depth 1 (6 faces are implied)",
                                        name, desc.depth));
            break;
        case TextureDimension::Texture3D:
            maxSize = limits.maxTextureSize3D;
            if (isDepthFormat(desc.format))
                throw Error(ErrorCode::InvalidDescription,
                            fmt::format("{}: a 3D texture cannot have the depth format {}", name, toString(desc.format)));
            break;
        case TextureDimension::Texture2DArray: break;   // layers: validateTextureLayers below
        case TextureDimension::TextureCubeArray: maxSize = limits.maxTextureSizeCube; break;
    }
    validateTextureLayers(desc, m_caps, m_info.backend);
    if (std::max({desc.width, desc.height, desc.dimension == TextureDimension::Texture3D ? desc.depth : 1u}) > maxSize)
        throw Error(ErrorCode::InvalidDescription,
                    fmt::format("{}: TextureDesc size {}x{}x{} exceeds this device's {} limit of {}", name, desc.width,
                                desc.height, desc.depth, toString(desc.dimension), maxSize));
    const uint32_t fullChain = fullMipCount(desc.width, desc.height,
                                            desc.dimension == TextureDimension::Texture3D ? desc.depth : 1);
    if (desc.mipLevels > fullChain)
        throw Error(ErrorCode::InvalidDescription,
                    fmt::format("{}: TextureDesc::mipLevels is {} but a {}x{}x{} texture has at most {} levels", name,
                                desc.mipLevels, desc.width, desc.height, desc.depth, fullChain));
    if (desc.usage == TextureUsage::None)
        throw Error(ErrorCode::InvalidDescription,
                    fmt::format("{}: TextureDesc::usage is None; give Sampled, RenderTarget and/or Storage", name));
    const FormatInfo& info = formatInfo(desc.format);
    if (any(desc.usage, TextureUsage::Storage)) {
        require(Capability::StorageImages, "TextureUsage::Storage");
        // GL has no sRGB or depth image formats for load/store (and neither do most Vulkan drivers).
        if (info.srgb || info.kind == FormatKind::Depth)
            throw Error(ErrorCode::InvalidDescription,
                        fmt::format("{}: TextureUsage::Storage is not available for {} textures; use a linear "
                                    "colour format (rgba8, rgba16f, rgba32f, r11g11b10f, r32f, r32ui)",
                                    name, toString(desc.format)));
    }
    if (any(desc.usage, TextureUsage::RenderTarget) && info.kind == FormatKind::Float)
        require(Capability::FloatRenderTargets, fmt::format("rendering to a {} texture", toString(desc.format)));

    TextureDesc resolved = desc;
    if (resolved.mipLevels == 0) resolved.mipLevels = fullChain;
    return std::make_shared<Texture>(m_context, resolved);
}

SamplerHandle Device::createSampler(const SamplerDesc& desc) {
    m_context->makeCurrent();
    if (!(desc.minLod <= desc.maxLod))
        throw Error(ErrorCode::InvalidDescription,
                    fmt::format("SamplerDesc minLod {} is above maxLod {}", desc.minLod, desc.maxLod));
    if (!(desc.maxAnisotropy >= 1.0f))
        throw Error(ErrorCode::InvalidDescription,
                    fmt::format("SamplerDesc::maxAnisotropy is {}; it must be >= 1", desc.maxAnisotropy));
    return std::make_shared<Sampler>(m_context, desc, m_anisotropy);
}

ShaderHandle Device::createShader(const ShaderDesc& desc) {
    m_context->makeCurrent();
    if (desc.stage == ShaderStage::Compute) require(Capability::Compute, "a compute shader");
    return std::make_shared<Shader>(m_context, desc);
}

PipelineHandle Device::createGraphicsPipeline(const GraphicsPipelineDesc& desc) {
    m_context->makeCurrent();
    const std::string name = desc.debugName.empty() ? std::string("graphics pipeline")
                                                    : fmt::format("graphics pipeline '{}'", desc.debugName);
    if (!desc.vertexShader || !desc.fragmentShader)
        throw Error(ErrorCode::InvalidDescription,
                    fmt::format("{}: GraphicsPipelineDesc needs both a vertex and a fragment shader", name));
    ownResource<Shader>(desc.vertexShader, *m_context, name.c_str(), "vertex shader");
    ownResource<Shader>(desc.fragmentShader, *m_context, name.c_str(), "fragment shader");
    if (desc.vertexShader->desc().stage != ShaderStage::Vertex || desc.fragmentShader->desc().stage != ShaderStage::Fragment)
        throw Error(ErrorCode::InvalidDescription,
                    fmt::format("{}: vertexShader must be a vertex shader and fragmentShader a fragment shader", name));
    if (desc.colorFormats.size() > m_caps.limits.maxColorAttachments)
        throw Error(ErrorCode::InvalidDescription,
                    fmt::format("{}: {} colour formats exceed the limit of {} attachments", name,
                                desc.colorFormats.size(), m_caps.limits.maxColorAttachments));
    for (const VertexAttribute& attribute : desc.vertexAttributes) {
        auto layout = std::find_if(desc.vertexBuffers.begin(), desc.vertexBuffers.end(),
                                   [&](const VertexBufferLayout& l) { return l.slot == attribute.bufferSlot; });
        if (layout == desc.vertexBuffers.end())
            throw Error(ErrorCode::InvalidDescription,
                        fmt::format("{}: vertex attribute at location {} reads buffer slot {}, which has no "
                                    "VertexBufferLayout; add one with addVertexBuffer",
                                    name, attribute.location, attribute.bufferSlot));
        if (attribute.location >= 16)
            throw Error(ErrorCode::InvalidDescription,
                        fmt::format("{}: vertex attribute location {} is above the limit of 15", name, attribute.location));
    }
    // GL would feed a missing attribute as (0, 0, 0, 1) and reinterpret a float attribute read as
    // an integer; Vulkan's validation rejects both, so reject them here too.
    for (const ShaderInput& input : static_cast<const Shader&>(*desc.vertexShader).inputs()) {
        auto attribute = std::find_if(desc.vertexAttributes.begin(), desc.vertexAttributes.end(),
                                      [&](const VertexAttribute& a) { return a.location == input.location; });
        if (attribute == desc.vertexAttributes.end())
            throw Error(ErrorCode::InvalidDescription,
                        fmt::format("{}: the vertex shader reads location {}, but no vertex attribute feeds it; add "
                                    "one with addVertexAttribute",
                                    name, input.location));
        const bool integerFormat = attribute->format == VertexFormat::UInt1;
        if (integerFormat != input.integer)
            throw Error(ErrorCode::InvalidDescription,
                        fmt::format("{}: vertex attribute at location {} is {} but the shader reads it as {}", name,
                                    input.location, integerFormat ? "an integer format (UInt1)" : "a float format",
                                    input.integer ? "an integer" : "a float"));
    }
    for (size_t i = 0; i < desc.colorFormats.size(); ++i) {
        const Format format = desc.colorFormats[i];
        const bool blends = i < desc.blend.size() && desc.blend[i].enable;
        if (blends && (format == Format::RGBA32_FLOAT || format == Format::R32_FLOAT))
            require(Capability::FloatBlend, fmt::format("blending into a {} attachment", toString(format)));
        if (blends && formatInfo(format).kind == FormatKind::UInt)
            throw Error(ErrorCode::InvalidDescription,
                        fmt::format("{}: colour attachment {} is {}, an integer format, which cannot blend; disable blending for it",
                                    name, i, toString(format)));
    }
    if (isES()) {
        // ES 3.0 has one blend state and one colour mask for all attachments.
        auto same = [](const BlendAttachment& a, const BlendAttachment& b) {
            return a.enable == b.enable && a.writeMask == b.writeMask &&
                   (!a.enable || (a.srcColor == b.srcColor && a.dstColor == b.dstColor && a.colorOp == b.colorOp &&
                                  a.srcAlpha == b.srcAlpha && a.dstAlpha == b.dstAlpha && a.alphaOp == b.alphaOp));
        };
        for (size_t i = 1; i < desc.colorFormats.size(); ++i) {
            BlendAttachment first = desc.blend.empty() ? BlendAttachment{} : desc.blend[0];
            BlendAttachment other = i < desc.blend.size() ? desc.blend[i] : BlendAttachment{};
            if (!same(first, other))
                throw Error(ErrorCode::InvalidDescription,
                            fmt::format("{}: colour attachment {} blends differently from attachment 0, but OpenGL "
                                        "ES 3.0 applies one blend state to every attachment; use the same state",
                                        name, i));
        }
    }
    return std::make_shared<Pipeline>(m_context, desc);
}

PipelineHandle Device::createComputePipeline(const ComputePipelineDesc& desc) {
    m_context->makeCurrent();
    require(Capability::Compute, "a compute pipeline");
    if (!desc.computeShader || desc.computeShader->desc().stage != ShaderStage::Compute)
        throw Error(ErrorCode::InvalidDescription, "ComputePipelineDesc::computeShader must be a compute shader");
    ownResource<Shader>(desc.computeShader, *m_context, "compute pipeline", "compute shader");
    return std::make_shared<Pipeline>(m_context, desc);
}

BindingSetHandle Device::createBindingSet(const BindingSetDesc& desc) {
    for (const BindingItem& item : desc.items) {
        const auto where = fmt::format("binding {}", item.binding);
        if (item.buffer) ownResource<Buffer>(item.buffer, *m_context, where.c_str(), "buffer");
        if (item.texture) ownResource<Texture>(item.texture, *m_context, where.c_str(), "texture");
        if (item.sampler) ownResource<Sampler>(item.sampler, *m_context, where.c_str(), "sampler");
        switch (item.type) {
            case ResourceType::UniformBuffer:
            case ResourceType::StorageBuffer: {
                const bool uniform = item.type == ResourceType::UniformBuffer;
                if (!uniform) require(Capability::StorageBuffers, "a storage-buffer binding");
                if (!item.buffer)
                    throw Error(ErrorCode::InvalidDescription, fmt::format("{}: the BindingItem has no buffer", where));
                const BufferDesc& bd = item.buffer->desc();
                if (!any(bd.usage, uniform ? BufferUsage::Uniform : BufferUsage::Storage))
                    throw Error(ErrorCode::InvalidDescription,
                                fmt::format("{}: buffer '{}' is bound as a {} buffer but lacks BufferUsage::{}", where,
                                            bd.debugName, uniform ? "uniform" : "storage", uniform ? "Uniform" : "Storage"));
                const uint64_t alignment = uniform ? m_caps.limits.uniformBufferOffsetAlignment
                                                   : m_caps.limits.storageBufferOffsetAlignment;
                if (alignment && item.offset % alignment != 0)
                    throw Error(ErrorCode::InvalidDescription,
                                fmt::format("{}: offset {} is not a multiple of the device's {} buffer offset "
                                            "alignment {}",
                                            where, item.offset, uniform ? "uniform" : "storage", alignment));
                if (item.offset >= bd.size || item.offset + item.range > bd.size)
                    throw Error(ErrorCode::InvalidDescription,
                                fmt::format("{}: offset {} + range {} exceeds the buffer size {}", where, item.offset,
                                            item.range, bd.size));
                const uint64_t range = item.range ? item.range : bd.size - item.offset;
                if (uniform && range > m_caps.limits.maxUniformBufferRange && item.range != 0)
                    throw Error(ErrorCode::InvalidDescription,
                                fmt::format("{}: range {} exceeds the uniform buffer range limit {}", where, range,
                                            m_caps.limits.maxUniformBufferRange));
                break;
            }
            case ResourceType::SampledTexture:
                if (!item.texture || !item.sampler)
                    throw Error(ErrorCode::InvalidDescription,
                                fmt::format("{}: a sampled-texture BindingItem needs a texture and a sampler", where));
                if (!any(item.texture->desc().usage, TextureUsage::Sampled))
                    throw Error(ErrorCode::InvalidDescription,
                                fmt::format("{}: texture '{}' lacks TextureUsage::Sampled", where,
                                            item.texture->desc().debugName));
                break;
            case ResourceType::StorageImage:
                require(Capability::StorageImages, "a storage-image binding");
                if (!item.texture)
                    throw Error(ErrorCode::InvalidDescription, fmt::format("{}: the BindingItem has no texture", where));
                if (!any(item.texture->desc().usage, TextureUsage::Storage))
                    throw Error(ErrorCode::InvalidDescription,
                                fmt::format("{}: texture '{}' lacks TextureUsage::Storage", where,
                                            item.texture->desc().debugName));
                if (item.mipLevel >= item.texture->desc().mipLevels)
                    throw Error(ErrorCode::InvalidDescription,
                                fmt::format("{}: mip level {} does not exist (the texture has {})", where,
                                            item.mipLevel, item.texture->desc().mipLevels));
                break;
        }
        if (item.type == ResourceType::SampledTexture || item.type == ResourceType::StorageImage)
            validateTextureView(item, m_caps, m_info.backend, fmt::format("BindingSetDesc item {} (binding {})", size_t(&item - desc.items.data()), item.binding));
    }
    return std::make_shared<BindingSet>(desc);
}

TimerQueryHandle Device::createTimerQuery() {
    m_context->makeCurrent();
    require(Capability::TimestampQueries, "a timer query");
    return std::make_shared<TimerQuery>(m_context);
}

CommandListHandle Device::createCommandList() { return std::make_shared<CommandList>(*this); }

// ---------------------------------------------------------------------------------------------
// Execution

void Device::execute(const CommandListHandle& commandList) {
    auto* list = dynamic_cast<CommandList*>(commandList.get());
    if (!list) throw Error(ErrorCode::InvalidUsage, "execute() was given a command list from another backend or none");
    m_context->makeCurrent();
    // Replay state never carries over between lists: what it points at is only kept alive by the
    // list that set it (and each list must set its own pipeline and buffers anyway).
    m_pipeline = nullptr;
    m_vertexBuffers.clear();
    m_indexBuffer = 0;
    m_vertexStateDirty = true;
    m_boundIndexBuffer = 0;
    list->replay();
    m_pipeline = nullptr;
}

void Device::waitIdle() {
    m_context->makeCurrent();
    gl().glFinish();
}

std::vector<DebugMessage> Device::takeDebugMessages() { return m_context->takeDebugMessages(); }

void Device::provokeValidationErrorForTesting() {
    m_context->makeCurrent();
    // GL_INVALID_ENUM on every GL and ES version: 0 is not a capability.
    gl().glEnable(0);
    gl().glGetError();   // the debug callback has reported it; clear the sticky flag
}

// ---------------------------------------------------------------------------------------------
// Immediate transfers

namespace {
void checkBufferRange(const Buffer& buffer, uint64_t offset, uint64_t size, const char* what) {
    if (size == 0 || offset > buffer.desc().size || size > buffer.desc().size - offset)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("{}: bytes [{}, {}) are outside buffer '{}' of {} bytes (or the size is 0)", what,
                                offset, offset + size, buffer.desc().debugName, buffer.desc().size));
}
}  // namespace

void Device::bufferSubData(const Buffer& buffer, const void* data, uint64_t size, uint64_t offset) {
    gl().glBindBuffer(GL_COPY_WRITE_BUFFER, buffer.name());
    gl().glBufferSubData(GL_COPY_WRITE_BUFFER, GLintptr(offset), GLsizeiptr(size), data);
}

void Device::writeBuffer(const BufferHandle& handle, const void* data, uint64_t size, uint64_t offset) {
    const Buffer& buffer = ownResource<Buffer>(handle, *m_context, "writeBuffer", "buffer");
    checkBufferRange(buffer, offset, size, "writeBuffer");
    if (!data) throw Error(ErrorCode::InvalidUsage, "writeBuffer: data is null");
    m_context->makeCurrent();
    bufferSubData(buffer, data, size, offset);
}

std::vector<std::byte> Device::readBuffer(const BufferHandle& handle, uint64_t offset, uint64_t size) {
    const Buffer& buffer = ownResource<Buffer>(handle, *m_context, "readBuffer", "buffer");
    if (size == 0 && offset < buffer.desc().size) size = buffer.desc().size - offset;
    checkBufferRange(buffer, offset, size, "readBuffer");
    m_context->makeCurrent();
    const GLFunctions& f = gl();
    f.glBindBuffer(GL_COPY_READ_BUFFER, buffer.name());
    const void* mapped = f.glMapBufferRange(GL_COPY_READ_BUFFER, GLintptr(offset), GLsizeiptr(size), GL_MAP_READ_BIT);
    if (!mapped)
        throw Error(ErrorCode::OutOfMemory, fmt::format("readBuffer: mapping {} bytes of buffer '{}' failed", size,
                                                        buffer.desc().debugName));
    std::vector<std::byte> result(size);
    std::memcpy(result.data(), mapped, size);
    f.glUnmapBuffer(GL_COPY_READ_BUFFER);
    return result;
}

void Device::writeTexture(const TextureHandle& handle, TextureSubresource sub, const void* data, uint64_t size) {
    const Texture& texture = ownResource<Texture>(handle, *m_context, "writeTexture", "texture");
    texture.validateSubresource(sub, "writeTexture");
    const uint64_t expected = texture.subresourceSize(sub.mipLevel);
    if (size != expected)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("writeTexture: {} bytes given but mip {} of '{}' holds {} bytes ({}x{} {}, tightly "
                                "packed)",
                                size, sub.mipLevel, texture.desc().debugName, expected, texture.width(sub.mipLevel),
                                texture.height(sub.mipLevel), toString(texture.desc().format)));
    if (!data) throw Error(ErrorCode::InvalidUsage, "writeTexture: data is null");
    m_context->makeCurrent();
    gl().glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    uploadTexture(texture, sub, data);
}

std::vector<std::byte> Device::readTexture(const TextureHandle& handle, TextureSubresource sub) {
    const Texture& texture = ownResource<Texture>(handle, *m_context, "readTexture", "texture");
    texture.validateSubresource(sub, "readTexture");
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
