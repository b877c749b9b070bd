// Dynamic uniform buffers (BindingItem::dynamicOffset), the checks every backend shares: the same
// mistake is the same error with the same message on every backend. The front checks the offsets'
// count and alignment (ICommandList::setBindingSet); a backend keeps each set's windows
// (dynamicWindowsOf, when the set is made) and checks the offsets against them when the set is
// bound (takeDynamicOffsets), and checks that a pipeline and a set agree on which
// bindings are dynamic when it first pairs them (requireDynamicAgreement).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <string_view>

#include "janus/rhi/rhi.h"

namespace janus::rhi {

// A set's dynamic items in binding order (the order setBindingSet takes their offsets), each as
// the largest offset that keeps its window inside its buffer.
struct DynamicWindows {
    uint32_t count = 0;
    std::array<uint32_t, kMaxDynamicOffsetsPerSet> itemIndex{};   // into BindingSetDesc::items
    std::array<uint64_t, kMaxDynamicOffsetsPerSet> mostOffset{};
    // Which offset moves BindingSetDesc::items[itemIndex] (a dynamic item: one of itemIndex).
    uint32_t slotOf(uint32_t item) const {
        return uint32_t(std::find(itemIndex.begin(), itemIndex.begin() + count, item) - itemIndex.begin());
    }
};
DynamicWindows dynamicWindowsOf(const BindingSetDesc& desc);

// Names the first offset that moves its window past the end of its buffer.
[[noreturn]] void throwDynamicWindowOutside(const IBindingSet& set, const DynamicWindows& windows,
                                            std::span<const uint32_t> offsets);
// `offsets` (windows.count of them: the front checked) into `kept`, once every window they move is
// inside its buffer: a refused bind changes nothing.
inline void takeDynamicOffsets(const IBindingSet& set, const DynamicWindows& windows, std::span<const uint32_t> offsets,
                               std::array<uint32_t, kMaxDynamicOffsetsPerSet>& kept) {
    for (size_t i = 0; i < offsets.size(); ++i)
        if (offsets[i] > windows.mostOffset[i]) [[unlikely]] throwDynamicWindowOutside(set, windows, offsets);
    for (size_t i = 0; i < offsets.size(); ++i) kept[i] = offsets[i];
}

// Whether `pipeline` declares set `set` binding `binding` dynamic.
bool declaresDynamic(std::span<const DynamicUniformBuffer> declared, uint32_t set, uint32_t binding);
// A binding the pipeline's shaders read, against the set's item for it: both dynamic or neither.
// `where` names the binding ("set 0 binding 2 ('Draw')"). Throws InvalidUsage saying which side to change.
void requireDynamicAgreement(const BindingItem& item, bool pipelineDeclares, std::string_view pipelineName,
                             std::string_view where);

}  // namespace janus::rhi
