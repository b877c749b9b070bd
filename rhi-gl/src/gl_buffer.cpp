// Buffers: one GL buffer object each, usable for every role its usage names.
#include <fmt/format.h>

#include <cstddef>
#include <cstdlib>
#include <memory>

#include "gl_device.h"

namespace janus::rhi::gl {

// `desc` is validated (size within Limits::maxBufferSize, 2^31 on GL).
Buffer::Buffer(ContextPtr context, const BufferDesc& desc) : m_context(std::move(context)), m_desc(desc) {
    const GLFunctions& gl = m_context->gl;
    // calloc: large zero blocks come from fresh pages, without a pass over them here.
    const std::unique_ptr<void, decltype(&std::free)> zeros(std::calloc(size_t(desc.size), 1), &std::free);
    if (!zeros)
        throw Error(ErrorCode::OutOfMemory,
                    fmt::format("buffer '{}': no host memory for the {} zero bytes of its first contents", desc.debugName,
                                desc.size));
    gl.glGenBuffers(1, &m_name);
    gl.glBindBuffer(GL_COPY_WRITE_BUFFER, m_name);
    // New buffers read as zero (rhi.h); GL leaves their contents undefined. The zeros come from
    // the host, with the storage. Not glClearBufferData: on NVIDIA's GL driver (580, H200) a
    // clear followed by glBufferSubData could end with the clear's zeros over the written data in
    // a process that had not started NVIDIA's Vulkan driver first (a 6-byte index buffer, the
    // bench's vertex or uniform buffer: their draws drew nothing; session 19).
    gl.glBufferData(GL_COPY_WRITE_BUFFER, GLsizeiptr(desc.size), zeros.get(), GL_DYNAMIC_DRAW);
    if (gl.glGetError() == GL_OUT_OF_MEMORY) {
        gl.glDeleteBuffers(1, &m_name);
        throw Error(ErrorCode::OutOfMemory,
                    fmt::format("buffer '{}': the driver could not allocate {} bytes", desc.debugName, desc.size));
    }
    if (!desc.debugName.empty() && gl.glObjectLabel && !m_context->isES())
        gl.glObjectLabel(GL_BUFFER, m_name, GLsizei(desc.debugName.size()), desc.debugName.data());
}

Buffer::~Buffer() {
    m_context->deleteObjects(GLObjectKind::Buffer, std::span(&m_name, 1));
}

}  // namespace janus::rhi::gl
