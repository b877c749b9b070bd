#include "janus/rhi/dynamic_offsets.h"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

namespace janus::rhi {

DynamicWindows dynamicWindowsOf(const BindingSetDesc& desc) {
    // Validated: at most kMaxDynamicOffsetsPerSet dynamic items, uniform buffers with a range.
    std::vector<uint32_t> items;
    for (size_t i = 0; i < desc.items.size(); ++i)
        if (desc.items[i].dynamicOffset) items.push_back(uint32_t(i));
    // Binding order, as Vulkan orders a set's dynamic offsets.
    std::sort(items.begin(), items.end(),
              [&](uint32_t a, uint32_t b) { return desc.items[a].binding < desc.items[b].binding; });
    DynamicWindows windows;
    for (const uint32_t i : items) {
        const BindingItem& item = desc.items[i];
        windows.itemIndex[windows.count] = i;
        windows.mostOffset[windows.count] = item.buffer->desc().size - item.offset - item.range;
        ++windows.count;
    }
    return windows;
}

void throwDynamicWindowOutside(const IBindingSet& set, const DynamicWindows& windows, std::span<const uint32_t> offsets) {
    size_t which = 0;
    while (which + 1 < offsets.size() && offsets[which] <= windows.mostOffset[which]) ++which;
    const uint32_t offset = offsets[which];
    const BindingItem& item = set.desc().items[windows.itemIndex[which]];
    const BufferDesc& buffer = item.buffer->desc();
    throw Error(ErrorCode::InvalidUsage,
                fmt::format("setBindingSet(): dynamic offset {} ({}) moves binding {}'s window (offset {} + {} + range "
                            "{}) past the end of the {}-byte buffer '{}'; the largest offset it takes is {}",
                            which, offset, item.binding, item.offset, offset, item.range, buffer.size,
                            buffer.debugName, windows.mostOffset[which]));
}

bool declaresDynamic(std::span<const DynamicUniformBuffer> declared, uint32_t set, uint32_t binding) {
    return std::find(declared.begin(), declared.end(), DynamicUniformBuffer{set, binding}) != declared.end();
}

void requireDynamicAgreement(const BindingItem& item, bool pipelineDeclares, std::string_view pipelineName,
                             std::string_view where) {
    if (item.dynamicOffset == pipelineDeclares) return;
    if (item.dynamicOffset)
        throw Error(ErrorCode::InvalidUsage,
                    fmt::format("{}: the binding set gives it a dynamic offset but pipeline '{}' does not read it as "
                                "one; add addDynamicUniformBuffer(set, {}) to the pipeline's desc",
                                where, pipelineName, item.binding));
    throw Error(ErrorCode::InvalidUsage,
                fmt::format("{}: pipeline '{}' reads it with a dynamic offset but the binding set's item has none; "
                            "call BindingItem::setDynamicOffset() on it",
                            where, pipelineName));
}

}  // namespace janus::rhi
