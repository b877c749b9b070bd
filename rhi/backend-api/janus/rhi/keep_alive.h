// What a command list's recording references stays alive until the list is re-recorded without
// it or destroyed. Every backend's command list holds its objects through a KeepAliveList.
//
// Each object is held once per recording, not once per use, and what a list used in its earlier
// recordings stays held: re-recording the same frame costs no reference counting, and end()
// does nothing when the recording used every held object (it counts them). An object the user
// dropped may therefore live until the list's next end() or destruction.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "janus/rhi/rhi.h"

namespace janus::rhi {

// On every object a command list can hold (detail::KeepMark, declared in rhi.h because binding
// sets carry it in their interface): the recording that last held it and where that list holds
// it. Several lists may record at once: the mark then says only which of them touched the object
// last, so a list decides what to release from its own entries (Kept::usedIn), never from the
// mark, and trusts the slot only when its own entry there holds this mark. Relaxed atomics: a
// stale or torn read at worst holds an object twice, which is harmless.
using KeepMark = detail::KeepMark;

namespace detail {
struct BackendAccess {
    static KeepMark& keepMark(const IBindingSet& set) { return set.m_keepMark; }
};
}  // namespace detail
// A binding set's mark, whatever its backend (IBindingSet holds it).
inline KeepMark& keepMarkOf(const IBindingSet& set) { return detail::BackendAccess::keepMark(set); }

class KeepAliveList {
public:
    // Starts a recording (ids are unique across all lists of all devices).
    void beginRecording() {
        static std::atomic<uint64_t> nextRecordingId{1};
        m_recordingId = nextRecordingId.fetch_add(1, std::memory_order_relaxed);
        m_used = 0;
    }

    // Holds `handle` (whose object carries `mark`) for this recording. Free when already held by
    // this recording; only marked as used again when an earlier recording of this list held it.
    template <class Interface>
    void keep(const std::shared_ptr<Interface>& handle, KeepMark& mark) {
        if (!keepIfHeld(mark)) append(handle, mark);
    }

    // keep() without its first-time half: false (and nothing done) when `mark`'s object is not
    // held by this list yet, for callers whose fast path must not call out (keep() then).
    bool keepIfHeld(KeepMark& mark) {
        if (mark.recording.load(std::memory_order_relaxed) == m_recordingId) return true;
        // The slot's entry, bounds-checked by address: no size computed from the vector's ends.
        const uintptr_t address = reinterpret_cast<uintptr_t>(m_entries.data()) +
                                  uintptr_t(mark.slot.load(std::memory_order_relaxed)) * sizeof(Entry);
        if (address >= reinterpret_cast<uintptr_t>(m_entries.data() + m_entries.size())) return false;
        Entry& entry = *reinterpret_cast<Entry*>(address);
        if (entry.mark != &mark) return false;
        if (entry.usedIn != m_recordingId) {
            entry.usedIn = m_recordingId;
            ++m_used;
        }
        // Last: after an atomic store the compiler reads the list's members again.
        mark.recording.store(m_recordingId, std::memory_order_relaxed);
        return true;
    }
    // End of a recording: lets go of what it did not use.
    void releaseUnused() {
        if (m_used == m_entries.size()) return;   // the same objects as before, or more
        size_t kept = 0;
        for (size_t i = 0; i < m_entries.size(); ++i) {
            Entry& entry = m_entries[i];
            if (entry.usedIn != m_recordingId) continue;
            if (kept != i) {
                // Another list may have pointed the mark at its own entry: only ours move it.
                if (entry.mark->slot.load(std::memory_order_relaxed) == i)
                    entry.mark->slot.store(uint32_t(kept), std::memory_order_relaxed);
                m_entries[kept] = entry;
                m_objects[kept] = std::move(m_objects[i]);
            }
            ++kept;
        }
        m_entries.resize(kept);
        m_objects.resize(kept);
        m_used = kept;
    }

private:
    // Out of line: the first time this list holds an object. Kept apart so that keep()'s common
    // paths, inlined into every bind, stay a few compares with no registers to save.
    template <class Interface>
    [[gnu::noinline]] void append(const std::shared_ptr<Interface>& handle, KeepMark& mark) {
        mark.recording.store(m_recordingId, std::memory_order_relaxed);
        mark.slot.store(uint32_t(m_entries.size()), std::memory_order_relaxed);
        m_entries.push_back({&mark, m_recordingId});
        m_objects.push_back(handle);
        ++m_used;
    }

    // What keep() reads, apart from the references it rarely touches: a bind of another object
    // touches 16 bytes here.
    struct Entry {
        KeepMark* mark;        // inside the object
        uint64_t usedIn = 0;   // the last recording of this list that used it
    };
    std::vector<Entry> m_entries;
    std::vector<std::shared_ptr<const void>> m_objects;   // m_objects[i] holds m_entries[i]'s object
    size_t m_used = 0;   // entries the current recording used
    uint64_t m_recordingId = 0;
};

}  // namespace janus::rhi
