// GPU timers: a pair of GL_TIMESTAMP queries (64-bit results; 32-bit ones wrap within seconds).
#include "gl_device.h"

namespace janus::rhi::gl {

TimerQuery::TimerQuery(ContextPtr context) : m_context(std::move(context)) {
    m_context->gl.glGenQueries(2, m_queries);
}

TimerQuery::~TimerQuery() {
    m_context->deleteObjects(GLObjectKind::Query, m_queries);
}

void Device::timestamp(GLuint query) { gl().glQueryCounter(query, GL_TIMESTAMP); }

}  // namespace janus::rhi::gl
