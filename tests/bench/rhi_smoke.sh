#!/usr/bin/env bash
# janus_bench_rhi, two frames of every benchmark with validation on (JANUS_BENCH_VALIDATE: the
# Vulkan validation layer and GL debug output on the RHI side, the layer on the raw Vulkan side):
# every benchmark checks what it drew or counted, so a raw or RHI side that does the work wrong,
# fails, or makes a validation message fails here rather than on the next GPU machine. Then the
# report scripts/bench.sh makes of that output: a ratio in every row, every explanatory line.
# Timings of two frames mean nothing; nothing here reads them.
# Usage: rhi_smoke.sh JANUS_BENCH_RHI REPO_ROOT
set -euo pipefail
binary=$1
repo_root=$2
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
# A table row's first cells ("vulkan | draw") as an extended regex: its bars literal, not alternatives.
cells() { printf '%s' "${1//|/\\|}"; }

status=0
JANUS_BENCH_VALIDATE=1 "$binary" --janus_frames=2 --benchmark_format=json --benchmark_out_format=json \
  --benchmark_out="$scratch/bench.json" >"$scratch/stdout" 2>"$scratch/stderr" || status=$?
[[ $status == 0 ]] || { cat "$scratch/stderr" >&2; fail "janus_bench_rhi exited with status $status"; }
# The raw Vulkan side has no debug messenger: the layer prints what it finds.
if grep -qi "validation error\|VUID-" "$scratch/stdout" "$scratch/stderr"; then
  grep -i -m3 "validation error\|VUID-" "$scratch/stdout" "$scratch/stderr" >&2
  fail "a validation message while benchmarking"
fi

"$binary" --benchmark_list_tests=true >"$scratch/listed"
python3 - "$scratch/bench.json" "$scratch/listed" <<'PY' || exit 1
import json, sys
runs = json.load(open(sys.argv[1]))["benchmarks"]
name = lambda text: "/".join(text.split("/")[:3])   # <work>/<backend>/<side>
listed = [name(line.strip()) for line in open(sys.argv[2]) if line.strip()]
ran = {name(run["run_name"]): run for run in runs}
missing = [name for name in listed if name not in ran]
failed = [f"{name}: {run['label']}" for name, run in ran.items() if run.get("label", "").startswith("failed: ")]
if missing or failed or len(listed) < 14:
    sys.exit(f"FAIL: listed {len(listed)} benchmarks; missing {missing}; failed {failed}")
# Every run names the logical CPU its last frame started on, and counts its frames' migrations.
nameless = [name for name, run in ran.items() if not (run.get("cpu", -1) >= 0 and run.get("cpu_migrations", -1) >= 0)]
if nameless:
    sys.exit(f"FAIL: runs without their CPU (counters cpu, cpu_migrations): {nameless}")
PY

report=$(bash "$repo_root/scripts/bench.sh" --from-json "$scratch/bench.json")
# The rows of the table and of the paired runs' table: scripts/bench.sh's PAIRS.
table_rows=("vulkan | draw" "vulkan | dispatch" "gl | draw" "gl | dispatch" "gles | draw"
            "vulkan | draw_dynamic" "gl | draw_dynamic" "gles | draw_dynamic")
for row in "${table_rows[@]}"; do
  grep -Eq "^\| $(cells "$row") \| [0-9]+ \| [0-9]+ \| [0-9.]+x \|" <<<"$report" || fail "the report has no ratio for $row:
$report"
done
for line in "Raw Vulkan draws recording into the RHI's command memory" \
            "Raw Vulkan draws with the RHI's choices that reach the driver" \
            "Raw Vulkan dispatches with the RHI's choices that reach the driver" \
            "Raw GL draws from buffers made as the RHI makes them" \
            "Raw GLES draws from buffers made as the RHI makes them" \
            "Vulkan draws with a null driver" "Vulkan dispatches with a null driver" \
            "Vulkan dynamic-offset draws with a null driver" \
            "GL draws with a null driver" "GLES draws with a null driver" \
            "Raw GL re-specifying the vertex attribute" "Raw Vulkan with a full barrier before every dispatch"; do
  grep -qF "$line" <<<"$report" || fail "the report lacks \"$line\":
$report"
done
# The paired runs (raw and RHI frames in alternating blocks of one run) have a table of their own.
grep -qF "Paired runs: raw and RHI frames in alternating blocks of 8 frame(s) each" <<<"$report" \
  || fail "the report has no table of the paired runs:
$report"
for row in "${table_rows[@]}"; do
  [[ $(grep -Ec "^\| $(cells "$row") \| [0-9]+ \| [0-9]+ \| [0-9.]+x \| (met|MISSED) \| [0-9.]+x to [0-9.]+x, [01] of 1 met \|$" <<<"$report") == 1 ]] \
    || fail "the paired table has no row for $row:
$report"
done
grep -qF "Driver performance messages in the timed frames (validation on):" <<<"$report" \
  || fail "the report of a validated run does not say which driver performance messages its frames had:
$report"
# Each side counts its driver's performance messages per frame: here one inserted per RHI frame.
status=0
JANUS_BENCH_VALIDATE=1 JANUS_BENCH_TEST_PERFORMANCE_MESSAGE=1 "$binary" --janus_frames=2 --benchmark_filter='^draw/[a-z]+/rhi/' \
  --benchmark_format=json --benchmark_out_format=json --benchmark_out="$scratch/messages.json" >/dev/null 2>"$scratch/stderr" || status=$?
[[ $status == 0 ]] || { cat "$scratch/stderr" >&2; fail "janus_bench_rhi with a test performance message exited with status $status"; }
report=$(bash "$repo_root/scripts/bench.sh" --from-json "$scratch/messages.json")
for side in vulkan gl gles; do
  grep -Eq "^- draw/$side/rhi: [0-9]+ in 2 frames; [0-9]+ driver performance message\(s\), the first: .*bench test message" <<<"$report" \
    || fail "the report does not count the performance message of each draw/$side/rhi frame:
$report"
done

# Two processes' runs (here the same file twice): each row also gives the ratio's spread per process.
report=$(bash "$repo_root/scripts/bench.sh" --from-json "$scratch/bench.json" --from-json "$scratch/bench.json")
for row in "vulkan | draw" "gl | draw" "gles | draw"; do
  grep -Eq "^\| $(cells "$row") \| .* \| [0-9.]+x to [0-9.]+x, median [0-9.]+x, [0-2] of 2 met \|$" <<<"$report" || fail "no per-process spread for $row:
$report"
done
# Three processes whose Vulkan draws are 1.0x, 2.0x and 1.2x raw's: the spread names the median of
# the processes' own ratios (1.2x), not the lowest, the highest or the first.
for p in 0 1 2; do
  python3 - "$scratch/bench.json" "$scratch/process$p.json" "$(( (p == 1) ? 20 : (p == 2) ? 12 : 10 ))" <<'SCALE'
import json, sys
report = json.load(open(sys.argv[1]))
for run in report["benchmarks"]:
    if run["run_name"].split("/")[:3] in (["draw", "vulkan", "raw"], ["draw", "vulkan", "rhi"]):
        run["submit_cpu_ns_per_op"] = 100.0 if run["run_name"].startswith("draw/vulkan/raw/") else 10.0 * int(sys.argv[3])
    if run["run_name"].startswith("draw/vulkan/paired/"):
        run["rhi_over_raw"] = int(sys.argv[3]) / 10
    if run["run_name"].startswith("draw/vulkan/raw_null_driver/"):   # the machine's speed, on CPU 10, 20 or 12
        run["submit_cpu_ns_per_op"], run["cpu"] = float(sys.argv[3]), int(sys.argv[3])
json.dump(report, open(sys.argv[2], "w"))
SCALE
done
report=$(bash "$repo_root/scripts/bench.sh" --from-json "$scratch/process0.json" --from-json "$scratch/process1.json" \
  --from-json "$scratch/process2.json")
grep -Eq "^\| vulkan \| draw \| .* \| 1\.00x to 2\.00x, median 1\.20x, 1 of 3 met \|$" <<<"$report" \
  || fail "the per-process spread does not give the median of the processes' ratios (1.20x):
$report"
# The spread of the CPU-only runs is the machine's speed, with the CPUs of the slowest and fastest.
grep -qF "This machine's speed: raw Vulkan draws with a null driver (CPU work alone) took 10.0 to 20.0 ns/op over 3 runs (2.00x); the slowest 1 run(s) ran on CPU(s) 20, the fastest 1 on 10." <<<"$report" \
  || fail "the report does not give the machine's speed from the null-driver runs:
$report"
# The same for the paired runs: their ratio is the median of the runs' own ratios.
grep -Eq "^\| vulkan \| draw \| [0-9]+ \| [0-9]+ \| 1\.20x \| MISSED \| 1\.00x to 2\.00x, 1 of 3 met \|$" <<<"$report" \
  || fail "the paired runs' ratio is not the median of their own ratios (1.20x):
$report"

# The null driver with a footprint (JANUS_BENCH_NULL_FOOTPRINT) still gets every call it counts.
status=0
JANUS_BENCH_NULL_FOOTPRINT=96 "$binary" --janus_frames=2 --benchmark_filter=null_driver >"$scratch/footprint" 2>&1 || status=$?
[[ $status == 0 ]] || { cat "$scratch/footprint" >&2; fail "the null-driver runs with a footprint exited with status $status"; }
status=0
JANUS_BENCH_NULL_FOOTPRINT=999999999 "$binary" --janus_frames=2 --benchmark_filter=gl/raw_null_driver >"$scratch/footprint" 2>&1 || status=$?
[[ $status != 0 ]] && grep -q "more than the" "$scratch/footprint" || fail "an absurd footprint was not refused by name"
status=0
JANUS_BENCH_NULL_FOOTPRINT=64k "$binary" --janus_frames=2 --benchmark_filter=gl/raw_null_driver >"$scratch/footprint" 2>&1 || status=$?
[[ $status != 0 ]] && grep -q "is not a number of bytes" "$scratch/footprint" || fail "a footprint that is not a number was not refused"

# Another frame size (--janus_ops_per_frame): every side still checks what it drew or counted (the
# last draw's colour, every counter, the null driver's calls and offsets), and the report of runs
# at both sizes splits each pair into per frame and per operation.
status=0
JANUS_BENCH_VALIDATE=1 "$binary" --janus_frames=2 --janus_ops_per_frame=5 --benchmark_filter='/(raw|rhi|raw_null_driver|rhi_null_driver)/' \
  --benchmark_format=json --benchmark_out_format=json --benchmark_out="$scratch/bench5.json" >/dev/null 2>"$scratch/stderr" || status=$?
[[ $status == 0 ]] || { cat "$scratch/stderr" >&2; fail "janus_bench_rhi --janus_ops_per_frame=5 exited with status $status"; }
grep -q '"ops_per_frame": "5"' "$scratch/bench5.json" || fail "the JSON of --janus_ops_per_frame=5 does not say so in its context"
report=$(bash "$repo_root/scripts/bench.sh" --from-json "$scratch/bench.json" --from-json "$scratch/bench5.json")
grep -qF "Per frame and per operation, from frames of 1000 (the table) and of 5 operations" <<<"$report" \
  || fail "no per-frame split in the report of runs at 1000 and 5 operations per frame:
$report"
for row in "vulkan | draw" "vulkan | dispatch" "gl | draw" "gl | dispatch" "gles | draw"; do
  grep -Eq "^\| $(cells "$row") \| [0-9]+ \| [0-9]+ \| -?[0-9.]+ \| -?[0-9.]+ \| -?[0-9]+ \| -?[0-9]+ \| " <<<"$report" \
    || fail "the per-frame split has no row for $row:
$report"
done
# The table itself is of the 1000-operation runs alone: one process's.
grep -q "median of 1 repetition(s)\.$" <<<"$report" || fail "the table mixed in the runs at another frame size:
$report"
status=0
"$binary" --janus_ops_per_frame=0 --benchmark_filter=none >"$scratch/flag" 2>&1 || status=$?
[[ $status == 2 ]] && grep -q "janus_ops_per_frame takes a whole number" "$scratch/flag" \
  || fail "--janus_ops_per_frame=0 was not refused by name (status $status): $(cat "$scratch/flag")"
status=0
"$binary" --janus_paired_block=0 --benchmark_filter=none >"$scratch/flag" 2>&1 || status=$?
[[ $status == 2 ]] && grep -q "janus_paired_block takes a whole number" "$scratch/flag" \
  || fail "--janus_paired_block=0 was not refused by name (status $status): $(cat "$scratch/flag")"
echo "janus_bench_rhi: $(wc -l <"$scratch/listed") benchmarks ran and checked their results; the report is whole"
