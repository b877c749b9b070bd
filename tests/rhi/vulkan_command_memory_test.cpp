// The Vulkan backend's command-pool host memory (rhi-vulkan/src/vulkan_command_memory.h): the
// allocator's contract as VkAllocationCallbacks (alignment, disjoint blocks, reallocation keeps
// contents), its recycling (first freed, first reused; re-recording takes nothing new from the
// system), and that a command list's driver records into it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "backend_test.h"
#include "vulkan_backend.h"
#include "vulkan_command_memory.h"

namespace janus::rhi::test {
namespace {

using vulkan::CommandMemory;

struct Block {
    std::byte* memory;
    size_t size;
    std::byte fill;
};

TEST(VulkanCommandMemoryTest, BlocksAreAlignedDisjointAndWritable) {
    CommandMemory memory;
    const VkAllocationCallbacks& callbacks = *memory.callbacks();
    std::vector<Block> blocks;
    const size_t sizes[] = {0, 1, 15, 16, 17, 100, 144, 1023, 1024, 1025, 2048, 2049, 16384, 16385, 70000};
    const size_t alignments[] = {1, 8, 16, 32, 64, 256, 4096};
    for (size_t size : sizes)
        for (size_t alignment : alignments) {
            auto* block = static_cast<std::byte*>(
                callbacks.pfnAllocation(callbacks.pUserData, size, alignment, VK_SYSTEM_ALLOCATION_SCOPE_OBJECT));
            ASSERT_NE(block, nullptr) << size << " bytes aligned to " << alignment;
            EXPECT_EQ(reinterpret_cast<uintptr_t>(block) % alignment, 0u) << size << " bytes aligned to " << alignment;
            const auto fill = std::byte(blocks.size() * 37 + 1);
            std::memset(block, int(fill), size);
            blocks.push_back({block, size, fill});
        }
    EXPECT_EQ(memory.liveBlocks(), blocks.size());
    // Every block still holds what was written into it: none overlaps another.
    for (const Block& b : blocks)
        for (size_t i = 0; i < b.size; ++i)
            ASSERT_EQ(b.memory[i], b.fill) << "byte " << i << " of a " << b.size << "-byte block was overwritten";
    for (const Block& b : blocks) callbacks.pfnFree(callbacks.pUserData, b.memory);
    callbacks.pfnFree(callbacks.pUserData, nullptr);   // allowed, and does nothing
    EXPECT_EQ(memory.liveBlocks(), 0u);
}

TEST(VulkanCommandMemoryTest, TheFirstBlockFreedIsTheFirstReused) {
    CommandMemory memory;
    void* first = memory.allocate(144, 8);
    void* second = memory.allocate(144, 8);
    void* third = memory.allocate(144, 8);
    // A driver frees a recording's commands in the order it recorded them; the next recording
    // then gets the same blocks in the same order (a forward walk through memory, as before).
    memory.free(first);
    memory.free(second);
    memory.free(third);
    EXPECT_EQ(memory.allocate(140, 8), first);
    EXPECT_EQ(memory.allocate(144, 16), second);
    EXPECT_EQ(memory.allocate(129, 8), third);
    EXPECT_NE(memory.allocate(144, 8), third) << "a block handed out twice";
}

TEST(VulkanCommandMemoryTest, RecordingTheSameAgainReservesNothingNew) {
    CommandMemory memory;
    size_t reservedAfterFirst = 0;
    for (int round = 0; round < 10; ++round) {
        std::vector<void*> blocks;
        for (size_t i = 0; i < 3000; ++i) blocks.push_back(memory.allocate(8 + (i * 53) % 3000, 8));
        blocks.push_back(memory.allocate(200000, 64));   // one of its own, given back when freed
        for (void* block : blocks) memory.free(block);
        if (round == 0) reservedAfterFirst = memory.reservedBytes();
        EXPECT_EQ(memory.reservedBytes(), reservedAfterFirst) << "round " << round;
        EXPECT_EQ(memory.liveBlocks(), 0u);
    }
    EXPECT_GT(reservedAfterFirst, 0u);
}

TEST(VulkanCommandMemoryTest, ReallocationKeepsTheContents) {
    CommandMemory memory;
    const VkAllocationCallbacks& callbacks = *memory.callbacks();
    auto reallocate = [&](void* original, size_t size) {
        return callbacks.pfnReallocation(callbacks.pUserData, original, size, 16, VK_SYSTEM_ALLOCATION_SCOPE_OBJECT);
    };
    auto* block = static_cast<unsigned char*>(reallocate(nullptr, 100));   // null: allocates
    ASSERT_NE(block, nullptr);
    for (int i = 0; i < 100; ++i) block[i] = static_cast<unsigned char>(i);
    // Growing within a class, to a bigger class, and to a block of its own.
    for (size_t size : {110, 5000, 100000}) {
        block = static_cast<unsigned char*>(reallocate(block, size));
        ASSERT_NE(block, nullptr);
        for (int i = 0; i < 100; ++i) ASSERT_EQ(block[i], i) << "byte " << i << " lost growing to " << size;
    }
    EXPECT_EQ(reallocate(block, 50), block) << "shrinking needs no copy";
    EXPECT_EQ(memory.liveBlocks(), 1u);
    EXPECT_EQ(reallocate(block, 0), nullptr);   // size 0: frees
    EXPECT_EQ(memory.liveBlocks(), 0u);
}

// On the device: the driver records through the list's memory, and recording the same frame
// again takes nothing more from the system.
class VulkanCommandListMemoryTest : public BackendTest {
protected:
    void SetUp() override {
        BackendTest::SetUp();
        if (IsSkipped() || HasFatalFailure()) return;   // configuration not selected: no device
        if (backend() != Backend::Vulkan) GTEST_SKIP() << "the Vulkan backend's command pools";
    }
};

TEST_P(VulkanCommandListMemoryTest, ReRecordingReusesTheListsMemory) {
    const BufferHandle source = createBuffer(BufferUsage::Vertex, 4096);
    const BufferHandle target = createBuffer(BufferUsage::Vertex, 4096);
    const CommandListHandle list = device().createCommandList();
    if (!dynamic_cast<const vulkan::CommandList&>(*list).usesCommandMemory())
        GTEST_SKIP() << "JANUS_VULKAN_COMMAND_MEMORY=off: command pools use the driver's own memory";
    const CommandMemory& memory = dynamic_cast<const vulkan::CommandList&>(*list).commandMemory();
    auto record = [&] {
        list->begin();
        for (uint64_t i = 0; i < 1000; ++i) list->copyBuffer(target, i * 4 % 4096, source, i * 8 % 4096, 4);
        list->end();
        device().execute(list);
        device().waitIdle();
    };
    record();
    const size_t reserved = memory.reservedBytes();
    const size_t live = memory.liveBlocks();
    // lavapipe allocates host memory for every recorded command; a driver that records into
    // memory of its own may never call the pool's allocator.
    const bool lavapipe = device().info().deviceName.starts_with("llvmpipe");
    if (lavapipe) {
        EXPECT_GT(live, 1000u) << "lavapipe's commands did not come from the list's memory";
    }
    if (live == 0) GTEST_SKIP() << device().info().deviceName << " allocated no host memory for the recording";
    for (int round = 0; round < 3; ++round) {
        record();
        EXPECT_EQ(memory.reservedBytes(), reserved) << "round " << round;
        EXPECT_EQ(memory.liveBlocks(), live) << "round " << round;
    }
}

// Every driver gets command memory unless JANUS_VULKAN_COMMAND_MEMORY says off.
TEST_P(VulkanCommandListMemoryTest, OnUnlessTheEnvironmentSaysOff) {
    auto usesIt = [](IDevice& device) {
        const CommandListHandle list = device.createCommandList();
        return dynamic_cast<const vulkan::CommandList&>(*list).usesCommandMemory();
    };
    const char* forced = std::getenv("JANUS_VULKAN_COMMAND_MEMORY");
    if (!forced || !*forced) {
        EXPECT_TRUE(usesIt(device())) << device().info().driverInfo;
    }
    const std::string saved = forced ? forced : "";
    for (const auto& [value, expected] : std::vector<std::pair<std::string, bool>>{{"on", true}, {"off", false}, {"1", true}, {"0", false}}) {
        ::setenv("JANUS_VULKAN_COMMAND_MEMORY", value.c_str(), 1);
        std::unique_ptr<IDevice> other = createDevice(DeviceDesc().setBackend(Backend::Vulkan));
        EXPECT_EQ(usesIt(*other), expected) << "JANUS_VULKAN_COMMAND_MEMORY=" << value;
    }
    ::setenv("JANUS_VULKAN_COMMAND_MEMORY", "sometimes", 1);
    EXPECT_TRUE(throwsRhiError([] { createDevice(DeviceDesc().setBackend(Backend::Vulkan)); }, ErrorCode::BackendUnavailable,
                               {"JANUS_VULKAN_COMMAND_MEMORY='sometimes'", "on or off"}));
    if (forced) ::setenv("JANUS_VULKAN_COMMAND_MEMORY", saved.c_str(), 1);
    else ::unsetenv("JANUS_VULKAN_COMMAND_MEMORY");
}

JANUS_INSTANTIATE_BACKEND_TESTS(VulkanCommandListMemoryTest);

}  // namespace
}  // namespace janus::rhi::test
