// janus_bench_rhi: CPU cost per draw and per dispatch of the Janus RHI against the same work
// issued with raw Vulkan / raw GL calls, in one run. scripts/bench.sh turns the JSON output into
// the ratio table of docs/BENCHMARKS.md.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <malloc.h>
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <limits>

#include "bench_common.h"

namespace janus::bench {

namespace {
uint32_t g_opsPerFrame = kDefaultOpsPerFrame;
uint32_t g_pairedBlock = kDefaultPairedBlock;
}  // namespace

uint32_t opsPerFrame() { return g_opsPerFrame; }
void setOpsPerFrame(uint32_t ops) { g_opsPerFrame = ops; }
uint32_t pairedBlock() { return g_pairedBlock; }
void setPairedBlock(uint32_t frames) { g_pairedBlock = frames; }

std::array<float, 4> drawColor(uint32_t drawIndex) {
    const std::array<uint8_t, 4> bytes = drawColorBytes(drawIndex);
    return {bytes[0] / 255.0f, bytes[1] / 255.0f, bytes[2] / 255.0f, bytes[3] / 255.0f};
}

std::array<uint8_t, 4> drawColorBytes(uint32_t drawIndex) {
    return {uint8_t(drawIndex & 0xFF), uint8_t(drawIndex >> 8), 255, 255};
}

void requireLastDrawColor(const void* texel, std::string_view who) {
    std::array<uint8_t, 4> got{};
    std::memcpy(got.data(), texel, got.size());
    const uint32_t ops = opsPerFrame();
    const std::array<uint8_t, 4> expected = drawColorBytes(ops - 1);
    if (got == expected) return;
    std::string whose = "no draw's colour";
    for (uint32_t i = 0; i < ops; ++i)
        if (drawColorBytes(i) == got) whose = fmt::format("the colour of draw {} of {}", i, ops);
    throw WrongResult(fmt::format("{}: texel (0, 0) is ({}), {}, not the last draw's ({})", who, fmt::join(got, ", "),
                                  whose, fmt::join(expected, ", ")));
}

std::vector<std::byte> drawParameterData() {
    std::vector<std::byte> data(slicedBufferBytes());
    for (uint32_t i = 0; i < opsPerFrame(); ++i) {
        const std::array<float, 4> color = drawColor(i);
        std::memcpy(data.data() + i * kSliceBytes, color.data(), sizeof(color));
    }
    return data;
}

namespace {
// CPU time of the calling thread only: on a shared 2-core machine, wall time also counts the time
// other processes hold the core, while this counts the work the benchmark thread itself did.
double threadCpuSeconds() {
    timespec now{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    return double(now.tv_sec) + double(now.tv_nsec) * 1e-9;
}

// The timed part of one frame, under a name of its own: `scripts/bench.sh instructions` counts
// the instructions executed inside it with callgrind (--toggle-collect='*timedSubmit*').
[[gnu::noinline]] void timedSubmit(const std::function<void()>& submit) { submit(); }

// Which logical CPUs a run's frames started on: the H200 machine ran the same code at two speeds
// 1.5x apart from run to run (docs/BENCHMARKS.md, session 25), and a CPU that shares its core with
// a busy sibling is one suspect. Reported as the counters cpu (where the last frame started) and
// cpu_migrations (frames that started on another CPU than the frame before), outside the timing.
class CpuTrail {
public:
    void atFrame() {
        const int cpu = sched_getcpu();
        if (m_last >= 0 && cpu != m_last) ++m_migrations;
        m_last = cpu;
    }
    void report(benchmark::State& state) const {
        state.counters["cpu"] = m_last;
        state.counters["cpu_migrations"] = double(m_migrations);
    }

private:
    int m_last = -1;
    uint64_t m_migrations = 0;
};
}  // namespace

void runFrames(benchmark::State& state, const std::function<void()>& submit, const std::function<void()>& wait) {
    using Clock = std::chrono::steady_clock;
    double submitCpuSeconds = 0, submitSeconds = 0, waitSeconds = 0;
    std::string failure;
    CpuTrail cpus;
    for (auto _ : state) {
        // After a failure the remaining iterations run empty: leaving the loop early would leave
        // Google Benchmark with a run that neither finished nor failed (see runGuarded).
        if (!failure.empty()) continue;
        try {
            cpus.atFrame();
            const double cpuStart = threadCpuSeconds();
            const auto start = Clock::now();
            timedSubmit(submit);
            const auto submitted = Clock::now();
            const double cpuSubmitted = threadCpuSeconds();
            wait();
            const auto finished = Clock::now();
            submitCpuSeconds += cpuSubmitted - cpuStart;
            submitSeconds += std::chrono::duration<double>(submitted - start).count();
            waitSeconds += std::chrono::duration<double>(finished - submitted).count();
        } catch (const std::exception& error) {
            failure = error.what();
        }
    }
    if (!failure.empty()) throw std::runtime_error(failure);
    // kAvgIterations divides by the iteration count: the values read as ns per draw/dispatch.
    auto perOp = [](double seconds) {
        return benchmark::Counter(seconds * 1e9 / opsPerFrame(), benchmark::Counter::kAvgIterations);
    };
    state.counters["submit_cpu_ns_per_op"] = perOp(submitCpuSeconds);
    state.counters["submit_ns_per_op"] = perOp(submitSeconds);
    state.counters["wait_ns_per_op"] = perOp(waitSeconds);
    cpus.report(state);
    state.SetItemsProcessed(int64_t(state.iterations()) * opsPerFrame());
}

void runPairedFrames(benchmark::State& state, const FrameSide& raw, const FrameSide& rhi) {
    const FrameSide* sides[2] = {&raw, &rhi};
    double submitCpuSeconds[2] = {0, 0};
    uint64_t block = 0;
    std::string failure;
    CpuTrail cpus;
    for (auto _ : state) {
        if (!failure.empty()) continue;   // as in runFrames
        try {
            // Which side goes first alternates, so that neither always follows the other's frames.
            for (uint64_t turn = block; turn < block + 2; ++turn) {
                const size_t s = turn % 2;
                const std::shared_ptr<void> entered = sides[s]->enter();
                for (uint32_t frame = 0; frame < pairedBlock(); ++frame) {
                    cpus.atFrame();
                    const double cpuStart = threadCpuSeconds();
                    timedSubmit(sides[s]->submit);
                    submitCpuSeconds[s] += threadCpuSeconds() - cpuStart;
                    sides[s]->wait();
                }
            }
            ++block;
        } catch (const std::exception& error) {
            failure = error.what();
        }
    }
    if (!failure.empty()) throw std::runtime_error(failure);
    auto perOp = [](double seconds) {
        return benchmark::Counter(seconds * 1e9 / (double(opsPerFrame()) * pairedBlock()),
                                  benchmark::Counter::kAvgIterations);
    };
    state.counters["raw_submit_cpu_ns_per_op"] = perOp(submitCpuSeconds[0]);
    state.counters["rhi_submit_cpu_ns_per_op"] = perOp(submitCpuSeconds[1]);
    state.counters["rhi_over_raw"] = submitCpuSeconds[0] > 0 ? submitCpuSeconds[1] / submitCpuSeconds[0] : 0.0;
    state.counters["paired_block"] = pairedBlock();
    cpus.report(state);
    state.SetItemsProcessed(int64_t(state.iterations()) * 2 * pairedBlock() * opsPerFrame());
}

void pairedRun(benchmark::State& state, const std::function<FrameSide()>& raw, const std::function<FrameSide()>& rhi) {
    runGuarded(state, [&] {
        // The RHI side first: its device names the machine, and its failure explains a missing driver.
        const FrameSide rhiFrames = rhi();
        const FrameSide rawFrames = raw();
        runPairedFrames(state, rawFrames, rhiFrames);
        for (const FrameSide* side : {&rawFrames, &rhiFrames}) {
            const std::shared_ptr<void> entered = side->enter();
            side->check();
        }
    });
}

namespace {
int g_failedRuns = 0;   // main's exit status says whether any run failed

std::vector<std::unique_ptr<Environment>>& environments() {
    static std::vector<std::unique_ptr<Environment>> all;
    return all;
}
}  // namespace

void adoptEnvironment(std::unique_ptr<Environment> environment) { environments().push_back(std::move(environment)); }

void destroyEnvironments() {
    auto& all = environments();
    while (!all.empty()) all.pop_back();
}

int failedRuns() { return g_failedRuns; }

void runFrames(benchmark::State& state, const std::function<void()>& submit, const std::function<void()>& wait,
               const std::function<std::vector<std::string>()>& takeMessages) {
    takeMessages();
    runFrames(state, submit, wait);
    const std::vector<std::string> texts = takeMessages();
    state.counters["performance_messages"] = double(texts.size());
    if (!texts.empty())
        state.SetLabel(fmt::format("{} driver performance message(s), the first: {}", texts.size(), texts.front()));
}

void runGuarded(benchmark::State& state, const std::function<void()>& body) {
    try {
        body();
    } catch (const std::exception& error) {
        // Said at once: Google Benchmark would show it only after all of the benchmark's repetitions.
        ++g_failedRuns;
        fmt::print(stderr, "janus_bench_rhi: a run failed: {}\n", error.what());
        std::fflush(stderr);
        // Not SkipWithError: with repetitions, Google Benchmark 1.7.1 aborts the process when a
        // failed run counts fewer iterations than the others (a failure before the timed loop
        // counts 0), and crashes when every repetition failed. A run that failed before its loop
        // runs the loop empty instead, and every failed run is labelled; scripts/bench.sh leaves
        // labelled runs out of its medians and names the failure (Google Benchmark's own
        // aggregates include them).
        if (state.iterations() == 0)
            for (auto _ : state) {
            }
        state.SetLabel(std::string(kFailedLabel) + error.what());
    }
}

}  // namespace janus::bench

namespace {

// Raw and RHI of one comparison are registered next to each other; scripts/bench.sh pairs them by
// name: <work>/<backend>/<raw|rhi>. frames > 0: every repetition times exactly that many frames.
void registerBenchmarks(int64_t frames) {
    using janus::rhi::Backend;
    using namespace janus::bench;
    auto add = [frames](const std::string& name, auto&& function) {
        // Real time per iteration is a whole frame (record + submit + wait), so --benchmark_min_time
        // bounds the wall time of each run; the counters split it.
        benchmark::internal::Benchmark* benchmark =
            benchmark::RegisterBenchmark(name.c_str(), function)->UseRealTime()->Unit(benchmark::kMicrosecond);
        if (frames > 0) benchmark->Iterations(frames);
    };
    add("draw/vulkan/raw", [](benchmark::State& state) { rawVulkanDraws(state, RawVulkanDraws::Plain); });
    add("draw/vulkan/rhi", [](benchmark::State& state) { rhiDraws(state, Backend::Vulkan); });
    add("dispatch/vulkan/raw", [](benchmark::State& state) { rawVulkanDispatches(state, RawVulkanDispatches::Plain); });
    add("dispatch/vulkan/rhi", [](benchmark::State& state) { rhiDispatches(state, Backend::Vulkan); });
    // Raw Vulkan recording into a pool with the RHI's command memory: RHI / this is what the RHI's
    // own code adds, with the allocator's gain taken out (scripts/bench.sh prints both ratios).
    add("draw/vulkan/raw_command_memory",
        [](benchmark::State& state) { rawVulkanDraws(state, RawVulkanDraws::CommandMemory); });
    // Not part of the ratio table: raw Vulkan with every RHI choice that reaches the driver (command
    // memory, the pipeline layout, reusable command buffers): RHI / this is the RHI's own code alone.
    add("draw/vulkan/raw_rhi_choices", [](benchmark::State& state) { rawVulkanDraws(state, RawVulkanDraws::RhiChoices); });
    // Not part of the ratio table: both sides with the per-draw calls answered by stubs
    // (null_driver.h), so that what is left is each side's own code per draw.
    add("draw/vulkan/raw_null_driver", [](benchmark::State& state) { rawVulkanDraws(state, RawVulkanDraws::NullDriver); });
    add("draw/vulkan/rhi_null_driver", [](benchmark::State& state) { rhiDrawsWithNullDriver(state, Backend::Vulkan); });
    add("dispatch/vulkan/raw_command_memory",
        [](benchmark::State& state) { rawVulkanDispatches(state, RawVulkanDispatches::CommandMemory); });
    add("dispatch/vulkan/raw_rhi_choices",
        [](benchmark::State& state) { rawVulkanDispatches(state, RawVulkanDispatches::RhiChoices); });
    // Not part of the ratio table: raw Vulkan with the RHI's old barrier rule (a full barrier before
    // every dispatch), to show what hazard tracking saved.
    add("dispatch/vulkan/raw_full_barriers",
        [](benchmark::State& state) { rawVulkanDispatches(state, RawVulkanDispatches::FullBarriers); });
    // Not part of the ratio table: the null-driver runs for dispatches (the bind and the dispatch
    // answered by stubs): the RHI's own code per dispatch.
    add("dispatch/vulkan/raw_null_driver",
        [](benchmark::State& state) { rawVulkanDispatches(state, RawVulkanDispatches::NullDriver); });
    add("dispatch/vulkan/rhi_null_driver", rhiDispatchesWithNullDriver);
    add("draw/gl/raw", [](benchmark::State& state) { rawGLDraws(state, Backend::GL, RawGLDraws::Plain); });
    add("draw/gl/rhi", [](benchmark::State& state) { rhiDraws(state, Backend::GL); });
    // Not part of the ratio table: raw GL with the RHI's old per-draw vertex setup (it now
    // re-specifies attributes only when the pipeline's layout or a vertex buffer changed).
    add("draw/gl/raw_respecified_vertices",
        [](benchmark::State& state) { rawGLDraws(state, Backend::GL, RawGLDraws::RespecifiedVertices); });
    // Not part of the ratio table: raw GL drawing from buffers made the RHI's way. The raw side makes
    // its buffers GL_STATIC_DRAW with their contents, the RHI GL_DYNAMIC_DRAW with zeros and then
    // writes them; a driver may place or track the two kinds differently, which the ratio would
    // count as the RHI's own cost (RHI / this takes it out).
    add("draw/gl/raw_rhi_buffers", [](benchmark::State& state) { rawGLDraws(state, Backend::GL, RawGLDraws::RhiBuffers); });
    // Not part of the ratio table: the null-driver runs, as for Vulkan above.
    add("draw/gl/raw_null_driver", [](benchmark::State& state) { rawGLDraws(state, Backend::GL, RawGLDraws::NullDriver); });
    add("draw/gl/rhi_null_driver", [](benchmark::State& state) { rhiDrawsWithNullDriver(state, Backend::GL); });
    // The draws again with one set whose dynamic offset moves per draw (DrawSlices::DynamicOffsets)
    // instead of a set per draw, on both sides. Raw GL's calls are the same either way (its range
    // bind is GL's dynamic offset), so its raw rows are the plain raw frames again.
    add("draw_dynamic/vulkan/raw",
        [](benchmark::State& state) { rawVulkanDraws(state, RawVulkanDraws::Plain, DrawSlices::DynamicOffsets); });
    add("draw_dynamic/vulkan/rhi",
        [](benchmark::State& state) { rhiDraws(state, Backend::Vulkan, DrawSlices::DynamicOffsets); });
    add("draw_dynamic/vulkan/raw_null_driver",
        [](benchmark::State& state) { rawVulkanDraws(state, RawVulkanDraws::NullDriver, DrawSlices::DynamicOffsets); });
    add("draw_dynamic/vulkan/rhi_null_driver",
        [](benchmark::State& state) { rhiDrawsWithNullDriver(state, Backend::Vulkan, DrawSlices::DynamicOffsets); });
    add("draw_dynamic/gl/raw", [](benchmark::State& state) { rawGLDraws(state, Backend::GL, RawGLDraws::Plain); });
    add("draw_dynamic/gl/rhi", [](benchmark::State& state) { rhiDraws(state, Backend::GL, DrawSlices::DynamicOffsets); });
    add("draw_dynamic/gles/raw", [](benchmark::State& state) { rawGLDraws(state, Backend::GLES, RawGLDraws::Plain); });
    add("draw_dynamic/gles/rhi",
        [](benchmark::State& state) { rhiDraws(state, Backend::GLES, DrawSlices::DynamicOffsets); });
    add("dispatch/gl/raw", rawGLDispatches);
    add("dispatch/gl/rhi", [](benchmark::State& state) { rhiDispatches(state, Backend::GL); });
    add("draw/gles/raw", [](benchmark::State& state) { rawGLDraws(state, Backend::GLES, RawGLDraws::Plain); });
    add("draw/gles/rhi", [](benchmark::State& state) { rhiDraws(state, Backend::GLES); });
    add("draw/gles/raw_rhi_buffers",
        [](benchmark::State& state) { rawGLDraws(state, Backend::GLES, RawGLDraws::RhiBuffers); });
    add("draw/gles/raw_null_driver",
        [](benchmark::State& state) { rawGLDraws(state, Backend::GLES, RawGLDraws::NullDriver); });
    add("draw/gles/rhi_null_driver", [](benchmark::State& state) { rhiDrawsWithNullDriver(state, Backend::GLES); });
    // Not part of the ratio table: each main pair again, its raw and RHI frames in alternating
    // blocks of one run (runPairedFrames); scripts/bench.sh prints them in a table of their own.
    // As many frames per side as the separate runs time.
    const int64_t blocks = frames > 0 ? std::max<int64_t>(1, (frames + pairedBlock() - 1) / pairedBlock()) : 0;
    auto addPaired = [blocks](const std::string& name, std::function<FrameSide()> raw, std::function<FrameSide()> rhi) {
        benchmark::internal::Benchmark* benchmark =
            benchmark::RegisterBenchmark(name.c_str(), [raw, rhi](benchmark::State& state) { pairedRun(state, raw, rhi); })
                ->UseRealTime()
                ->Unit(benchmark::kMicrosecond);
        if (blocks > 0) benchmark->Iterations(blocks);
    };
    addPaired("draw/vulkan/paired", [] { return rawVulkanSide(Work::Draws); },
              [] { return rhiSide(Backend::Vulkan, Work::Draws); });
    addPaired("dispatch/vulkan/paired", [] { return rawVulkanSide(Work::Dispatches); },
              [] { return rhiSide(Backend::Vulkan, Work::Dispatches); });
    addPaired("draw/gl/paired", [] { return rawGLSide(Backend::GL, Work::Draws); },
              [] { return rhiSide(Backend::GL, Work::Draws); });
    addPaired("dispatch/gl/paired", [] { return rawGLSide(Backend::GL, Work::Dispatches); },
              [] { return rhiSide(Backend::GL, Work::Dispatches); });
    addPaired("draw/gles/paired", [] { return rawGLSide(Backend::GLES, Work::Draws); },
              [] { return rhiSide(Backend::GLES, Work::Draws); });
    addPaired("draw_dynamic/vulkan/paired", [] { return rawVulkanSide(Work::DynamicDraws); },
              [] { return rhiSide(Backend::Vulkan, Work::DynamicDraws); });
    addPaired("draw_dynamic/gl/paired", [] { return rawGLSide(Backend::GL, Work::DynamicDraws); },
              [] { return rhiSide(Backend::GL, Work::DynamicDraws); });
    addPaired("draw_dynamic/gles/paired", [] { return rawGLSide(Backend::GLES, Work::DynamicDraws); },
              [] { return rhiSide(Backend::GLES, Work::DynamicDraws); });
}

// janus_bench_rhi's own flags, taken out of argv before Google Benchmark sees them:
//   --janus_frames=N         every repetition times exactly N frames. Fixed frame counts make
//                            --benchmark_enable_random_interleaving usable: Google Benchmark 1.7.1
//                            aborts (a ComputeStats check) when interleaved repetitions settle on
//                            different iteration counts, as they did on the H200. Interleaving
//                            spreads raw and RHI repetitions over the same minutes, so a noisy
//                            neighbour or a clock change hits both (on the H100 one process's GL
//                            draw ratio was 0.88x, the next 1.57x).
//   --janus_ops_per_frame=N  draws or dispatches per frame (default kDefaultOpsPerFrame).
//   --janus_paired_block=N   frames per side in each block of the paired runs (default
//                            kDefaultPairedBlock). Shorter blocks share the machine's moments more
//                            closely; longer ones let each side's frames run with its own data in
//                            the caches, as separate runs do.
struct JanusFlags {
    int64_t frames = 0;   // 0: Google Benchmark chooses
    uint32_t opsPerFrame = janus::bench::kDefaultOpsPerFrame;
    uint32_t pairedBlock = janus::bench::kDefaultPairedBlock;
};

JanusFlags takeJanusFlags(int& argc, char** argv) {
    struct NumberFlag {
        std::string_view prefix, what;
        int64_t min, max;
        std::function<void(int64_t)> store;
    };
    JanusFlags flags;
    const NumberFlag known[] = {
        {"--janus_frames=", "a whole number of frames", 1, 1000000, [&](int64_t n) { flags.frames = n; }},
        {"--janus_ops_per_frame=", "a whole number of draws or dispatches per frame", 1,
         janus::bench::kMaxOpsPerFrame, [&](int64_t n) { flags.opsPerFrame = uint32_t(n); }},
        {"--janus_paired_block=", "a whole number of frames", 1, 1000, [&](int64_t n) { flags.pairedBlock = uint32_t(n); }},
    };
    int kept = 1;
    for (int i = 1; i < argc; ++i) {
        const std::string_view argument = argv[i];
        const NumberFlag* flag = nullptr;
        for (const NumberFlag& candidate : known)
            if (argument.starts_with(candidate.prefix)) flag = &candidate;
        if (!flag) {
            argv[kept++] = argv[i];
            continue;
        }
        const std::string value(argument.substr(flag->prefix.size()));
        char* end = nullptr;
        const long long number = std::strtoll(value.c_str(), &end, 10);
        if (value.empty() || *end != '\0' || number < flag->min || number > flag->max) {
            fmt::print(stderr, "janus_bench_rhi: {} takes {} from {} to {}, got '{}'\n",
                       flag->prefix.substr(0, flag->prefix.size() - 1), flag->what, flag->min, flag->max, value);
            std::exit(2);
        }
        flag->store(number);
    }
    argc = kept;
    argv[argc] = nullptr;
    return flags;
}

}  // namespace

int main(int argc, char** argv) {
    // llvmpipe allocates tens of kilobytes of scene data per draw and frees it when the frame is
    // done. With glibc's default trimming, whether those pages go back to the kernel (and fault in
    // again next frame) depends on heap layout, which made one GL context up to 3x slower than an
    // otherwise identical one. Never trimming the heap takes that luck out of the comparison.
    mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
    mallopt(M_TOP_PAD, 64 << 20);
    const JanusFlags flags = takeJanusFlags(argc, argv);
    janus::bench::setOpsPerFrame(flags.opsPerFrame);
    janus::bench::setPairedBlock(flags.pairedBlock);
    registerBenchmarks(flags.frames);
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::AddCustomContext("ops_per_frame", std::to_string(janus::bench::opsPerFrame()));
    benchmark::AddCustomContext("target", fmt::format("{0}x{0} RGBA8", janus::bench::kTargetSize));
    benchmark::AddCustomContext("paired_block", std::to_string(janus::bench::pairedBlock()));
    benchmark::AddCustomContext("validation", janus::bench::validationRequested() ? "on" : "off");
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    janus::bench::destroyEnvironments();
    if (const int failed = janus::bench::failedRuns()) {
        fmt::print(stderr, "janus_bench_rhi: {} run(s) failed (labelled \"{}...\" in the output)\n", failed,
                   janus::bench::kFailedLabel);
        return janus::bench::kExitSomeRunsFailed;
    }
    return 0;
}
