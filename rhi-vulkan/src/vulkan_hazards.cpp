// Hazard tracking inside a command list: barriers only where a command reads or writes what an
// earlier command since the last barrier wrote, or writes what one read.
#include <algorithm>

#include "vulkan_backend.h"

namespace janus::rhi::vulkan {

bool HazardTracker::RangeSet::overlapsAny(KeyRange range) const {
    // The first range ending after range.begin is the only candidate.
    auto it = std::upper_bound(ranges.begin(), ranges.end(), range.begin,
                               [](uint64_t begin, const KeyRange& r) { return begin < r.end; });
    return it != ranges.end() && it->begin < range.end;
}

void HazardTracker::RangeSet::insert(KeyRange range) {
    hull.begin = std::min(hull.begin, range.begin);
    hull.end = std::max(hull.end, range.end);
    if (ranges.empty() || ranges.back().end < range.begin) {
        ranges.push_back(range);   // past everything tracked
        return;
    }
    auto first = std::lower_bound(ranges.begin(), ranges.end(), range.begin,
                                  [](const KeyRange& r, uint64_t begin) { return r.end < begin; });
    auto last = first;
    while (last != ranges.end() && last->begin <= range.end) {
        range.begin = std::min(range.begin, last->begin);
        range.end = std::max(range.end, last->end);
        ++last;
    }
    if (first == last) {
        ranges.insert(first, range);
    } else {
        *first = range;
        ranges.erase(first + 1, last);
    }
}

void HazardTracker::accessOneGeneral(VkCommandBuffer cmd, const ResourceAccess& only) {
    Tracked* tracked = m_unknownWrites ? nullptr : find(only.resource);
    if (m_unknownWrites || (tracked && conflicts(*tracked, only))) {
        barrier(cmd);
        tracked = nullptr;
    }
    if (tracked)
        record(*tracked, only);
    else
        record(only);
}

void HazardTracker::reset() {
    forget();
    m_unknownWrites = true;
    m_omitNextBarrier = false;
}

HazardTracker::Tracked* HazardTracker::search(const void* resource) {
    for (Tracked& tracked : m_tracked)
        if (tracked.resource == resource) {
            m_lastFound = &tracked;
            return &tracked;
        }
    return nullptr;
}

bool HazardTracker::conflicts(const ResourceAccess& access) const {
    if (m_unknownWrites) return true;
    const Tracked* tracked = find(access.resource);
    return tracked && conflicts(*tracked, access);
}

void HazardTracker::record(const ResourceAccess& access) {
    Tracked* tracked = find(access.resource);
    if (!tracked) {
        tracked = &m_tracked.emplace_back(Tracked{access.resource, {}, {}});
        m_lastFound = tracked;   // the others may have moved: found again by search()
    }
    record(*tracked, access);
}

void HazardTracker::access(VkCommandBuffer cmd, std::span<const ResourceAccess> accesses) {
    if (accesses.size() == 1) return accessOne(cmd, accesses[0]);   // one lookup instead of two
    for (const ResourceAccess& a : accesses)
        if (conflicts(a)) {
            barrier(cmd);
            break;
        }
    for (const ResourceAccess& a : accesses) record(a);
}

void HazardTracker::barrier(VkCommandBuffer cmd) {
    // The second scope is every later command, so everything tracked can be forgotten after it.
    // (A narrower second scope would need to remember which accesses it did not cover.)
    if (!m_unknownWrites && m_srcStages == 0) return;   // nothing to order
    if (m_omitNextBarrier) {
        m_omitNextBarrier = false;
        forget();
        return;
    }
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    VkPipelineStageFlags srcStages = m_srcStages;
    barrier.srcAccessMask = m_srcAccess;
    if (m_unknownWrites) {
        srcStages = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
        barrier.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
    }
    barrier.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    vkCmdPipelineBarrier(cmd, srcStages, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1, &barrier, 0, nullptr, 0, nullptr);
    forget();
}

void HazardTracker::forget() {
    m_tracked.clear();
    m_lastFound = nullptr;
    m_unknownWrites = false;
    m_srcStages = 0;
    m_srcAccess = 0;
}

}  // namespace janus::rhi::vulkan
