#!/usr/bin/env bash
# Everything issue 10 asks of a GPU machine, in one call: a lent machine has about 15 minutes in
# all, its start included, so this is prepared here and run there once.
#
# Here:   bash ../shared/gpu/pack.sh build .gpu          (see ../shared/gpu/README.md)
# There:  bash scripts/gpu_check.sh --out "$OUT"          (device `run` with carry [".gpu"])
# Try the script itself here with local binaries:
#         scripts/gpu_check.sh --build-dir build --out /tmp/gpu-check --quick
#
# Steps, each under its own time limit (the whole run stays under about 8 minutes):
#   info.txt             janus info (backends, platforms, driver)
#   rhi_tests.txt        janus_rhi_tests, 4 shards in parallel (JANUS_TEST_BACKENDS from run.sh:
#   renderer_tests.txt   vulkan, gl_egl, gles), then janus_renderer_tests the same way
#   forward/             janus bench forward at 1920x1080 (issue 10 items 5 and 6: the cut-off
#                        error table and the per-pass GPU times)
#   bench_rhi.p*.json    janus_bench_rhi in 3 fresh processes of 3 repetitions each (item 4);
#                        bench_rhi.md is their table when python3 is there (else here:
#                        scripts/bench.sh --from-json bench_rhi.p0.json --from-json ...)
#   summary.txt          one line per step: its exit status, time and the suites' totals
# and packs them into OUT/gpu-check.tar.gz (the device returns at most 8 files), with
# summary.txt also beside it.
#
# Options: --out DIR (required), --build-dir DIR (run local binaries instead of .gpu/run.sh),
# --quick (small sizes and short runs: for trying the script, not for numbers).
set -uo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="" build_dir="" quick=0
while [[ $# -gt 0 ]]; do
  case "$1" in
    --out) out="$2"; shift 2 ;;
    --build-dir) build_dir="$(realpath -m "$2")"; shift 2 ;;
    --quick) quick=1; shift ;;
    -h|--help) sed -n '2,25p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "gpu_check.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
  esac
done
[[ -n "$out" ]] || { echo "gpu_check.sh: --out DIR is required" >&2; exit 2; }

# run PROGRAM ARGS...: through the carried loaders and driver setup, or the local build.
run() {
  local program="$1"; shift
  if [[ -z "$build_dir" ]]; then
    bash "$repo_root/.gpu/run.sh" "$program" "$@"
    return
  fi
  case "$program" in
    janus) "$build_dir/apps/janus/janus" "$@" ;;
    janus_bench_rhi) "$build_dir/bench/janus_bench_rhi" "$@" ;;
    *) "$build_dir/tests/$program" "$@" ;;
  esac
}
export -f run   # `timeout` runs it through bash -c
export build_dir repo_root
if [[ -z "$build_dir" && ! -f "$repo_root/.gpu/run.sh" ]]; then
  echo "gpu_check.sh: no .gpu/run.sh: pack a build first (bash ../shared/gpu/pack.sh build .gpu) and carry .gpu" >&2
  exit 2
fi

results="$(mktemp -d)"
trap 'rm -rf "$results"' EXIT
summary="$results/summary.txt"
{
  echo "gpu_check.sh at $(git -C "$repo_root" rev-parse --short HEAD 2>/dev/null || echo '?') on $(hostname), $(date -u +%FT%TZ)"
  command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
} > "$summary"

# step NAME LIMIT_SECONDS PROGRAM ARGS...: `run`s it, output into NAME.txt, a summary line with
# status and time.
step() {
  local name="$1" limit="$2"; shift 2
  local start=$SECONDS status
  timeout --kill-after=10 "$limit" bash -c 'run "$@"' run "$@" > "$results/$name.txt" 2>&1
  status=$?
  local verdict="exit $status"
  [[ $status == 124 || $status == 137 ]] && verdict="TIMED OUT after ${limit} s"
  echo "$name: $verdict, $((SECONDS - start)) s" >> "$summary"
  return $status
}

# A gtest suite in 4 parallel shards; the totals of all shards go to the summary.
sharded_suite() {
  local name="$1" limit="$2" program="$3"
  local shards=4 pids=() i
  for ((i = 0; i < shards; ++i)); do
    GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX=$i \
      step "$name.shard$i" "$limit" "$program" --gtest_brief=1 $([[ $quick == 1 ]] && echo --gtest_filter='*Orientation*:*Clear*') &
    pids+=($!)
  done
  for pid in "${pids[@]}"; do wait "$pid"; done
  cat "$results/$name".shard*.txt > "$results/$name.txt"
  rm -f "$results/$name".shard*.txt
  local passed failed
  passed=$(grep -ho '^\[  PASSED  \] [0-9]*' "$results/$name.txt" | awk '{s += $4} END {print s + 0}')
  failed=$(grep -c '^\[  FAILED  \] .* ms)$' "$results/$name.txt")
  echo "$name: $passed passed, $failed failed (failures: grep FAILED $name.txt)" >> "$summary"
}

step info 60 janus info
sharded_suite rhi_tests 200 janus_rhi_tests
sharded_suite renderer_tests 240 janus_renderer_tests
if [[ $quick == 1 ]]; then
  step forward 120 janus bench forward --quick --out "$results/forward"
  bench_processes=1 bench_options=(--benchmark_filter='vulkan' --benchmark_min_time=0.05)
else
  step forward 150 janus bench forward --size 1920x1080 --out "$results/forward"
  # Three fresh processes: a ratio from one process can be where its driver's heap happened to land.
  bench_processes=3 bench_options=(--benchmark_repetitions=3 --benchmark_enable_random_interleaving=true)
fi
from_json=()
for ((p = 0; p < bench_processes; ++p)); do
  step "bench_rhi.p$p" 60 janus_bench_rhi "${bench_options[@]}" \
    --benchmark_out="$results/bench_rhi.p$p.json" --benchmark_out_format=json
  [[ -s "$results/bench_rhi.p$p.json" ]] && from_json+=(--from-json "$results/bench_rhi.p$p.json")
done
if command -v python3 >/dev/null && [[ ${#from_json[@]} -gt 0 ]]; then
  bash "$repo_root/scripts/bench.sh" "${from_json[@]}" > "$results/bench_rhi.md" 2>&1
fi

mkdir -p "$out"
cp "$summary" "$out/summary.txt"
tar -czf "$out/gpu-check.tar.gz" -C "$results" .
cat "$summary"
