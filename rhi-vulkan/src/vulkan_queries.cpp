// GPU timers: a pool of two timestamp queries each. Results are read in Device::timerSeconds.
#include "vulkan_backend.h"

namespace janus::rhi::vulkan {

TimerQuery::TimerQuery(ContextPtr context) : m_context(std::move(context)) {
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = 2;   // begin, end
    check(vkCreateQueryPool(m_context->device, &info, nullptr, &pool), ErrorCode::OutOfMemory, "vkCreateQueryPool");
}

TimerQuery::~TimerQuery() { vkDestroyQueryPool(m_context->device, pool, nullptr); }

}  // namespace janus::rhi::vulkan
