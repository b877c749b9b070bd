// GPU timers: a pair of GL_TIMESTAMP queries (64-bit results; 32-bit ones wrap within seconds).
#include "gl_device.h"

namespace janus::rhi::gl {

TimerQuery::TimerQuery(ContextPtr context) : m_context(std::move(context)) {
    m_context->gl.glGenQueries(2, m_queries);
}

TimerQuery::~TimerQuery() {
    m_context->deleteObjects(GLObjectKind::Query, m_queries);
}

void Device::timestamp(GLuint query, bool beginsTimer) {
    gl().glQueryCounter(query, GL_TIMESTAMP);
    // llvmpipe bins a timestamp into every tile of the framebuffer bound now, with the work that
    // follows in that framebuffer: each thread then keeps the time it reached the timestamp in
    // its last tile, after all its other tiles' work (a 512x512 pass read as 1/30 of itself). A
    // flush closes the binned work here, so a timer's begin is taken before its pass starts.
    if (beginsTimer && m_timestampsPerTile) gl().glFlush();
}

}  // namespace janus::rhi::gl
