// Backend-neutral range checks of draws against the bound vertex and index buffers
// (rhi/src/draw_range_validation.cpp), as WebGPU has them: a draw may not read a vertex, an
// instance or an index past the end of its buffer. Drivers leave such reads undefined (Mesa reads
// zeros, other drivers what lies there, or fault); every backend checks them, so the same mistake
// is the same InvalidUsage everywhere. The limits are computed when the pipeline or a buffer
// changes, so a draw checks its range with two compares. Index values of indexed draws are checked
// only with validation on, when the list executes (index_value_validation.h).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <string_view>

#include "janus/rhi/rhi.h"

namespace janus::rhi {

// A uniform or storage buffer item against the block its shader declares: the bound range must
// hold the block (for a storage block ending in a runtime array: the part before it). Shader
// reads past the range are undefined (Mesa reads zeros, other drivers the rest of the buffer),
// so every backend checks this when it first pairs a set with a pipeline, as WebGPU does. `where()`
// names the binding; it is called only for the message. Throws InvalidUsage.
[[noreturn]] void throwBufferRangeBelowBlock(const BindingItem& item, uint64_t blockSize, std::string_view where);
// The bytes a buffer item shows (range 0: to the end of the buffer).
inline uint64_t boundBytes(const BindingItem& item) {
    return item.range ? item.range : item.buffer->desc().size - item.offset;
}
template <class Where>
void requireBufferCoversBlock(const BindingItem& item, uint64_t blockSize, Where&& where) {
    if (item.buffer && boundBytes(item) < blockSize) throwBufferRangeBelowBlock(item, blockSize, where());
}

// A buffer bound at a vertex slot, and where its vertex data starts.
struct BoundVertexBuffer {
    const IBuffer* buffer = nullptr;
    uint64_t offset = 0;
};
// The buffer bound at each slot the pipeline reads (every such slot has one: checked first).
using VertexBufferLookup = std::function<BoundVertexBuffer(uint32_t slot)>;

// How far a draw may read: firstVertex + vertexCount <= vertices (draw only; indexed draws are
// checked against indices) and firstInstance + instanceCount <= instances.
struct DrawRangeLimits {
    static constexpr uint64_t kUnlimited = std::numeric_limits<uint64_t>::max();
    uint64_t vertices = kUnlimited;
    uint64_t instances = kUnlimited;

    // Whether a draw's instances / a draw's vertices and instances reach past these limits.
    bool instancesExceeded(uint32_t firstInstance, uint32_t instanceCount) const {
        return uint64_t(firstInstance) + instanceCount > instances;
    }
    bool exceeded(uint32_t firstVertex, uint32_t vertexCount, uint32_t firstInstance, uint32_t instanceCount) const {
        return uint64_t(firstVertex) + vertexCount > vertices || instancesExceeded(firstInstance, instanceCount);
    }
};
// Whether an indexed draw reads past the index buffer's `indexLimit` (indexCountLimit) or `limits`.
inline bool indexedDrawExceeds(const DrawRangeLimits& limits, uint64_t indexLimit, uint32_t firstIndex,
                               uint32_t indexCount, uint32_t firstInstance, uint32_t instanceCount) {
    return uint64_t(firstIndex) + indexCount > indexLimit || limits.instancesExceeded(firstInstance, instanceCount);
}
DrawRangeLimits drawRangeLimits(const GraphicsPipelineDesc& desc, const VertexBufferLookup& bound);

// The per-vertex slot that limits which vertices an indexed draw's values may name: the one that
// holds the fewest (index_value_validation.h checks the values against it).
struct VertexLimit {
    uint64_t vertices = DrawRangeLimits::kUnlimited;   // no per-vertex slot: no limit
    uint32_t slot = 0;
    const IBuffer* buffer = nullptr;
    uint64_t offset = 0, bytes = 0;   // where its vertices start, and the bytes from there
    uint32_t stride = 0;
};
VertexLimit vertexLimit(const GraphicsPipelineDesc& desc, const VertexBufferLookup& bound);

// How many indices of `type` the index buffer holds from `offset` (validated: inside the buffer).
inline uint64_t indexCountLimit(const IBuffer& buffer, uint64_t offset, IndexType type) {
    return (buffer.desc().size - offset) / (type == IndexType::UInt16 ? 2 : 4);
}

// A buffer as messages name it: its debug name in quotes, or "(unnamed)".
std::string quotedBufferName(const IBuffer& buffer);

// What a draw asked for, for the message of a range it exceeds.
struct DrawRange {
    std::string_view call;            // "draw()", "drawIndexed()"
    uint64_t first = 0, count = 0;    // vertices (draw) or indices (drawIndexed)
    uint64_t firstInstance = 0, instanceCount = 0;
};
// Throws InvalidUsage naming the first range of `range` that exceeds its limit: the slot, its
// buffer and what fits in it, or the index buffer. Call it only when one does.
[[noreturn]] void throwDrawOutOfRange(const DrawRange& range, const GraphicsPipelineDesc& desc,
                                      const VertexBufferLookup& bound, const IBuffer* indexBuffer,
                                      uint64_t indexOffset, IndexType indexType);

}  // namespace janus::rhi
