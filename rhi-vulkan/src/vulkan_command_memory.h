// Host memory for one command pool: VkAllocationCallbacks that recycle blocks per size class,
// first freed first reused.
//
// Why: a driver that records into host memory (lavapipe allocates every recorded command on the
// heap and frees them all at vkResetCommandPool) otherwise takes every command from the process
// heap, and where glibc places those blocks depends on everything else the process allocated
// before. After an application has made and freed its own objects (a thousand binding sets, say)
// the commands of one recording land scattered over megabytes, and recording a frame cost twice
// as much as the same calls in a process with a tidier heap (docs/BENCHMARKS.md, "Command
// memory"). Recycled per pool, a recording's commands occupy the blocks the previous recording of
// the same list used, in the same order, whatever the process did in between.
//
// Blocks go back to the system only when the CommandMemory is destroyed, so a command list holds
// the memory of its largest recording (as a command pool without the release flag does).
//
// Threading: none needed. The Vulkan specification allows a driver to call a command pool's
// allocator only inside commands on that pool or its command buffers, on the calling thread
// ("Host Memory"), and those commands are externally synchronised per pool.
#pragma once

#include <vulkan/vulkan.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace janus::rhi::vulkan {

class CommandMemory {
public:
    CommandMemory();
    ~CommandMemory();
    CommandMemory(const CommandMemory&) = delete;
    CommandMemory& operator=(const CommandMemory&) = delete;

    // Valid while this object lives: the pool created with them must be destroyed first.
    const VkAllocationCallbacks* callbacks() const { return &m_callbacks; }

    void* allocate(size_t size, size_t alignment);
    void* reallocate(void* original, size_t size, size_t alignment);
    void free(void* memory);

    // What the system gave (slabs and blocks of their own) and blocks handed out now.
    size_t reservedBytes() const { return m_reservedBytes; }
    size_t liveBlocks() const { return m_liveBlocks; }

    // Size classes: 16-byte steps up to 1 KiB (commands are mostly a few hundred bytes), then
    // powers of two up to 16 KiB, carved from 64 KiB slabs. Larger blocks, and blocks aligned to
    // more than 16 bytes, are blocks of their own from the system.
    static constexpr size_t kGranule = 16;
    static constexpr size_t kSmallLimit = 1024;
    static constexpr size_t kClassLimit = 16 * 1024;
    static constexpr size_t kSlabBytes = 64 * 1024;

private:
    struct FreeBlock {
        FreeBlock* next;
    };
    // Singly linked, appended at the tail and taken from the head; `tail` is meaningful only
    // while `head` is not null.
    struct FreeList {
        FreeBlock* head = nullptr;
        FreeBlock* tail = nullptr;
    };
    static constexpr uint32_t kSmallClasses = kSmallLimit / kGranule;   // 64
    static constexpr uint32_t kClasses = kSmallClasses + 4;               // + 2, 4, 8, 16 KiB
    static constexpr uint32_t kOwnBlock = UINT32_MAX;

    static uint32_t classOf(size_t size);
    static size_t classBytes(uint32_t sizeClass);
    void* allocateSlow(size_t size, size_t alignment);
    void* carve(size_t bytes);

    VkAllocationCallbacks m_callbacks{};
    std::array<FreeList, kClasses> m_free{};
    std::vector<void*> m_slabs;
    std::byte* m_slabCursor = nullptr;
    std::byte* m_slabEnd = nullptr;
    size_t m_reservedBytes = 0;
    size_t m_liveBlocks = 0;
};

}  // namespace janus::rhi::vulkan
