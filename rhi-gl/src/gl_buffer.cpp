// Buffers: one GL buffer object each, usable for every role its usage names.
#include <fmt/format.h>

#include <cstddef>
#include <vector>

#include "gl_device.h"

namespace janus::rhi::gl {

// `desc` is validated (size within Limits::maxBufferSize, 2^31 on GL).
Buffer::Buffer(ContextPtr context, const BufferDesc& desc) : m_context(std::move(context)), m_desc(desc) {
    const GLFunctions& gl = m_context->gl;
    gl.glGenBuffers(1, &m_name);
    gl.glBindBuffer(GL_COPY_WRITE_BUFFER, m_name);
    // New buffers read as zero (rhi.h); GL leaves their contents undefined. Desktop GL 4.3 zeroes
    // on the device (glClearBufferData with no data); ES 3.0 can only upload zeros.
    if (gl.glClearBufferData) {
        gl.glBufferData(GL_COPY_WRITE_BUFFER, GLsizeiptr(desc.size), nullptr, GL_DYNAMIC_DRAW);
        if (gl.glGetError() != GL_OUT_OF_MEMORY)
            gl.glClearBufferData(GL_COPY_WRITE_BUFFER, GL_R8, GL_RED, GL_UNSIGNED_BYTE, nullptr);
    } else {
        const std::vector<std::byte> zeros(desc.size);
        gl.glBufferData(GL_COPY_WRITE_BUFFER, GLsizeiptr(desc.size), zeros.data(), GL_DYNAMIC_DRAW);
    }
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
