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

// accessOne, a dispatch's path (inline for a run of neighbouring slices): a conflicting access
// gets a barrier first. The barrier is observed through what the tracker forgot: it is omitted
// (omitNextBarrier), so no command buffer is needed, and an omitted barrier still forgets.
TEST(VulkanHazardTrackerTest, AccessOneBarriersBeforeAConflictingAccess) {
    HazardTracker tracker = cleanTracker();
    for (uint64_t i = 0; i < 10; ++i) tracker.accessOne(VK_NULL_HANDLE, write(&g_bufferA, i * 16, i * 16 + 16));
    ASSERT_TRUE(tracker.conflicts(read(&g_bufferA, 40, 41))) << "ten neighbouring writes are all tracked";
    tracker.omitNextBarrier();
    tracker.accessOne(VK_NULL_HANDLE, read(&g_bufferA, 40, 41));   // read after write: a barrier first
    EXPECT_FALSE(tracker.conflicts(read(&g_bufferA, 0, 160))) << "the writes before the barrier are ordered";
    EXPECT_TRUE(tracker.conflicts(write(&g_bufferA, 40, 41))) << "the read after it is tracked";
    EXPECT_FALSE(tracker.conflicts(write(&g_bufferA, 41, 42)));
}

// The same where the read continues the last read range (the inline path's case) but reaches a
// write tracked since.
TEST(VulkanHazardTrackerTest, AccessOneBarriersBeforeAReadContinuingAnotherIntoAWrite) {
    HazardTracker tracker = cleanTracker();
    tracker.accessOne(VK_NULL_HANDLE, read(&g_bufferA, 0, 16));
    tracker.accessOne(VK_NULL_HANDLE, write(&g_bufferA, 32, 48));   // no conflict with [0, 16)
    ASSERT_TRUE(tracker.conflicts(read(&g_bufferA, 16, 40)));
    tracker.omitNextBarrier();
    tracker.accessOne(VK_NULL_HANDLE, read(&g_bufferA, 16, 40));   // continues [0, 16), reaches the write
    EXPECT_FALSE(tracker.conflicts(read(&g_bufferA, 32, 48))) << "the write was ordered by a barrier";
    EXPECT_FALSE(tracker.conflicts(write(&g_bufferA, 0, 16))) << "and so was the first read";
    EXPECT_TRUE(tracker.conflicts(write(&g_bufferA, 20, 21))) << "the read after the barrier is tracked";
}

// And a write continuing the last write range into a read tracked since (write after read).
TEST(VulkanHazardTrackerTest, AccessOneBarriersBeforeAWriteContinuingAnotherIntoARead) {
    HazardTracker tracker = cleanTracker();
    tracker.accessOne(VK_NULL_HANDLE, write(&g_bufferA, 0, 16));
    tracker.accessOne(VK_NULL_HANDLE, read(&g_bufferA, 20, 30));   // no conflict with [0, 16)
    ASSERT_TRUE(tracker.conflicts(write(&g_bufferA, 16, 24)));
    tracker.omitNextBarrier();
    tracker.accessOne(VK_NULL_HANDLE, write(&g_bufferA, 16, 24));   // continues [0, 16), reaches the read
    EXPECT_FALSE(tracker.conflicts(read(&g_bufferA, 0, 16))) << "the first write was ordered by a barrier";
    EXPECT_FALSE(tracker.conflicts(write(&g_bufferA, 24, 30))) << "and so was the read";
    EXPECT_TRUE(tracker.conflicts(read(&g_bufferA, 16, 24))) << "the write after the barrier is tracked";
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
