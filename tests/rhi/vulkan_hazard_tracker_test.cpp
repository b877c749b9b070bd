// The Vulkan backend's hazard tracker on its own (rhi-vulkan/src/vulkan_hazards.cpp): which
// accesses conflict with what was tracked since the last barrier. The device tests
// (hazard_tracking_test.cpp) check the barriers in real command lists; these pin down the range
// logic, including the hull each range set keeps for its quick rejections.
#include <gtest/gtest.h>

#include "vulkan_backend.h"

namespace janus::rhi::vulkan {
namespace {

// Two resources: only their addresses matter.
int g_bufferA = 0, g_bufferB = 0;

ResourceAccess access(const void* resource, uint64_t begin, uint64_t end, bool write) {
    return {resource, {begin, end}, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
            write ? VkAccessFlags(VK_ACCESS_SHADER_WRITE_BIT) : VkAccessFlags(VK_ACCESS_SHADER_READ_BIT), write};
}
ResourceAccess write(const void* resource, uint64_t begin, uint64_t end) { return access(resource, begin, end, true); }
ResourceAccess read(const void* resource, uint64_t begin, uint64_t end) { return access(resource, begin, end, false); }

// A tracker with nothing tracked (a new list assumes earlier writes to everything; the omitted
// barrier forgets them without recording a command).
HazardTracker cleanTracker() {
    HazardTracker tracker;
    tracker.reset();
    EXPECT_TRUE(tracker.conflicts(read(&g_bufferA, 0, 4))) << "a new list must order after earlier submissions";
    tracker.omitNextBarrier();
    tracker.barrier(VK_NULL_HANDLE);
    return tracker;
}

TEST(VulkanHazardTrackerTest, WritesConflictOnlyWhereTheyOverlap) {
    HazardTracker tracker = cleanTracker();
    tracker.record(write(&g_bufferA, 0, 16));
    tracker.record(write(&g_bufferA, 32, 48));   // two ranges: the hull [0, 48) covers the gap
    EXPECT_FALSE(tracker.conflicts(read(&g_bufferA, 16, 32))) << "the gap between two written ranges";
    EXPECT_FALSE(tracker.conflicts(write(&g_bufferA, 20, 30)));
    EXPECT_TRUE(tracker.conflicts(read(&g_bufferA, 20, 40))) << "reaches into the second range";
    EXPECT_TRUE(tracker.conflicts(read(&g_bufferA, 15, 16))) << "the last byte of the first range";
    EXPECT_FALSE(tracker.conflicts(write(&g_bufferA, 48, 64))) << "adjacent, past the hull";
    EXPECT_FALSE(tracker.conflicts(read(&g_bufferB, 0, 64))) << "another resource";
}

TEST(VulkanHazardTrackerTest, AdjacentWritesMergeAndStillConflict) {
    HazardTracker tracker = cleanTracker();
    for (uint64_t i = 0; i < 100; ++i) {   // a dispatch per slice, as the benchmark does
        EXPECT_FALSE(tracker.conflicts(write(&g_bufferA, i * 256, i * 256 + 4))) << "slice " << i;
        tracker.record(write(&g_bufferA, i * 256, i * 256 + 4));
    }
    EXPECT_TRUE(tracker.conflicts(read(&g_bufferA, 50 * 256, 50 * 256 + 1)));
    EXPECT_FALSE(tracker.conflicts(read(&g_bufferA, 50 * 256 + 4, 51 * 256))) << "between two slices";
    EXPECT_FALSE(tracker.conflicts(read(&g_bufferA, 100 * 256, 101 * 256))) << "past the last slice";
}

TEST(VulkanHazardTrackerTest, WriteAfterReadConflictsAndReadAfterReadDoesNot) {
    HazardTracker tracker = cleanTracker();
    tracker.record(read(&g_bufferA, 100, 110));
    tracker.record(read(&g_bufferA, 0, 10));   // inserted before: the hull grows downwards
    EXPECT_TRUE(tracker.conflicts(write(&g_bufferA, 105, 106)));
    EXPECT_TRUE(tracker.conflicts(write(&g_bufferA, 5, 6)));
    EXPECT_FALSE(tracker.conflicts(write(&g_bufferA, 10, 100))) << "between the two reads";
    EXPECT_FALSE(tracker.conflicts(read(&g_bufferA, 0, 200)));
}

TEST(VulkanHazardTrackerTest, ABarrierForgetsEverything) {
    HazardTracker tracker = cleanTracker();
    tracker.record(write(&g_bufferA, 0, 16));
    tracker.record(write(&g_bufferB, 0, 16));
    ASSERT_TRUE(tracker.conflicts(read(&g_bufferB, 0, 16)));
    tracker.omitNextBarrier();
    tracker.barrier(VK_NULL_HANDLE);
    EXPECT_FALSE(tracker.conflicts(read(&g_bufferA, 0, 16)));
    EXPECT_FALSE(tracker.conflicts(read(&g_bufferB, 0, 16)));
    EXPECT_FALSE(tracker.hasWrites());
}

}  // namespace
}  // namespace janus::rhi::vulkan
