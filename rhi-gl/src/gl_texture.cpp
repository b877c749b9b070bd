// Textures (immutable storage) and samplers.
#include <fmt/format.h>

#include <cstddef>
#include <vector>

#include "gl_device.h"
#include "janus/shaders/shaders.h"

namespace janus::rhi::gl {

namespace {
// EXT_texture_filter_anisotropic (core in GL 4.6); glcorearb.h for 4.3 may lack the token.
constexpr GLenum kTextureMaxAnisotropy = 0x84FE;

void bindForEdit(const GLFunctions& gl, GLenum target, GLuint texture) {
    gl.glActiveTexture(GL_TEXTURE0 + kScratchTextureUnit);
    gl.glBindTexture(target, texture);
}

GLenum toGL(Filter filter) { return filter == Filter::Nearest ? GL_NEAREST : GL_LINEAR; }

GLenum minFilter(Filter min, Filter mip) {
    if (min == Filter::Nearest) return mip == Filter::Nearest ? GL_NEAREST_MIPMAP_NEAREST : GL_NEAREST_MIPMAP_LINEAR;
    return mip == Filter::Nearest ? GL_LINEAR_MIPMAP_NEAREST : GL_LINEAR_MIPMAP_LINEAR;
}

GLenum toGL(AddressMode mode) {
    switch (mode) {
        case AddressMode::Repeat: return GL_REPEAT;
        case AddressMode::MirroredRepeat: return GL_MIRRORED_REPEAT;
        case AddressMode::ClampToEdge: return GL_CLAMP_TO_EDGE;
    }
    return GL_REPEAT;
}
}  // namespace

GLenum compareFunction(CompareOp op) {
    switch (op) {
        case CompareOp::Never: return GL_NEVER;
        case CompareOp::Less: return GL_LESS;
        case CompareOp::Equal: return GL_EQUAL;
        case CompareOp::LessOrEqual: return GL_LEQUAL;
        case CompareOp::Greater: return GL_GREATER;
        case CompareOp::NotEqual: return GL_NOTEQUAL;
        case CompareOp::GreaterOrEqual: return GL_GEQUAL;
        case CompareOp::Always: return GL_ALWAYS;
    }
    return GL_ALWAYS;
}

const GLFormat& glFormat(Format format) {
    static const GLFormat kUnknown{};
    static const GLFormat kRGBA8{GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE};
    static const GLFormat kSRGBA8{GL_SRGB8_ALPHA8, GL_RGBA, GL_UNSIGNED_BYTE};
    static const GLFormat kRGBA16F{GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT};
    static const GLFormat kRGBA32F{GL_RGBA32F, GL_RGBA, GL_FLOAT};
    static const GLFormat kR11G11B10F{GL_R11F_G11F_B10F, GL_RGB, GL_UNSIGNED_INT_10F_11F_11F_REV};
    static const GLFormat kR32UI{GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT};
    static const GLFormat kRGBA32UI{GL_RGBA32UI, GL_RGBA_INTEGER, GL_UNSIGNED_INT};
    static const GLFormat kR32F{GL_R32F, GL_RED, GL_FLOAT};
    static const GLFormat kD32F{GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT};
    switch (format) {
        case Format::Unknown: return kUnknown;
        case Format::RGBA8_UNORM: return kRGBA8;
        case Format::RGBA8_SRGB: return kSRGBA8;
        case Format::RGBA16_FLOAT: return kRGBA16F;
        case Format::RGBA32_FLOAT: return kRGBA32F;
        case Format::R11G11B10_FLOAT: return kR11G11B10F;
        case Format::R32_UINT: return kR32UI;
        case Format::RGBA32_UINT: return kRGBA32UI;
        case Format::R32_FLOAT: return kR32F;
        case Format::D32_FLOAT: return kD32F;
    }
    return kUnknown;
}

// ---------------------------------------------------------------------------------------------

Texture::Texture(ContextPtr context, const TextureDesc& resolvedDesc)
    : m_context(std::move(context)), m_desc(resolvedDesc) {
    const GLFunctions& gl = m_context->gl;
    if (m_desc.sampleCount > 1) {
        createRenderbuffer();
        return;
    }
    switch (m_desc.dimension) {
        case TextureDimension::Texture2D: m_target = GL_TEXTURE_2D; break;
        case TextureDimension::TextureCube: m_target = GL_TEXTURE_CUBE_MAP; break;
        case TextureDimension::Texture3D: m_target = GL_TEXTURE_3D; break;
        case TextureDimension::Texture2DArray: m_target = GL_TEXTURE_2D_ARRAY; break;
        case TextureDimension::TextureCubeArray: m_target = GL_TEXTURE_CUBE_MAP_ARRAY; break;
    }
    m_maxLevel = m_desc.mipLevels - 1;
    gl.glGenTextures(1, &m_name);
    bindForEdit(gl, m_target, m_name);
    const GLenum internalFormat = format().internalFormat;
    if (m_target == GL_TEXTURE_3D || m_target == GL_TEXTURE_2D_ARRAY || m_target == GL_TEXTURE_CUBE_MAP_ARRAY)
        // Arrays: depth = layers (cube arrays: layer-faces, 6 x cubes).
        gl.glTexStorage3D(m_target, GLsizei(m_desc.mipLevels), internalFormat, GLsizei(m_desc.width),
                          GLsizei(m_desc.height), GLsizei(m_target == GL_TEXTURE_3D ? m_desc.depth : m_desc.arrayLayers));
    else
        gl.glTexStorage2D(m_target, GLsizei(m_desc.mipLevels), internalFormat, GLsizei(m_desc.width),
                          GLsizei(m_desc.height));
    if (gl.glGetError() == GL_OUT_OF_MEMORY) {
        gl.glDeleteTextures(1, &m_name);
        throw Error(ErrorCode::OutOfMemory, fmt::format("texture '{}': the driver could not allocate {}x{}x{} {}",
                                                        m_desc.debugName, m_desc.width, m_desc.height, m_desc.depth,
                                                        toString(m_desc.format)));
    }
    zeroContents();
    if (!m_desc.debugName.empty() && gl.glObjectLabel && !m_context->isES())
        gl.glObjectLabel(GL_TEXTURE, m_name, GLsizei(m_desc.debugName.size()), m_desc.debugName.data());
}

// A multisampled texture (validated: a 2D render target, one mip, a count the format table allows).
void Texture::createRenderbuffer() {
    const GLFunctions& gl = m_context->gl;
    m_target = GL_RENDERBUFFER;
    m_firstUse = true;
    gl.glGenRenderbuffers(1, &m_name);
    gl.glBindRenderbuffer(GL_RENDERBUFFER, m_name);
    gl.glRenderbufferStorageMultisample(GL_RENDERBUFFER, GLsizei(m_desc.sampleCount), format().internalFormat,
                                        GLsizei(m_desc.width), GLsizei(m_desc.height));
    gl.glBindRenderbuffer(GL_RENDERBUFFER, 0);
    if (gl.glGetError() == GL_OUT_OF_MEMORY) {
        gl.glDeleteRenderbuffers(1, &m_name);
        throw Error(ErrorCode::OutOfMemory, fmt::format("texture '{}': the driver could not allocate {}x{} {} with {} samples",
                                                        m_desc.debugName, m_desc.width, m_desc.height,
                                                        toString(m_desc.format), m_desc.sampleCount));
    }
    if (!m_desc.debugName.empty() && gl.glObjectLabel && !m_context->isES())
        gl.glObjectLabel(GL_RENDERBUFFER, m_name, GLsizei(m_desc.debugName.size()), m_desc.debugName.data());
}

void Texture::zeroContents() const {
    // New textures read as zero (rhi.h); GL leaves immutable storage undefined.
    const GLFunctions& gl = m_context->gl;
    const GLFormat& glf = format();
    if (m_context->clearTexImage) {
        for (uint32_t mip = 0; mip < m_desc.mipLevels; ++mip)
            gl.glClearTexImage(m_name, GLint(mip), glf.uploadFormat, glf.uploadType, nullptr);
        return;
    }
    // Without glClearTexImage: upload zeros, one whole level (a cube: one face) at a time. The
    // texture is still bound to the scratch unit from its creation.
    gl.glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    const std::vector<std::byte> zeros(subresourceSize(0) * layers(0));
    for (uint32_t mip = 0; mip < m_desc.mipLevels; ++mip) {
        const auto w = GLsizei(width(mip)), h = GLsizei(height(mip));
        switch (m_desc.dimension) {
            case TextureDimension::Texture2D:
                gl.glTexSubImage2D(GL_TEXTURE_2D, GLint(mip), 0, 0, w, h, glf.uploadFormat, glf.uploadType, zeros.data());
                break;
            case TextureDimension::TextureCube:
                for (GLenum face = 0; face < 6; ++face)
                    gl.glTexSubImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + face, GLint(mip), 0, 0, w, h, glf.uploadFormat,
                                       glf.uploadType, zeros.data());
                break;
            case TextureDimension::Texture3D:
            case TextureDimension::Texture2DArray:
            case TextureDimension::TextureCubeArray:
                gl.glTexSubImage3D(m_target, GLint(mip), 0, 0, 0, w, h, GLsizei(layers(mip)), glf.uploadFormat,
                                   glf.uploadType, zeros.data());
                break;
        }
    }
}

Texture::~Texture() {
    for (auto& [key, view] : m_views) m_context->deleteObjects(GLObjectKind::Texture, std::span(&view, 1));
    m_context->deleteObjects(isRenderbuffer() ? GLObjectKind::Renderbuffer : GLObjectKind::Texture, std::span(&m_name, 1));
}

namespace {
GLenum viewTarget(TextureDimension dimension) {
    switch (dimension) {
        case TextureDimension::Texture2D: return GL_TEXTURE_2D;
        case TextureDimension::Texture3D: return GL_TEXTURE_3D;
        case TextureDimension::TextureCube: return GL_TEXTURE_CUBE_MAP;
        case TextureDimension::Texture2DArray: return GL_TEXTURE_2D_ARRAY;
        case TextureDimension::TextureCubeArray: return GL_TEXTURE_CUBE_MAP_ARRAY;
    }
    return GL_TEXTURE_2D;
}
}  // namespace

std::pair<GLuint, GLenum> Texture::viewFor(const ResolvedTextureView& view) const {
    if (isWholeTexture(view, m_desc)) return {m_name, m_target};
    const auto key = std::make_tuple(int(view.dimension), view.baseMip, view.mipCount, view.baseLayer, view.layerCount);
    const GLenum target = viewTarget(view.dimension);
    if (auto it = m_views.find(key); it != m_views.end()) return {it->second, target};
    // Views need immutable storage (we always use glTexStorage*) and GL 4.3 / ARB_texture_view
    // (Capability::TextureViews; binding sets check it). A volume's view has its one layer.
    const GLFunctions& gl = m_context->gl;
    const bool volume = view.dimension == TextureDimension::Texture3D;
    GLuint name = 0;
    gl.glGenTextures(1, &name);
    gl.glTextureView(name, target, m_name, format().internalFormat, view.baseMip, view.mipCount,
                     volume ? 0 : view.baseLayer, volume ? 1 : view.layerCount);
    m_views.emplace(key, name);
    return {name, target};
}

void Texture::applyMipRange(uint32_t baseMip, uint32_t mipCount) const {
    const uint32_t maxLevel = baseMip + mipCount - 1;
    const GLFunctions& gl = m_context->gl;
    if (m_baseLevel != baseMip) gl.glTexParameteri(m_target, GL_TEXTURE_BASE_LEVEL, GLint(baseMip));
    if (m_maxLevel != maxLevel) gl.glTexParameteri(m_target, GL_TEXTURE_MAX_LEVEL, GLint(maxLevel));
    m_baseLevel = baseMip;
    m_maxLevel = maxLevel;
}

uint32_t Texture::layers(uint32_t mip) const {
    switch (m_desc.dimension) {
        case TextureDimension::Texture2D: return 1;
        case TextureDimension::TextureCube: return 6;
        case TextureDimension::Texture3D: return mipExtent(m_desc.depth, mip);
        case TextureDimension::Texture2DArray:
        case TextureDimension::TextureCubeArray: return m_desc.arrayLayers;
    }
    return 1;
}

uint64_t Texture::subresourceSize(uint32_t mip) const {
    return uint64_t(width(mip)) * height(mip) * formatInfo(m_desc.format).bytesPerPixel;
}

void Texture::attach(GLenum framebufferTarget, GLenum attachmentPoint, uint32_t mip, uint32_t layer) const {
    const GLFunctions& gl = m_context->gl;
    if (isRenderbuffer()) return gl.glFramebufferRenderbuffer(framebufferTarget, attachmentPoint, GL_RENDERBUFFER, m_name);
    switch (m_desc.dimension) {
        case TextureDimension::Texture2D:
            gl.glFramebufferTexture2D(framebufferTarget, attachmentPoint, GL_TEXTURE_2D, m_name, GLint(mip));
            break;
        case TextureDimension::TextureCube:
            // Face targets work on GL 4.3 and ES 3.0 alike (layered attach of a cube needs 4.5).
            gl.glFramebufferTexture2D(framebufferTarget, attachmentPoint, GL_TEXTURE_CUBE_MAP_POSITIVE_X + layer,
                                      m_name, GLint(mip));
            break;
        case TextureDimension::Texture3D:
        case TextureDimension::Texture2DArray:
        case TextureDimension::TextureCubeArray:   // layer = layer-face, 6 * cube + face
            gl.glFramebufferTextureLayer(framebufferTarget, attachmentPoint, m_name, GLint(mip), GLint(layer));
            break;
    }
}

// ---------------------------------------------------------------------------------------------
// Texture transfers (the device's, since they use its framebuffer cache)

void Device::uploadTexture(const Texture& texture, TextureSubresource sub, const void* pixels) {
    const GLFunctions& f = gl();
    const GLFormat& format = texture.format();
    const auto width = GLsizei(texture.width(sub.mipLevel)), height = GLsizei(texture.height(sub.mipLevel));
    bindForEdit(f, texture.target(), texture.name());
    switch (texture.desc().dimension) {
        case TextureDimension::Texture2D:
            f.glTexSubImage2D(GL_TEXTURE_2D, GLint(sub.mipLevel), 0, 0, width, height, format.uploadFormat,
                              format.uploadType, pixels);
            break;
        case TextureDimension::TextureCube:
            f.glTexSubImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + sub.layer, GLint(sub.mipLevel), 0, 0, width, height,
                              format.uploadFormat, format.uploadType, pixels);
            break;
        case TextureDimension::Texture3D:
        case TextureDimension::Texture2DArray:
        case TextureDimension::TextureCubeArray:
            f.glTexSubImage3D(texture.target(), GLint(sub.mipLevel), 0, 0, GLint(sub.layer), width, height, 1,
                              format.uploadFormat, format.uploadType, pixels);
            break;
    }
}

void Device::copyTextureImage(const Texture& dst, TextureSubresource dstSub, const Texture& src,
                                TextureSubresource srcSub) {
    const GLFunctions& f = gl();
    const auto width = GLsizei(src.width(srcSub.mipLevel)), height = GLsizei(src.height(srcSub.mipLevel));
    if (!isES()) {
        // A raw copy: no filtering, no sRGB conversion, depth included.
        f.glCopyImageSubData(src.name(), src.target(), GLint(srcSub.mipLevel), 0, 0, GLint(srcSub.layer), dst.name(),
                             dst.target(), GLint(dstSub.mipLevel), 0, 0, GLint(dstSub.layer), width, height, 1);
        return;
    }
    // ES 3.0 has no glCopyImageSubData: blit between two single-attachment framebuffers.
    const bool depth = isDepthFormat(src.desc().format);
    auto framebufferFor = [&](const Texture& texture, TextureSubresource sub) {
        FramebufferKey key;
        const AttachmentKey attachment{texture.name(), sub.mipLevel, sub.layer};
        if (depth) {
            key.depth = attachment;
            return m_context->framebuffer(key, {}, &texture);
        }
        key.colors.push_back(attachment);
        return m_context->framebuffer(key, {&texture}, nullptr);
    };
    const GLuint readFbo = framebufferFor(src, srcSub);
    const GLuint drawFbo = framebufferFor(dst, dstSub);
    f.glBindFramebuffer(GL_READ_FRAMEBUFFER, readFbo);
    f.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, drawFbo);
    f.glDisable(GL_SCISSOR_TEST);
    f.glBlitFramebuffer(0, 0, width, height, 0, 0, width, height, depth ? GL_DEPTH_BUFFER_BIT : GL_COLOR_BUFFER_BIT,
                        GL_NEAREST);
    f.glEnable(GL_SCISSOR_TEST);
}

std::vector<std::byte> Device::readDepthThroughColor(const Texture& texture, TextureSubresource sub) {
    require(Capability::FloatRenderTargets, "reading back depth on OpenGL ES without GL_NV_read_depth (via r32f)");
    const GLFunctions& f = gl();
    if (!m_depthCopyPipeline) {
        auto load = [&](ShaderStage stage, const char* name) {
            return std::make_shared<Shader>(
                m_context, ShaderDesc().setStage(stage).setSpirv(janus::shaders::get(name)).setDebugName(name));
        };
        GraphicsPipelineDesc desc;
        desc.setShaders(load(ShaderStage::Vertex, "gl_depth_copy_vert"), load(ShaderStage::Fragment, "gl_depth_copy_frag"))
            .addColorFormat(Format::R32_FLOAT)
            .setDebugName("GL depth-to-colour copy");
        m_depthCopyPipeline = std::make_shared<Pipeline>(m_context, desc);
    }
    const uint32_t width = texture.width(sub.mipLevel), height = texture.height(sub.mipLevel);
    // The image alone as mip 0 of a 2D texture (a depth blit reaches cube faces and mips), so
    // the shader needs no face or level logic.
    const Texture flat(m_context, TextureDesc().setFormat(Format::D32_FLOAT).setSize(width, height)
                                        .setUsage(TextureUsage::Sampled | TextureUsage::RenderTarget));
    copyTextureImage(flat, {}, texture, sub);
    const Texture color(m_context, TextureDesc().setFormat(Format::R32_FLOAT).setSize(width, height)
                                         .setUsage(TextureUsage::RenderTarget));
    FramebufferKey key;
    key.colors.push_back({color.name(), 0, 0});
    f.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_context->framebuffer(key, {&color}, nullptr));
    f.glViewport(0, 0, GLsizei(width), GLsizei(height));
    f.glScissor(0, 0, GLsizei(width), GLsizei(height));
    m_context->state.setDepthRange(0.0f, 1.0f);
    m_depthCopyPipeline->applyState();
    f.glActiveTexture(GL_TEXTURE0 + kDepthCopyTextureUnit);
    f.glBindTexture(GL_TEXTURE_2D, flat.name());
    f.glBindSampler(kDepthCopyTextureUnit, 0);
    // ES treats a depth texture under linear filtering as incomplete, even for texelFetch.
    f.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    f.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    f.glDrawArrays(GL_TRIANGLES, 0, 3);
    std::vector<std::byte> depth = downloadTexture(color, {});
    // A command list may be mid-replay (copyTextureToBuffer): give it its pipeline back. Else no
    // program stays in use (see Device::execute): `flat`, which it samples, is deleted below.
    if (m_pipeline)
        m_pipeline->applyState();
    else
        f.glUseProgram(0);
    return depth;
}

// ---------------------------------------------------------------------------------------------
// Samplers

Sampler::Sampler(ContextPtr context, const SamplerDesc& desc, bool anisotropySupported)
    : m_context(std::move(context)), m_desc(desc) {
    const GLFunctions& gl = m_context->gl;
    auto configure = [&](GLuint sampler) {
        gl.glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, GLint(minFilter(desc.minFilter, desc.mipFilter)));
        gl.glSamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER, GLint(toGL(desc.magFilter)));
        gl.glSamplerParameteri(sampler, GL_TEXTURE_WRAP_S, GLint(toGL(desc.addressU)));
        gl.glSamplerParameteri(sampler, GL_TEXTURE_WRAP_T, GLint(toGL(desc.addressV)));
        gl.glSamplerParameteri(sampler, GL_TEXTURE_WRAP_R, GLint(toGL(desc.addressW)));
        gl.glSamplerParameterf(sampler, GL_TEXTURE_MIN_LOD, desc.minLod);
        gl.glSamplerParameterf(sampler, GL_TEXTURE_MAX_LOD, desc.maxLod);
        if (desc.compare) {
            gl.glSamplerParameteri(sampler, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
            gl.glSamplerParameteri(sampler, GL_TEXTURE_COMPARE_FUNC, GLint(compareFunction(*desc.compare)));
        }
        if (anisotropySupported && desc.maxAnisotropy > 1.0f)
            gl.glSamplerParameterf(sampler, kTextureMaxAnisotropy, desc.maxAnisotropy);
    };
    gl.glGenSamplers(1, &m_name);
    configure(m_name);
}

Sampler::~Sampler() {
    m_context->deleteObjects(GLObjectKind::Sampler, std::span(&m_name, 1));
}

}  // namespace janus::rhi::gl
