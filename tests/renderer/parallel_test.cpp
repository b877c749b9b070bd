// parallelFor (renderer/src/core/parallel.h): every item once, the same results on any number of
// threads, and exceptions that come back to the caller instead of ending the process.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/parallel.h"

namespace janus::renderer {
namespace {

TEST(ParallelFor, RunsEveryItemOnceOnAnyNumberOfThreads) {
    for (unsigned threads : {1u, 2u, 3u, 8u, 64u}) {
        std::vector<std::atomic<int>> runs(1000);
        std::vector<size_t> squares(runs.size());
        parallelFor(runs.size(), threads, [&](size_t i) {
            ++runs[i];
            squares[i] = i * i;
        });
        for (size_t i = 0; i < runs.size(); ++i) {
            ASSERT_EQ(runs[i], 1) << "item " << i << " on " << threads << " threads";
            ASSERT_EQ(squares[i], i * i);
        }
    }
    parallelFor(0, 4, [](size_t) { FAIL() << "no item to run"; });
}

TEST(ParallelFor, TheLowestFailingItemsExceptionReachesTheCaller) {
    for (unsigned threads : {1u, 2u, 4u}) {
        try {
            parallelFor(100, threads, [](size_t i) {
                if (i == 37 || i == 80) throw std::runtime_error("item " + std::to_string(i));
            });
            FAIL() << "no exception on " << threads << " threads";
        } catch (const std::runtime_error& e) {
            // Items go out in order, so every item below a failure has gone out and runs: the
            // lowest failing item is found whichever thread failed first.
            EXPECT_STREQ(e.what(), "item 37") << threads << " threads";
        }
    }
}

TEST(ParallelFor, ThreadsAreTheRequestOrTheHardwareAndNeverMoreThanTheItems) {
    EXPECT_EQ(parallelThreads(3, 100), 3u);
    EXPECT_EQ(parallelThreads(8, 2), 2u);
    EXPECT_EQ(parallelThreads(8, 0), 1u);
    EXPECT_GE(parallelThreads(0, 100), 1u);
}

}  // namespace
}  // namespace janus::renderer
