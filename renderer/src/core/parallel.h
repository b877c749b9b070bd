// One way to spread independent items over the CPU's threads (the CPU tile builder, the GI and
// GGX references, scene image decoding and mip chains).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace janus::renderer {

// The threads parallelFor should run for `items` items: `requested`, or one per hardware thread
// when 0, and never more than the items (at least 1).
inline unsigned parallelThreads(unsigned requested, size_t items) {
    const unsigned wanted = requested != 0 ? requested : std::max(1u, std::thread::hardware_concurrency());
    return unsigned(std::clamp<size_t>(wanted, 1, std::max<size_t>(items, 1)));
}

// Runs body(i) for every i in [0, count) on `threads` threads, the calling one among them. Items
// are handed out one at a time, so what body writes per item is the same however many threads
// run. An exception from body stops the handing out; when every thread has stopped, the one
// thrown for the lowest item is rethrown: every item below a failing one had gone out and ran, so
// that is the lowest failing item whatever the timing (no exception leaves a worker thread).
template <typename Body>
void parallelFor(size_t count, unsigned threads, const Body& body) {
    if (threads <= 1 || count <= 1) {
        for (size_t i = 0; i < count; ++i) body(i);
        return;
    }
    std::atomic<size_t> next{0};
    std::mutex failureMutex;
    std::exception_ptr failure;
    size_t failedItem = count;
    auto worker = [&] {
        for (size_t i = next++; i < count; i = next++) {
            try {
                body(i);
            } catch (...) {
                const std::lock_guard lock(failureMutex);
                if (i < failedItem) failedItem = i, failure = std::current_exception();
                next = count;   // hand out nothing more
            }
        }
    };
    std::vector<std::thread> pool;
    pool.reserve(threads - 1);
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& thread : pool) thread.join();
    if (failure) std::rethrow_exception(failure);
}

}  // namespace janus::renderer
