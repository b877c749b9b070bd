#include "janus/rhi/draw_range_validation.h"

#include <fmt/format.h>

#include <algorithm>
#include <string>

namespace janus::rhi {
namespace {

// How many elements (vertices or instances) slot `layout` holds: the last one must hold all of
// the slot's attributes, which need not fill the stride.
struct SlotLimit {
    uint64_t elements = DrawRangeLimits::kUnlimited;
    uint64_t bytes = 0, attributeEnd = 0;   // for messages
};
SlotLimit slotLimit(const GraphicsPipelineDesc& desc, const VertexBufferLayout& layout, const BoundVertexBuffer& bound) {
    uint64_t end = 0;
    bool read = false;
    for (const VertexAttribute& a : desc.vertexAttributes)
        if (a.bufferSlot == layout.slot) {
            end = std::max<uint64_t>(end, uint64_t(a.offset) + vertexFormatSize(a.format));
            read = true;
        }
    if (!read) return {};   // a slot no attribute reads limits nothing
    const uint64_t size = bound.buffer->desc().size;
    const uint64_t bytes = bound.offset < size ? size - bound.offset : 0;
    return {bytes < end ? 0 : (bytes - end) / layout.stride + 1, bytes, end};
}

}  // namespace

DrawRangeLimits drawRangeLimits(const GraphicsPipelineDesc& desc, const VertexBufferLookup& bound) {
    DrawRangeLimits limits;
    for (const VertexBufferLayout& layout : desc.vertexBuffers) {
        const uint64_t elements = slotLimit(desc, layout, bound(layout.slot)).elements;
        uint64_t& limit = layout.perInstance ? limits.instances : limits.vertices;
        limit = std::min(limit, elements);
    }
    return limits;
}

VertexLimit vertexLimit(const GraphicsPipelineDesc& desc, const VertexBufferLookup& bound) {
    VertexLimit result;
    for (const VertexBufferLayout& layout : desc.vertexBuffers) {
        if (layout.perInstance) continue;
        const BoundVertexBuffer buffer = bound(layout.slot);
        const SlotLimit limit = slotLimit(desc, layout, buffer);
        if (limit.elements >= result.vertices) continue;
        result = {limit.elements, layout.slot, buffer.buffer, buffer.offset, limit.bytes, layout.stride};
    }
    return result;
}

std::string quotedBufferName(const IBuffer& buffer) {
    return buffer.desc().debugName.empty() ? std::string("(unnamed)") : fmt::format("'{}'", buffer.desc().debugName);
}

namespace {
std::string span(uint64_t first, uint64_t count) {
    return count ? fmt::format("{}..{}", first, first + count - 1) : fmt::format("from {}", first);
}
}  // namespace

void throwBufferRangeBelowBlock(const BindingItem& item, uint64_t blockSize, std::string_view where) {
    const uint64_t range = boundBytes(item);
    const bool uniform = item.type == ResourceType::UniformBuffer;
    throw Error(ErrorCode::InvalidUsage,
                fmt::format("{}: the shader's {} block needs {} bytes{}, but the binding shows {} bytes of buffer {} "
                            "(offset {}{}); bind a range of at least {} bytes (reads past it are undefined)",
                            where, uniform ? "uniform" : "storage", blockSize,
                            uniform ? "" : " (before its runtime array)", range, quotedBufferName(*item.buffer), item.offset,
                            item.range ? fmt::format(", range {}", item.range) : std::string(", to the end"),
                            blockSize));
}

void throwDrawOutOfRange(const DrawRange& range, const GraphicsPipelineDesc& desc, const VertexBufferLookup& bound,
                         const IBuffer* indexBuffer, uint64_t indexOffset, IndexType indexType) {
    const bool indexed = indexBuffer != nullptr;
    if (indexed) {
        const uint64_t limit = indexCountLimit(*indexBuffer, indexOffset, indexType);
        if (range.first + range.count > limit)
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("{}: indices {} (firstIndex {} + indexCount {}) read past the index buffer "
                                    "{}, which holds {} {}-bit indices from offset {}; draw fewer indices or bind "
                                    "a larger buffer",
                                    range.call, span(range.first, range.count), range.first, range.count,
                                    quotedBufferName(*indexBuffer), limit, indexType == IndexType::UInt16 ? 16 : 32,
                                    indexOffset));
    }
    for (const bool perInstance : {false, true}) {
        if (!perInstance && indexed) continue;   // index values: at execute, with validation on
        const uint64_t first = perInstance ? range.firstInstance : range.first;
        const uint64_t count = perInstance ? range.instanceCount : range.count;
        for (const VertexBufferLayout& layout : desc.vertexBuffers) {
            if (layout.perInstance != perInstance) continue;
            const BoundVertexBuffer buffer = bound(layout.slot);
            const SlotLimit limit = slotLimit(desc, layout, buffer);
            if (first + count <= limit.elements) continue;
            const char* one = perInstance ? "instance" : "vertex";
            const char* many = perInstance ? "instances" : "vertices";
            throw Error(ErrorCode::InvalidUsage,
                        fmt::format("{}: {} {} (first{} {} + {}Count {}) read past vertex buffer slot {}: buffer {} has {} "
                                    "bytes from offset {}, which hold {} {} of stride {} (the slot's attributes end "
                                    "at byte {} of each); draw fewer {} or bind a larger buffer",
                                    range.call, many, span(first, count), perInstance ? "Instance" : "Vertex", first,
                                    one, count, layout.slot, quotedBufferName(*buffer.buffer), limit.bytes, buffer.offset,
                                    limit.elements, many, layout.stride, limit.attributeEnd, many));
        }
    }
    throw Error(ErrorCode::InvalidUsage, fmt::format("{}: the draw reads past a vertex or index buffer", range.call));
}

}  // namespace janus::rhi
