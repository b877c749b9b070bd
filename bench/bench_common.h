// Shared by every benchmark in janus_bench_rhi: the workload both sides issue, the timing loop
// that splits "record + submit" from "wait", and the registry that owns the devices.
#pragma once

#include <benchmark/benchmark.h>
#include <janus/rhi/rhi.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace janus::bench {

// One frame of work. The same numbers drive the raw and the RHI side of every comparison.
// Draws or dispatches per frame (per command list): kDefaultOpsPerFrame, or janus_bench_rhi's
// --janus_ops_per_frame. A cost paid once per frame weighs 1/opsPerFrame() on each operation, so
// runs at two frame sizes split per-frame from per-operation cost (scripts/bench.sh does).
inline constexpr uint32_t kDefaultOpsPerFrame = 1000;
// Each draw's colour is its index in two bytes (drawColorBytes): no two draws of a frame alike.
inline constexpr uint32_t kMaxOpsPerFrame = 65536;
uint32_t opsPerFrame();
void setOpsPerFrame(uint32_t ops);   // before the first benchmark runs: the sides size their sets by it
inline constexpr uint32_t kTargetSize = 8;            // 8x8 RGBA8 target: rasterisation is negligible
// Every draw/dispatch binds its own 256-byte slice: 256 satisfies every device's UBO/SSBO
// offset alignment, so both sides use identical offsets without querying anything.
inline constexpr uint64_t kSliceBytes = 256;
inline uint64_t slicedBufferBytes() { return kSliceBytes * opsPerFrame(); }
// The triangle covers the top-left corner (rows 0..3 on every backend), texel (0, 0) included.
inline constexpr std::array<float, 6> kTriangle = {-1.0f, -1.0f, 0.0f, -1.0f, -1.0f, 0.0f};

// Colour of draw i: exact in RGBA8 (multiples of 1/255), so the last draw's colour can be checked
// byte for byte in the target.
std::array<float, 4> drawColor(uint32_t drawIndex);
std::array<uint8_t, 4> drawColorBytes(uint32_t drawIndex);
// Throws WrongResult unless `texel` (RGBA8, texel (0, 0) of the target) has the last draw's
// colour; the message says whose colour it has instead (another draw's, or none: the clear's).
void requireLastDrawColor(const void* texel, std::string_view who);
// opsPerFrame() std140 blocks { vec4 color; }, one per kSliceBytes slice.
std::vector<std::byte> drawParameterData();

// JANUS_BENCH_VALIDATE=1 runs every device with validation layers / GL debug output and fails on
// any message but performance ones (slower: for checking the benchmark, not for timing it).
bool validationRequested();

// Thrown when a benchmark finds that the work it timed did not produce the expected result.
class WrongResult : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Runs `submit` (record + submit the frame; timed) then `wait` (until the frame has finished;
// timed separately) once per benchmark iteration. Reports, per draw/dispatch:
//   submit_cpu_ns_per_op  CPU time of the benchmark thread to record and submit (the compared figure)
//   submit_ns_per_op      wall time of the same
//   wait_ns_per_op        wall time waiting for the device to finish (lavapipe/llvmpipe execute on
//                         CPU threads, so this is mostly the driver running the work)
void runFrames(benchmark::State& state, const std::function<void()>& submit, const std::function<void()>& wait);

// Devices live until main() tears them down, in reverse order of creation: Google Benchmark calls
// each benchmark function several times and device start-up must not be timed or repeated.
class Environment {
public:
    virtual ~Environment() = default;
};

void adoptEnvironment(std::unique_ptr<Environment> environment);
void destroyEnvironments();

template <typename T, typename... Args>
T& sharedEnvironment(Args&&... args) {
    static T* instance = nullptr;
    if (!instance) {
        auto created = std::make_unique<T>(std::forward<Args>(args)...);
        instance = created.get();
        adoptEnvironment(std::move(created));
    }
    return *instance;
}

// runFrames, also reporting the driver's performance messages of those frames (GL debug output's
// GL_DEBUG_TYPE_PERFORMANCE, the RHI's IDevice::takePerformanceMessages; validation on, with
// JANUS_BENCH_VALIDATE): `takeMessages` returns the side's messages since its last call, so what
// came before the frames (setting up, an earlier run's check) is dropped and the check after them
// is not counted. Never failures, but a driver that recompiles a shader or moves a buffer every
// frame says so here, and that would be a per-frame cost of the side. Reported as the run's
// counter performance_messages and, when there are any, its label "<n> driver performance
// message(s), the first: <text>" (scripts/bench.sh prints them under the table).
void runFrames(benchmark::State& state, const std::function<void()>& submit, const std::function<void()>& wait,
               const std::function<std::vector<std::string>()>& takeMessages);

// One side of a paired run (runPairedFrames): its frame, the wait for it, and the check of what
// its frames did. `enter` is called before each block of its frames and before the check, and
// what it returns is held while they run: the GL sides make their context current there, untimed.
struct FrameSide {
    std::function<void()> submit;
    std::function<void()> wait;
    std::function<void()> check;
    std::function<std::shared_ptr<void>()> enter = [] { return std::shared_ptr<void>(); };
};
// How each draw gets its own uniform slice: a binding set (descriptor set) of its own, or one set
// whose dynamic offset moves per draw (BindingItem::dynamicOffset, Vulkan's
// UNIFORM_BUFFER_DYNAMIC). Raw GL binds a range per draw either way: glBindBufferRange is GL's
// dynamic offset.
enum class DrawSlices { PerDrawSets, DynamicOffsets };
enum class Work { Draws, Dispatches, DynamicDraws };
// A side whose frames are submitDraws(slices) / submitDispatches() and whose checks are
// checkDraws() / checkDispatches() (every raw side and the RHI scene).
template <class Side>
FrameSide frameSideOf(Side& side, Work work, std::function<void()> wait) {
    FrameSide frames;
    frames.wait = std::move(wait);
    if (work != Work::Dispatches) {
        const DrawSlices slices = work == Work::DynamicDraws ? DrawSlices::DynamicOffsets : DrawSlices::PerDrawSets;
        frames.submit = [&side, slices] { side.submitDraws(slices); };
        frames.check = [&side] { side.checkDraws(); };
    } else {
        frames.submit = [&side] { side.submitDispatches(); };
        frames.check = [&side] { side.checkDispatches(); };
    }
    return frames;
}
// `side`, the raw or RHI side of `backend`, for a dispatch benchmark: it must have compute.
template <class Side>
Side& requireCompute(Side& side, rhi::Backend backend) {
    if (!side.hasCompute()) throw std::runtime_error(std::string(rhi::toString(backend)) + " has no compute");
    return side;
}
FrameSide rawVulkanSide(Work work);
FrameSide rawGLSide(rhi::Backend backend, Work work);
FrameSide rhiSide(rhi::Backend backend, Work work);

// Frames per side in each block of a paired run (janus_bench_rhi --janus_paired_block; default 8).
inline constexpr uint32_t kDefaultPairedBlock = 8;
uint32_t pairedBlock();
void setPairedBlock(uint32_t frames);

// Raw and RHI frames of one comparison in alternating blocks of pairedBlock() frames each, the side
// that goes first alternating too, in one run: both sides share the same moments of the machine.
// On the H200 the same code ran at one of two speeds about 1.5x apart from one benchmark run to
// the next (docs/BENCHMARKS.md, "Paired runs"), which separate runs of raw and RHI cannot
// tell from a difference between them. One iteration is one block of each side. Reports
// raw_submit_cpu_ns_per_op and rhi_submit_cpu_ns_per_op (as runFrames' submit_cpu_ns_per_op) and
// their ratio, rhi_over_raw, of this run alone.
void runPairedFrames(benchmark::State& state, const FrameSide& raw, const FrameSide& rhi);
void pairedRun(benchmark::State& state, const std::function<FrameSide()>& raw, const std::function<FrameSide()>& rhi);

// Calls `body` and turns exceptions into a run labelled kFailedLabel + the message, so that one
// unavailable backend does not hide the others' results.
inline constexpr std::string_view kFailedLabel = "failed: ";
void runGuarded(benchmark::State& state, const std::function<void()>& body);
// How many runs failed so far. janus_bench_rhi then exits with kExitSomeRunsFailed: everything
// ran and the report is whole, but some of its runs are failures.
int failedRuns();
inline constexpr int kExitSomeRunsFailed = 3;

// The benchmarks. Each times opsPerFrame() draws (into the 8x8 target, rebinding the colour
// uniform block per draw) or dispatches (1x1x1, rebinding the counter per dispatch) per iteration.
void rhiDraws(benchmark::State& state, rhi::Backend backend, DrawSlices slices = DrawSlices::PerDrawSets);
// With the per-draw driver calls answered by stubs (null_driver.h): the RHI's own code.
void rhiDrawsWithNullDriver(benchmark::State& state, rhi::Backend backend,
                            DrawSlices slices = DrawSlices::PerDrawSets);
void rhiDispatches(benchmark::State& state, rhi::Backend backend);
// The same for Vulkan dispatches.
void rhiDispatchesWithNullDriver(benchmark::State& state);
// How the raw Vulkan side draws: as an application would, or with RHI choices added (explanatory
// runs, printed apart by scripts/bench.sh).
enum class RawVulkanDraws {
    Plain,
    CommandMemory,   // recording into a command pool whose host memory is the RHI's CommandMemory
    RhiChoices,      // that, and the RHI's pipeline layout (four set layouts) and reusable command
                     // buffers (no ONE_TIME_SUBMIT): every choice of the RHI's that reaches the driver
    NullDriver,      // Plain, with the per-draw calls answered by stubs (null_driver.h)
};
void rawVulkanDraws(benchmark::State& state, RawVulkanDraws how, DrawSlices slices = DrawSlices::PerDrawSets);
// How the raw Vulkan side dispatches: as an application would, or with one thing changed
// (explanatory runs, printed apart by scripts/bench.sh).
enum class RawVulkanDispatches {
    Plain,
    CommandMemory,   // recording into a command pool whose host memory is the RHI's CommandMemory
    RhiChoices,      // that, the RHI's compute pipeline layout (four set layouts) and reusable
                     // command buffers: every choice of the RHI's that reaches the driver
    FullBarriers,    // a full barrier before each dispatch (the RHI's rule before hazard tracking)
    NullDriver,      // Plain, with the per-dispatch calls answered by stubs (null_driver.h)
};
void rawVulkanDispatches(benchmark::State& state, RawVulkanDispatches how);
// How the raw GL side draws: as a hand-written renderer would, or with one habit of the RHI's GL
// backend added (explanatory runs, printed apart by scripts/bench.sh).
enum class RawGLDraws {
    Plain,
    RespecifiedVertices,   // the vertex attribute re-specified before every draw (the RHI's old setup)
    RhiBuffers,            // from buffers made as the RHI makes them (gl_buffer.cpp): GL_DYNAMIC_DRAW,
                           // zeros from the host, then the contents by glBufferSubData
    NullDriver,            // Plain, with the per-draw calls answered by stubs (null_driver.h)
};
// GL or GLES.
void rawGLDraws(benchmark::State& state, rhi::Backend backend, RawGLDraws how);
void rawGLDispatches(benchmark::State& state);

}  // namespace janus::bench
