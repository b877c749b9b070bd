// GPU timers: a pair of GL_TIMESTAMP queries (64-bit results; 32-bit ones wrap within seconds).
#include "gl_device.h"

namespace janus::rhi::gl {

GLTimerQuery::GLTimerQuery(ContextPtr context) : m_context(std::move(context)) {
    m_context->gl.glGenQueries(2, m_queries);
}

GLTimerQuery::~GLTimerQuery() {
    m_context->makeCurrent();
    m_context->gl.glDeleteQueries(2, m_queries);
}

void GLDevice::timestamp(GLuint query) {
    // Software rasterizers (llvmpipe) defer drawing until a flush and stamp time when the stamp
    // is reached in their queue; finishing first makes the stamp mean "all earlier work done"
    // there too. It serialises the GPU around timers, which is what a timer measures anyway.
    gl().glFinish();
    gl().glQueryCounter(query, GL_TIMESTAMP);
}

}  // namespace janus::rhi::gl
