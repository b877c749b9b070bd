// The check of indexed draws' index values at execute (see index_value_validation.h).
#include "janus/rhi/index_value_validation.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <string>

namespace janus::rhi {
namespace detail {

struct FrontAccess {
    static const std::shared_ptr<HostIndexContents>& contents(const IBuffer& buffer) { return buffer.m_hostIndexContents; }
};

std::shared_ptr<HostIndexContents> hostIndexContents(const IBuffer& buffer) { return FrontAccess::contents(buffer); }

void HostIndexContents::hostWrite(uint64_t offset, std::span<const std::byte> data) {
    const std::lock_guard lock(m_mutex);
    writeLocked(offset, data);
}

void HostIndexContents::writeLocked(uint64_t offset, std::span<const std::byte> data) {
    writeInto(m_bytes, m_known, offset, data);
    m_extremes.clear();
}

void HostIndexContents::writeInto(std::vector<std::byte>& bytes, bool& known, uint64_t offset,
                                  std::span<const std::byte> data) {
    std::copy(data.begin(), data.end(), bytes.begin() + std::ptrdiff_t(offset));
    if (offset == 0 && data.size() == bytes.size()) known = true;
}

void HostIndexContents::markShaderWritable() {
    const std::lock_guard lock(m_mutex);
    m_shaderWritable = true;
}

namespace {

// The smallest and largest value of `range` in `bytes` (inside: the draw's range was checked
// against the buffer's size when it was recorded).
template <typename Index>
IndexExtremes extremesOf(std::span<const std::byte> bytes, const IndexRange& range) {
    IndexExtremes result;
    const std::byte* at = bytes.data() + range.offset + range.first * sizeof(Index);
    for (uint64_t i = 0; i < range.count; ++i) {
        Index value;
        std::memcpy(&value, at + i * sizeof(Index), sizeof(Index));
        if (value < result.minValue) result.minValue = value, result.minAt = range.first + i;
        if (value > result.maxValue) result.maxValue = value, result.maxAt = range.first + i;
    }
    return result;
}
IndexExtremes extremesOf(std::span<const std::byte> bytes, const IndexRange& range) {
    return range.type == IndexType::UInt16 ? extremesOf<uint16_t>(bytes, range) : extremesOf<uint32_t>(bytes, range);
}

}  // namespace

void IndexValueLog::clear() {
    m_events.clear();
    m_data.clear();
    m_indexedDraws = 0;
}

void IndexValueLog::noteWrite(const IBuffer& buffer, uint64_t offset, const void* data, uint64_t size) {
    std::shared_ptr<HostIndexContents> contents = hostIndexContents(buffer);
    if (!contents) return;
    Event event{Event::Kind::Write, std::move(contents)};
    event.offset = offset;
    event.dataBegin = m_data.size();
    event.size = size;
    const auto* bytes = static_cast<const std::byte*>(data);
    m_data.insert(m_data.end(), bytes, bytes + size);
    m_events.push_back(std::move(event));
}

void IndexValueLog::noteUnknownWrite(const IBuffer& buffer) {
    if (std::shared_ptr<HostIndexContents> contents = hostIndexContents(buffer))
        m_events.push_back({Event::Kind::UnknownWrite, std::move(contents)});
}

void IndexValueLog::noteIndexedDraw(const IBuffer& indexBuffer, uint64_t indexOffset, IndexType type,
                                    uint32_t firstIndex, uint32_t indexCount, int32_t vertexOffset,
                                    const VertexLimit& limit) {
    const uint32_t drawNumber = ++m_indexedDraws;
    // No per-vertex slot: the values name nothing that could be missing.
    if (limit.vertices == DrawRangeLimits::kUnlimited || indexCount == 0) return;
    Event event{Event::Kind::Draw, hostIndexContents(indexBuffer)};
    if (!event.contents) return;   // made before validation was on: not possible through the front
    event.offset = indexOffset;
    event.indexBuffer = &indexBuffer;
    event.type = type;
    event.firstIndex = firstIndex;
    event.indexCount = indexCount;
    event.drawNumber = drawNumber;
    event.vertexOffset = vertexOffset;
    event.limit = limit;
    m_events.push_back(std::move(event));
}

namespace {
[[noreturn]] void throwIndexOutOfRange(const IBuffer& indexBuffer, uint64_t indexOffset, IndexType type,
                                       uint32_t drawNumber, int32_t vertexOffset, uint32_t value, uint64_t at,
                                       const VertexLimit& limit) {
    const int64_t vertex = int64_t(value) + vertexOffset;
    throw Error(
        ErrorCode::InvalidUsage,
        fmt::format("execute(): drawIndexed #{} of the command list reads index value {} at index {} of index buffer "
                    "{} ({}-bit, from offset {}){}, which names vertex {}; vertex buffer slot {} holds {} vertices "
                    "(buffer {}: {} bytes from offset {}, stride {}), so {}. Fix the indices{}, or bind a larger "
                    "vertex buffer (reads past it are undefined: zeros on Mesa, other memory or a device fault "
                    "elsewhere)",
                    drawNumber, value, at, quotedBufferName(indexBuffer), type == IndexType::UInt16 ? 16 : 32, indexOffset,
                    vertexOffset ? fmt::format(" plus vertexOffset {}", vertexOffset) : std::string(), vertex,
                    limit.slot, limit.vertices, quotedBufferName(*limit.buffer), limit.bytes, limit.offset, limit.stride,
                    limit.vertices ? fmt::format("index values{} must name vertices 0..{}",
                                                 vertexOffset ? " plus vertexOffset" : "", limit.vertices - 1)
                                   : std::string("no index value names a vertex there"),
                    vertexOffset ? " or the vertexOffset" : ""));
}

// Throws for the extreme of `extremes` that names a vertex outside the limit of `draw`.
template <class Draw>
void requireInside(const Draw& draw, const IndexExtremes& extremes) {
    const int64_t limit = int64_t(std::min<uint64_t>(draw.limit.vertices, INT64_MAX / 2));
    if (int64_t(extremes.maxValue) + draw.vertexOffset >= limit)
        throwIndexOutOfRange(*draw.indexBuffer, draw.offset, draw.type, draw.drawNumber, draw.vertexOffset,
                             extremes.maxValue, extremes.maxAt, draw.limit);
    if (int64_t(extremes.minValue) + draw.vertexOffset < 0)
        throwIndexOutOfRange(*draw.indexBuffer, draw.offset, draw.type, draw.drawNumber, draw.vertexOffset,
                             extremes.minValue, extremes.minAt, draw.limit);
}
}  // namespace

void IndexValueLog::check() const {
    // What this list's own writes make of a buffer, for its later draws; the buffers themselves
    // change only once the list has executed (applyWrites).
    struct Overlay {
        const HostIndexContents* contents;
        std::vector<std::byte> bytes;
        bool known;
    };
    std::vector<Overlay> overlays;
    auto overlayOf = [&](HostIndexContents& contents, bool create) -> Overlay* {
        for (Overlay& overlay : overlays)
            if (overlay.contents == &contents) return &overlay;
        if (!create) return nullptr;
        const std::lock_guard lock(contents.m_mutex);
        return &overlays.emplace_back(Overlay{&contents, contents.m_bytes, contents.m_known});
    };
    for (const Event& event : m_events) {
        HostIndexContents& contents = *event.contents;
        switch (event.kind) {
            case Event::Kind::Write: {
                Overlay& overlay = *overlayOf(contents, true);
                HostIndexContents::writeInto(overlay.bytes, overlay.known, event.offset, dataOf(event));
                break;
            }
            case Event::Kind::UnknownWrite: overlayOf(contents, true)->known = false; break;
            case Event::Kind::Draw: {
                const IndexRange range{event.offset, event.firstIndex, event.indexCount, event.type};
                if (const Overlay* overlay = overlayOf(contents, false)) {
                    const std::lock_guard lock(contents.m_mutex);
                    if (!overlay->known || contents.m_shaderWritable) continue;
                    requireInside(event, extremesOf(overlay->bytes, range));
                    continue;
                }
                IndexExtremes extremes;
                {
                    const std::lock_guard lock(contents.m_mutex);
                    if (!contents.m_known || contents.m_shaderWritable) continue;
                    auto cached = std::find_if(contents.m_extremes.begin(), contents.m_extremes.end(),
                                               [&](const auto& entry) { return entry.first == range; });
                    if (cached != contents.m_extremes.end()) {
                        extremes = cached->second;
                    } else {
                        extremes = extremesOf(contents.m_bytes, range);
                        // A frame's draws come back every frame: keep their ranges, within bounds.
                        if (contents.m_extremes.size() >= 1024) contents.m_extremes.clear();
                        contents.m_extremes.emplace_back(range, extremes);
                    }
                }
                requireInside(event, extremes);
                break;
            }
        }
    }
}

void IndexValueLog::applyWrites() const {
    for (const Event& event : m_events) {
        if (event.kind == Event::Kind::Draw) continue;
        HostIndexContents& contents = *event.contents;
        const std::lock_guard lock(contents.m_mutex);
        if (event.kind == Event::Kind::Write) {
            contents.writeLocked(event.offset, dataOf(event));
        } else {
            contents.m_known = false;
            contents.m_extremes.clear();
        }
    }
}

}  // namespace detail
}  // namespace janus::rhi
