// With validation on, the index values of indexed draws (rhi/src/index_value_validation.cpp).
//
// An index past the end of a per-vertex buffer reads memory the draw does not own: Mesa reads
// zeros, other drivers read whatever lies there or fault the device. The range checks of
// draw_range_validation.h stop at the index buffer's size, since its values live on the GPU. The
// validation layer keeps a host copy of each index buffer's contents instead (every byte the host
// gives it: the zeros it starts with, IDevice::writeBuffer, ICommandList::writeBuffer), and
// IDevice::execute checks every indexed draw of the list against that copy in the list's order,
// before the backend runs any of it: the same InvalidUsage on every backend, naming the draw, the
// index and the vertex buffer it reaches past.
//
// What the host did not write is not known, so it is not checked: a buffer is left unchecked from
// a copy into it (copyBuffer, copyTextureToBuffer) until the host writes the whole of it again,
// and for good once a binding set can write it as a storage buffer. Primitive restart is never
// enabled, so every index value names a vertex.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <utility>
#include <vector>

#include "janus/rhi/draw_range_validation.h"
#include "janus/rhi/rhi.h"

namespace janus::rhi::detail {

// A run of indices: `count` of `type` from index `first`, the buffer's indices starting at byte `offset`.
struct IndexRange {
    uint64_t offset, first, count;
    IndexType type;
    bool operator==(const IndexRange&) const = default;
};
// The smallest and largest value of a range, and where they are (index positions).
struct IndexExtremes {
    uint32_t minValue = UINT32_MAX, maxValue = 0;
    uint64_t minAt = 0, maxAt = 0;
};

// The host's copy of an index buffer's contents (created with validation on and BufferUsage::Index).
class HostIndexContents {
public:
    explicit HostIndexContents(uint64_t size) : m_bytes(size) {}

    // IDevice::writeBuffer (and, at execute, ICommandList::writeBuffer): writing the whole buffer
    // makes it known again after a copy into it.
    void hostWrite(uint64_t offset, std::span<const std::byte> data);
    // A binding set can write it as a storage buffer: never known again.
    void markShaderWritable();

private:
    friend class IndexValueLog;
    void writeLocked(uint64_t offset, std::span<const std::byte> data);
    // `data` into `bytes` at `offset`; all of them: `known` becomes true.
    static void writeInto(std::vector<std::byte>& bytes, bool& known, uint64_t offset, std::span<const std::byte> data);
    std::mutex m_mutex;
    std::vector<std::byte> m_bytes;
    bool m_known = true;             // false after a copy into it, until the host writes all of it
    bool m_shaderWritable = false;   // set once, never cleared
    std::vector<std::pair<IndexRange, IndexExtremes>> m_extremes;   // of the current contents
};

// What a command list did that the check at execute needs, in recording order. One per command
// list, created with validation on.
class IndexValueLog {
public:
    void clear();
    // The recording writes `data` into `buffer` at `offset` (ICommandList::writeBuffer).
    void noteWrite(const IBuffer& buffer, uint64_t offset, const void* data, uint64_t size);
    // The recording writes `buffer` in a way the host does not see (copies into it).
    void noteUnknownWrite(const IBuffer& buffer);
    // An indexed draw: its index range and the vertices its values may name.
    void noteIndexedDraw(const IBuffer& indexBuffer, uint64_t indexOffset, IndexType type, uint32_t firstIndex,
                         uint32_t indexCount, int32_t vertexOffset, const VertexLimit& limit);
    // Throws InvalidUsage for the first indexed draw that names a vertex outside its limit, seeing
    // the list's own earlier writes; changes no buffer's copy (IDevice::execute, before the backend).
    void check() const;
    // The list's writes, into the buffers' copies (IDevice::execute, once the backend executed it).
    void applyWrites() const;

private:
    struct Event {
        enum class Kind { Write, UnknownWrite, Draw } kind;
        std::shared_ptr<HostIndexContents> contents;   // of the buffer written or drawn from
        // Write: bytes [dataBegin, dataBegin + size) of m_data go to `offset`. Draw: `offset` is
        // the index buffer's.
        uint64_t offset = 0, dataBegin = 0, size = 0;
        // Draw:
        const IBuffer* indexBuffer = nullptr;
        IndexType type = IndexType::UInt16;
        uint32_t firstIndex = 0, indexCount = 0, drawNumber = 0;
        int32_t vertexOffset = 0;
        VertexLimit limit;
    };
    std::span<const std::byte> dataOf(const Event& write) const {
        return std::span(m_data).subspan(write.dataBegin, write.size);
    }
    std::vector<Event> m_events;
    std::vector<std::byte> m_data;
    uint32_t m_indexedDraws = 0;
};

// The host copy of `buffer`, if it has one (validation on, BufferUsage::Index).
std::shared_ptr<HostIndexContents> hostIndexContents(const IBuffer& buffer);

}  // namespace janus::rhi::detail
