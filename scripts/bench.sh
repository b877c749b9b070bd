#!/usr/bin/env bash
# Runs the RHI overhead benchmark (bench/, target janus_bench_rhi) and prints a Markdown table:
# per draw / per dispatch CPU cost of the Janus RHI against the same work issued with raw Vulkan /
# raw GL in the same run, and the ratio RHI/raw (target: <= 1.1x). For Vulkan it also prints the
# ratio against raw Vulkan recording into the RHI's command-pool memory (what the RHI's own code
# adds, the allocator's effect taken out: docs/BENCHMARKS.md, "Command memory").
#
# Usage: scripts/bench.sh [--build-dir DIR] [--repetitions N] [--min-time SECONDS] [--json FILE]
#   --build-dir    CMake build directory (default: build-bench); the target is built if missing
#   --repetitions  runs of each benchmark; the table uses the median (default: 5)
#   --min-time     minimum timed seconds per run (default: 0.2)
#   --processes    run the whole benchmark in N fresh processes and take the medians over all
#                  their repetitions (default: 1). Where a driver's heap lands in a process
#                  changes its speed (llvmpipe's GL draws: 0.99x in one process, 1.43x in the
#                  next), so a ratio from one process can be that process's luck. With more than
#                  one process (or --from-json file) the table's last column gives the lowest
#                  and highest of the processes' own ratios, their median, and how many met the
#                  target.
#   --interleave   FRAMES: every repetition times exactly FRAMES frames (janus_bench_rhi's
#                  --janus_frames) and the repetitions of all benchmarks run in random order
#                  (Google Benchmark's random interleaving), so raw and RHI share the same minutes
#                  of a noisy machine; --min-time is then unused
#   --ops-per-frame N: draws or dispatches per frame (janus_bench_rhi --janus_ops_per_frame;
#                  default 1000). Give runs at 1000 and at another size together (--from-json) and
#                  the report splits each side's cost into per frame and per operation
#   --json         also keep Google Benchmark's JSON output in FILE
#   --from-json    make the table from FILE (a --json file, or janus_bench_rhi's
#                  --benchmark_out from another machine, e.g. scripts/gpu_check.sh's) without
#                  running; repeat it for the runs of several processes
#
# Instructions: scripts/bench.sh instructions [--build-dir DIR] [--filter REGEX] [--runs N]
#                                             [--ops-per-frame N] [--split-with M]
#   the same comparisons counted in instructions per operation with callgrind (steady state, two
#   runs subtracted, median of N such estimates; valgrind needed; about 10 minutes per run), the
#   null-driver rows too; --split-with M also splits each side into per frame and per operation:
#   scripts/bench_instructions.py.
#
# Forward+: scripts/bench.sh forward [--build-dir DIR] [janus bench forward options...]
#   builds `janus` if missing and runs `janus bench forward` (default --out bench-forward);
#   the results in docs/BENCHMARKS.md ("Forward+") come from this.
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [[ "${1:-}" == forward ]]; then
  shift
  build_dir="$repo_root/build-bench"
  if [[ "${1:-}" == --build-dir ]]; then build_dir="$(realpath -m "$2")"; shift 2; fi
  if [[ ! -x "$build_dir/apps/janus/janus" ]]; then
    [[ -f "$build_dir/build.ninja" ]] || cmake -S "$repo_root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
    ninja -C "$build_dir" janus >&2
  fi
  has_out=0
  for arg in "$@"; do [[ "$arg" == --out || "$arg" == -o ]] && has_out=1; done
  if [[ $has_out == 0 ]]; then set -- "$@" --out bench-forward; fi
  exec "$build_dir/apps/janus/janus" bench forward "$@"
fi
if [[ "${1:-}" == instructions ]]; then
  shift
  build_dir="$repo_root/build-bench"
  if [[ "${1:-}" == --build-dir ]]; then build_dir="$(realpath -m "$2")"; shift 2; fi
  command -v valgrind >/dev/null || { echo "bench.sh instructions: valgrind is not installed (apt install valgrind)" >&2; exit 2; }
  if [[ ! -x "$build_dir/bench/janus_bench_rhi" ]]; then
    [[ -f "$build_dir/build.ninja" ]] || cmake -S "$repo_root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
    ninja -C "$build_dir" janus_bench_rhi >&2
  fi
  exec python3 "$repo_root/scripts/bench_instructions.py" --binary "$build_dir/bench/janus_bench_rhi" "$@"
fi
build_dir="$repo_root/build-bench"
repetitions=5
min_time=0.2
processes=1
interleave_frames=""
ops_per_frame=""
json_out=""
from_json=()

while [[ $# -gt 0 ]]; do
  case "$1" in
    --build-dir) build_dir="$(realpath -m "$2")"; shift 2 ;;
    --repetitions) repetitions="$2"; shift 2 ;;
    --min-time) min_time="$2"; shift 2 ;;
    --processes) processes="$2"; shift 2 ;;
    --interleave) interleave_frames="$2"; shift 2 ;;
    --ops-per-frame) ops_per_frame="$2"; shift 2 ;;
    --json) json_out="$2"; shift 2 ;;
    --from-json) from_json+=("$2"); shift 2 ;;
    -h|--help) sed -n '2,39p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "bench.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
  esac
done
if ! [[ "$repetitions" =~ ^[1-9][0-9]*$ ]]; then
  echo "bench.sh: --repetitions must be a positive integer, got '$repetitions'" >&2; exit 2
fi
if [[ -n "$interleave_frames" ]] && ! [[ "$interleave_frames" =~ ^[1-9][0-9]*$ ]]; then
  echo "bench.sh: --interleave takes a positive whole number of frames, got '$interleave_frames'" >&2; exit 2
fi
if ! [[ "$processes" =~ ^[1-9][0-9]*$ ]]; then
  echo "bench.sh: --processes must be a positive integer, got '$processes'" >&2; exit 2
fi

scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
if [[ ${#from_json[@]} -gt 0 ]]; then
  for file in "${from_json[@]}"; do
    [[ -f "$file" ]] || { echo "bench.sh: --from-json: no file '$file'" >&2; exit 2; }
  done
  reports=("${from_json[@]}")
else
  binary="$build_dir/bench/janus_bench_rhi"
  if [[ ! -x "$binary" ]]; then
    if [[ ! -f "$build_dir/build.ninja" ]]; then
      cmake -S "$repo_root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
    fi
    ninja -C "$build_dir" janus_bench_rhi >&2
  fi
  # Without --interleave repetitions run back to back: Google Benchmark 1.7's random interleaving
  # aborts (a failed ComputeStats check) when a benchmark's repetitions settle on different
  # iteration counts, as they did on the H200 machine; fixed frame counts rule that out. Fresh
  # processes (--processes) spread load bursts either way.
  timing=(--benchmark_min_time="$min_time")
  [[ -n "$interleave_frames" ]] && timing=(--janus_frames="$interleave_frames" --benchmark_enable_random_interleaving=true)
  [[ -n "$ops_per_frame" ]] && timing+=(--janus_ops_per_frame="$ops_per_frame")   # the binary checks the number
  reports=()
  for ((p = 0; p < processes; ++p)); do
    # Status 3: every benchmark ran, some runs failed (labelled; the table names them).
    status=0
    "$binary" --benchmark_format=json --benchmark_out_format=json --benchmark_out="$scratch/process$p.json" \
      --benchmark_repetitions="$repetitions" "${timing[@]}" >/dev/null || status=$?
    [[ $status == 0 || $status == 3 ]] || exit "$status"
    reports+=("$scratch/process$p.json")
  done
fi
# One report: the first process's context, every process's runs.
json_file="$scratch/all.json"
python3 - "$json_file" "${reports[@]}" <<'MERGE'
import json, sys
reports = [json.load(open(path)) for path in sys.argv[2:]]
# Each run keeps which process made it (a merged file's own tags stay apart by a prefix): the
# table's spread column is the ratio per process.
# Each also keeps its frame size (janus_bench_rhi --janus_ops_per_frame): runs at another size than
# the table's go into the per-frame split below it.
for index, r in enumerate(reports):
    for run in r["benchmarks"]:
        run["janus_process"] = f"{index}.{run['janus_process']}" if "janus_process" in run else str(index)
        run.setdefault("janus_ops_per_frame", int(r["context"].get("ops_per_frame", 1000)))
merged = {"context": reports[0]["context"], "benchmarks": [run for r in reports for run in r["benchmarks"]]}
merged["context"]["processes"] = sum(r["context"].get("processes", 1) for r in reports)
json.dump(merged, open(sys.argv[1], "w"), indent=1)
MERGE
[[ -n "$json_out" ]] && cp "$json_file" "$json_out"

python3 - "$json_file" <<'EOF'
import json
import statistics
import sys

TARGET = 1.1
with open(sys.argv[1]) as f:
    report = json.load(f)

# run_name is "<work>/<backend>/<raw|rhi>/real_time". The medians are taken here over the
# repetitions, so one repetition works too (Google Benchmark writes no aggregates then).
# The table is of the default frame (1000 operations) where there are such runs, else of the
# largest; runs at other frame sizes are kept apart for the per-frame split.
DEFAULT_OPS = 1000
sizes = {run.get("janus_ops_per_frame", DEFAULT_OPS) for run in report["benchmarks"]}
table_ops = DEFAULT_OPS if DEFAULT_OPS in sizes or not sizes else max(sizes)
runs, errors, other_sizes = {}, {}, {}
for run in report["benchmarks"]:
    key = tuple(run["run_name"].split("/")[:3])
    ops = run.get("janus_ops_per_frame", DEFAULT_OPS)
    # janus_bench_rhi labels a failed run "failed: <why>" (bench/bench_main.cpp, runGuarded).
    if run.get("error_occurred") or run.get("label", "").startswith("failed: "):
        errors.setdefault(key, []).append(run.get("error_message") or run["label"][len("failed: "):])
    elif run.get("run_type") == "iteration":
        (runs if ops == table_ops else other_sizes.setdefault(ops, {})).setdefault(key, []).append(run)

def median(key, counter):
    return statistics.median(run[counter] for run in runs[key])

# RHI / raw in each process that ran both sides (medians over that process's repetitions): how far
# one process's ratio can stray from the table's, which is the measurement's noise on that machine.
def process_ratios(raw_key, rhi_key):
    def by_process(key):
        groups = {}
        for run in runs[key]:
            groups.setdefault(run.get("janus_process", "0"), []).append(run["submit_cpu_ns_per_op"])
        return {p: statistics.median(values) for p, values in groups.items()}
    raw, rhi = by_process(raw_key), by_process(rhi_key)
    return sorted(rhi[p] / raw[p] for p in raw if p in rhi)

# The table's rows: (backend, work) of the compared pairs. draw_dynamic: the draws again, each
# draw's slice given by one set's dynamic offset instead of a set per draw (bench_common.h,
# DrawSlices), on both sides.
PAIRS = [("vulkan", "draw"), ("vulkan", "dispatch"), ("gl", "draw"), ("gl", "dispatch"), ("gles", "draw"),
         ("vulkan", "draw_dynamic"), ("gl", "draw_dynamic"), ("gles", "draw_dynamic")]
WORK_NAMES = {"draw": "draws", "dispatch": "dispatches", "draw_dynamic": "dynamic-offset draws"}
WORK_UNIT = {"draw": "draw", "dispatch": "dispatch", "draw_dynamic": "draw"}

def process_count(runs_by_key):
    return len({run.get("janus_process", "0") for key_runs in runs_by_key.values() for run in key_runs})

context = report["context"]
repetitions = max((len(r) for r in runs.values()), default=0)
# The processes behind the table (runs at another frame size may come from others).
processes = process_count(runs) or 1
print(f"Run {context['date']} on {context['host_name']} ({context['num_cpus']} CPUs); "
      f"{table_ops} ops per frame into a {context.get('target', '?')} target; "
      f"median of {repetitions} repetition(s)" + (f" from {processes} processes." if processes > 1 else "."))
print()
if context.get("validation") == "on":
    print("Validation was on (JANUS_BENCH_VALIDATE=1): the sides were checked, and the timings below say nothing.")
    print()
spread = processes > 1
print(f"| backend | work | raw ns/op | RHI ns/op | ratio RHI/raw | target <= {TARGET}x | wait raw ns/op | wait RHI ns/op |"
      + (" RHI/raw per process |" if spread else ""))
print("|---|---|---:|---:|---:|---|---:|---:|" + ("---|" if spread else ""))
missed = 0
for backend, work in PAIRS:
    raw_key, rhi_key = (work, backend, "raw"), (work, backend, "rhi")
    if raw_key not in runs or rhi_key not in runs:
        why = (errors.get(raw_key) or errors.get(rhi_key) or ["not run"])[0]
        print(f"| {backend} | {work} | - | - | - | skipped: {why} | - | - |" + (" - |" if spread else ""))
        continue
    raw_ns, rhi_ns = median(raw_key, "submit_cpu_ns_per_op"), median(rhi_key, "submit_cpu_ns_per_op")
    ratio = rhi_ns / raw_ns
    met = ratio <= TARGET
    missed += not met
    print(f"| {backend} | {work} | {raw_ns:.0f} | {rhi_ns:.0f} | {ratio:.2f}x | {'met' if met else 'MISSED'} | "
          f"{median(raw_key, 'wait_ns_per_op'):.0f} | {median(rhi_key, 'wait_ns_per_op'):.0f} |", end="")
    if spread:
        ratios = process_ratios(raw_key, rhi_key)
        print(f" {ratios[0]:.2f}x to {ratios[-1]:.2f}x, median {statistics.median(ratios):.2f}x, "
              f"{sum(r <= TARGET for r in ratios)} of {len(ratios)} met |" if ratios else " - |", end="")
    print()
print()
print("ns/op: CPU time of the benchmark thread to record + submit one frame, divided by the draws or "
      "dispatches in it (median over repetitions). wait: wall time until the frame had finished "
      "(fence wait / waitIdle / glFinish), reported apart and not part of the ratio."
      + (" RHI/raw per process: the lowest and highest of the processes' own ratios, their median, and how many met "
         "the target. Where a machine switches between speeds from process to process (the H200's raw Vulkan draw: "
         "about 54 or about 80 ns), the median of the processes' own ratios compares each RHI run with the raw run "
         "of its own process; the table's ratio compares medians taken over all processes."
         if spread else ""))
# Paired runs (janus_bench_rhi's <work>/<backend>/paired): each main pair again, raw and RHI frames
# in alternating blocks of one run, so that both sides share the machine's moments. The ratio is
# the median of the runs' own ratios (each run's RHI time over its raw time).
paired_rows = []
for backend, work in PAIRS:
    key = (work, backend, "paired")
    if key not in runs:
        continue
    ratios = [run["rhi_over_raw"] for run in runs[key]]
    ratio = statistics.median(ratios)
    row = (f"| {backend} | {work} | {median(key, 'raw_submit_cpu_ns_per_op'):.0f} | "
           f"{median(key, 'rhi_submit_cpu_ns_per_op'):.0f} | {ratio:.2f}x | {'met' if ratio <= TARGET else 'MISSED'} | "
           f"{min(ratios):.2f}x to {max(ratios):.2f}x, {sum(r <= TARGET for r in ratios)} of {len(ratios)} met |")
    paired_rows.append(row)
if paired_rows:
    blocks = sorted({int(run.get("paired_block", 0)) for key in runs if key[2] == "paired" for run in runs[key]})
    print(f"\nPaired runs: raw and RHI frames in alternating blocks of {', '.join(map(str, blocks))} frame(s) each, "
          f"in one run (docs/BENCHMARKS.md, \"Paired runs\"). Ratio: the median of the runs' own RHI/raw.")
    print()
    print(f"| backend | work | raw ns/op | RHI ns/op | ratio RHI/raw | target <= {TARGET}x | RHI/raw per run |")
    print("|---|---|---:|---:|---:|---|---|")
    print("\n".join(paired_rows))
# Raw Vulkan recording into the RHI's command-pool memory: RHI / this is what the RHI's own code
# adds with the allocator's effect taken out (docs/BENCHMARKS.md, "Command memory").
for work in ("draw", "dispatch"):
    extra, rhi_key = (work, "vulkan", "raw_command_memory"), (work, "vulkan", "rhi")
    if extra in runs and rhi_key in runs:
        raw_cm = median(extra, "submit_cpu_ns_per_op")
        print(f"\nRaw Vulkan {WORK_NAMES[work]} recording into the RHI's command memory: {raw_cm:.0f} ns/op; "
              f"RHI / this = {median(rhi_key, 'submit_cpu_ns_per_op') / raw_cm:.2f}x (what the RHI's own code adds).")
# The raw side with the RHI's choices that reach the driver: this / raw is what those choices cost
# in the driver, RHI / this what the RHI adds besides them (docs/BENCHMARKS.md, "Explanatory runs").
AS_RHI = [("draw", "vulkan", "raw_rhi_choices", "Raw Vulkan draws with the RHI's choices that reach the driver (command memory, "
           "pipeline layout, reusable command buffers)", "those choices' share", "the RHI's own code"),
          ("dispatch", "vulkan", "raw_rhi_choices", "Raw Vulkan dispatches with the RHI's choices that reach the driver (command "
           "memory, pipeline layout, reusable command buffers)", "those choices' share", "the RHI's own code"),
          ("draw", "gl", "raw_rhi_buffers", "Raw GL draws from buffers made as the RHI makes them", "the buffer kind's share", "the rest"),
          ("draw", "gles", "raw_rhi_buffers", "Raw GLES draws from buffers made as the RHI makes them", "the buffer kind's share", "the rest")]
for work, backend, side, what, share, rest in AS_RHI:
    extra, raw_key, rhi_key = (work, backend, side), (work, backend, "raw"), (work, backend, "rhi")
    if extra in runs and rhi_key in runs and raw_key in runs:
        as_rhi = median(extra, "submit_cpu_ns_per_op")
        print(f"\n{what}: {as_rhi:.0f} ns/op (this / raw = {as_rhi / median(raw_key, 'submit_cpu_ns_per_op'):.2f}x, {share}); "
              f"RHI / this = {median(rhi_key, 'submit_cpu_ns_per_op') / as_rhi:.2f}x ({rest}).")
# Both sides with the per-operation calls answered by stubs (bench/null_driver.h): what is left is
# each side's own code per draw or dispatch, and RHI minus raw is the RHI's, on this machine's CPU.
NULL_CALLS = {("draw", "vulkan"): "vkCmdBindDescriptorSets and vkCmdDraw",
              ("dispatch", "vulkan"): "vkCmdBindDescriptorSets and vkCmdDispatch",
              ("draw_dynamic", "vulkan"): "vkCmdBindDescriptorSets with its dynamic offset, and vkCmdDraw",
              ("draw", "gl"): "glBindBufferRange and glDrawArrays", ("draw", "gles"): "glBindBufferRange and glDrawArrays"}
for (work, backend), calls in NULL_CALLS.items():
    raw_null, rhi_null = (work, backend, "raw_null_driver"), (work, backend, "rhi_null_driver")
    raw_key, rhi_key = (work, backend, "raw"), (work, backend, "rhi")
    if raw_null in runs and rhi_null in runs:
        own = median(rhi_null, "submit_cpu_ns_per_op") - median(raw_null, "submit_cpu_ns_per_op")
        name = "Vulkan" if backend == "vulkan" else backend.upper()
        line = (f"\n{name} {WORK_NAMES[work]} with a null driver ({calls} answered by stubs): "
                f"raw {median(raw_null, 'submit_cpu_ns_per_op'):.1f}, RHI {median(rhi_null, 'submit_cpu_ns_per_op'):.1f} ns/op: "
                f"the RHI's own code takes {own:.1f} ns per {WORK_UNIT[work]}")
        if raw_key in runs and rhi_key in runs:   # a run of the null driver alone has no real operation to compare with
            raw_ns = median(raw_key, "submit_cpu_ns_per_op")
            line += (f"; over this run's raw {WORK_UNIT[work]} ({raw_ns:.0f} ns) that alone would be {(raw_ns + own) / raw_ns:.2f}x "
                     f"(measured: {median(rhi_key, 'submit_cpu_ns_per_op') / raw_ns:.2f}x)")
        print(line + ".")
# The machine's own speed: raw Vulkan draws with a null driver are CPU work alone (no driver call
# per draw), so the spread of their runs is how far the machine's speed moved while measuring (the
# H200's CPU: 1.5x from run to run; docs/BENCHMARKS.md, session 25). Separate raw and RHI runs
# carry that spread into their ratio; the paired runs do not. With the runs' CPU counters
# (janus_bench_rhi's cpu), also which logical CPUs the slowest and the fastest quarter ran on.
speed_key = ("draw", "vulkan", "raw_null_driver")
if speed_key in runs and len(runs[speed_key]) > 1:
    by_time = sorted(runs[speed_key], key=lambda run: run["submit_cpu_ns_per_op"])
    fastest, slowest = by_time[0]["submit_cpu_ns_per_op"], by_time[-1]["submit_cpu_ns_per_op"]
    line = (f"\nThis machine's speed: raw Vulkan draws with a null driver (CPU work alone) took {fastest:.1f} to "
            f"{slowest:.1f} ns/op over {len(by_time)} runs ({slowest / fastest:.2f}x)")
    if all("cpu" in run for run in by_time):
        quarter = max(1, len(by_time) // 4)
        cpus = lambda part: ", ".join(str(c) for c in sorted({int(run["cpu"]) for run in part}))
        line += (f"; the slowest {quarter} run(s) ran on CPU(s) {cpus(by_time[-quarter:])}, "
                 f"the fastest {quarter} on {cpus(by_time[:quarter])}")
    print(line + ".")
# Explanatory runs: the raw side with one RHI habit added, to show what that habit costs.
for extra, what in [(("dispatch", "vulkan", "raw_full_barriers"), "Raw Vulkan with a full barrier before every dispatch (the RHI's policy before hazard tracking)"),
                    (("draw", "gl", "raw_respecified_vertices"), "Raw GL re-specifying the vertex attribute before every draw (what the RHI did before it tracked vertex state)")]:
    if extra in runs:
        print(f"\n{what}: {median(extra, 'submit_cpu_ns_per_op'):.0f} ns/op, wait {median(extra, 'wait_ns_per_op'):.0f} ns/op.")
# Per frame and per operation: a frame's fixed cost F (begin, pass, pipeline, submit; for the RHI
# also execute()'s setup and what replay does once per list) weighs F/n on each of its n
# operations, so cost(n) = F/n + D. Runs at two frame sizes give both: D is what a draw costs once
# frames are long, and RHI/raw of D is the per-operation ratio without any per-frame difference.
for ops, sized in sorted(other_sizes.items()):
    rows, negative_frame = [], False
    for backend, work in PAIRS:
        keys = [(work, backend, side) for side in ("raw", "rhi")]
        if not all(key in runs and key in sized for key in keys):
            continue
        split = []
        for key in keys:
            at_table = median(key, "submit_cpu_ns_per_op")
            at_other = statistics.median(run["submit_cpu_ns_per_op"] for run in sized[key])
            per_op = (table_ops * at_table - ops * at_other) / (table_ops - ops)
            split.append((at_other, table_ops * (at_table - per_op), per_op))
        (raw_other, raw_frame, raw_op), (rhi_other, rhi_frame, rhi_op) = split
        negative_frame = negative_frame or raw_frame < 0 or rhi_frame < 0
        ratio = f"{rhi_op / raw_op:.2f}x" if raw_op > 0 else "- (raw per op <= 0: too noisy)"
        rows.append(f"| {backend} | {work} | {raw_other:.0f} | {rhi_other:.0f} | {raw_frame / 1000:.1f} | "
                    f"{rhi_frame / 1000:.1f} | {raw_op:.0f} | {rhi_op:.0f} | {ratio} |")
    if not rows:
        continue
    print(f"\nPer frame and per operation, from frames of {table_ops} (the table) and of {ops} operations "
          f"({process_count(sized)} process(es) at {ops}): cost per op = per frame / ops + per op.")
    print()
    print(f"| backend | work | raw ns/op at {ops} | RHI ns/op at {ops} | raw us/frame | RHI us/frame | raw ns/op alone | "
          f"RHI ns/op alone | RHI/raw per op |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
    print("\n".join(rows))
    if negative_frame:
        print("\nA negative cost per frame means the cost per operation was not the same at both frame sizes "
              "(llvmpipe's grows with the draws in a frame, whose scene it bins): that row's split does not hold.")
# With validation on (JANUS_BENCH_VALIDATE=1), each side counts the driver's performance messages in
# its timed frames (bench_common.h, runFrames): a side whose driver recompiles or
# moves something every frame pays for it per frame.
if context.get("validation") == "on":
    noisy = []
    for key, key_runs in sorted(runs.items()):
        counted = [run for run in key_runs if "performance_messages" in run]
        total = sum(int(run["performance_messages"]) for run in counted)
        if total:
            first = next(run["label"] for run in counted if run.get("label"))
            noisy.append(f"- {'/'.join(key)}: {total} in {sum(int(run['iterations']) for run in counted)} frames; {first}")
    print("\nDriver performance messages in the timed frames (validation on): " + ("none." if not noisy else ""))
    if noisy:
        print()
        print("\n".join(noisy))
for key, messages in sorted(errors.items()):
    if key in runs:   # the table used the repetitions that ran; say that some did not
        print(f"\n{len(messages)} repetition(s) of {'/'.join(key)} failed and were left out: {messages[0]}")
if missed and context.get("validation") != "on":
    print(f"\n{missed} comparison(s) above the {TARGET}x target: see docs/BENCHMARKS.md for where the time goes.")
EOF
