#include "vulkan_command_memory.h"

#include <algorithm>
#include <bit>
#include <cstdlib>
#include <cstring>

namespace janus::rhi::vulkan {

namespace {
// The 16 bytes before every block handed out.
struct Header {
    uint32_t sizeClass;
    uint32_t offset;     // blocks of their own: where the block starts in what the system gave
    uint64_t capacity;   // blocks of their own: usable bytes
};
static_assert(sizeof(Header) == CommandMemory::kGranule);

Header* headerOf(void* memory) { return reinterpret_cast<Header*>(static_cast<std::byte*>(memory) - sizeof(Header)); }
}  // namespace

uint32_t CommandMemory::classOf(size_t size) {
    if (size <= kSmallLimit) return uint32_t((std::max<size_t>(size, 1) - 1) / kGranule);
    if (size > kClassLimit) return kOwnBlock;
    return kSmallClasses + uint32_t(std::bit_width(size - 1)) - 11;   // 2 KiB -> +0 ... 16 KiB -> +3
}

size_t CommandMemory::classBytes(uint32_t sizeClass) {
    if (sizeClass < kSmallClasses) return (size_t(sizeClass) + 1) * kGranule;
    return size_t(2048) << (sizeClass - kSmallClasses);
}

// The path of nearly every call, kept short: a command-sized block off its free list.
void* CommandMemory::allocate(size_t size, size_t alignment) {
    if (alignment <= kGranule && size - 1 < kSmallLimit) [[likely]] {   // 1..1024 bytes
        FreeList& list = m_free[(size - 1) / kGranule];
        if (FreeBlock* block = list.head) [[likely]] {
            list.head = block->next;
            ++m_liveBlocks;
            return block;
        }
    }
    return allocateSlow(size, alignment);
}

void CommandMemory::free(void* memory) {
    if (!memory) return;
    --m_liveBlocks;
    const Header& header = *headerOf(memory);
    if (header.sizeClass == kOwnBlock) [[unlikely]] {
        m_reservedBytes -= header.offset + header.capacity;
        std::free(static_cast<std::byte*>(memory) - header.offset);
        return;
    }
    // First freed, first reused: the next recording walks the blocks in the order this one did.
    auto* block = static_cast<FreeBlock*>(memory);
    block->next = nullptr;
    FreeList& list = m_free[header.sizeClass];
    if (list.head)
        list.tail->next = block;
    else
        list.head = block;
    list.tail = block;
}

CommandMemory::CommandMemory() {
    m_callbacks.pUserData = this;
    m_callbacks.pfnAllocation = [](void* self, size_t size, size_t alignment, VkSystemAllocationScope) {
        return static_cast<CommandMemory*>(self)->allocate(size, alignment);
    };
    m_callbacks.pfnReallocation = [](void* self, void* original, size_t size, size_t alignment,
                                     VkSystemAllocationScope) {
        return static_cast<CommandMemory*>(self)->reallocate(original, size, alignment);
    };
    m_callbacks.pfnFree = [](void* self, void* memory) { static_cast<CommandMemory*>(self)->free(memory); };
}

CommandMemory::~CommandMemory() {
    for (void* slab : m_slabs) std::free(slab);
}

void* CommandMemory::carve(size_t bytes) {
    if (size_t(m_slabEnd - m_slabCursor) < bytes) {
        void* slab = std::malloc(kSlabBytes);
        if (!slab) return nullptr;
        m_slabs.push_back(slab);
        m_reservedBytes += kSlabBytes;
        m_slabCursor = static_cast<std::byte*>(slab);
        m_slabEnd = m_slabCursor + kSlabBytes;
    }
    void* block = m_slabCursor;
    m_slabCursor += bytes;
    return block;
}

void* CommandMemory::allocateSlow(size_t size, size_t alignment) {
    const uint32_t sizeClass = alignment <= kGranule ? classOf(size) : kOwnBlock;
    if (sizeClass == kOwnBlock) {
        // Aligned to `alignment` (a power of two; at least 16 so the header stays aligned), with
        // the header in the `alignment` bytes before the block.
        alignment = std::max(alignment, kGranule);
        const size_t capacity = (std::max<size_t>(size, 1) + alignment - 1) / alignment * alignment;
        void* system = std::aligned_alloc(alignment, alignment + capacity);
        if (!system) return nullptr;
        m_reservedBytes += alignment + capacity;
        void* memory = static_cast<std::byte*>(system) + alignment;
        *headerOf(memory) = Header{kOwnBlock, uint32_t(alignment), capacity};
        ++m_liveBlocks;
        return memory;
    }
    FreeList& list = m_free[sizeClass];
    void* memory = list.head;
    if (memory) {
        list.head = list.head->next;
    } else {
        void* block = carve(sizeof(Header) + classBytes(sizeClass));
        if (!block) return nullptr;
        memory = static_cast<std::byte*>(block) + sizeof(Header);
        *headerOf(memory) = Header{sizeClass, 0, 0};
    }
    ++m_liveBlocks;
    return memory;
}

void* CommandMemory::reallocate(void* original, size_t size, size_t alignment) {
    if (!original) return allocate(size, alignment);
    if (size == 0) {
        free(original);
        return nullptr;
    }
    const Header& header = *headerOf(original);
    const bool own = header.sizeClass == kOwnBlock;
    const size_t capacity = own ? header.capacity : classBytes(header.sizeClass);
    // The specification guarantees the same alignment as the original allocation.
    if (size <= capacity) return original;
    void* memory = allocate(size, alignment);
    if (!memory) return nullptr;   // the original stays valid, as the callback must leave it
    std::memcpy(memory, original, capacity);
    free(original);
    return memory;
}

}  // namespace janus::rhi::vulkan
