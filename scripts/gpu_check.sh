#!/usr/bin/env bash
# Everything issue 10 asks of a GPU machine, in one call: a lent machine has about 15 minutes in
# all, its start included, so this is prepared here and run there once.
#
# Here:   bash scripts/gpu_pack.sh build                 (../shared/gpu/pack.sh, retried, into
#                                                         .gpu-pack: .gpu is over the device's 64 MiB)
# There:  bash scripts/gpu_check.sh --out "$OUT"          (device `run` with carry [".gpu-pack"])
# Try the script itself here with local binaries:
#         scripts/gpu_check.sh --build-dir build --out /tmp/gpu-check --quick
#
# Steps, each under its own time limit (the whole run stays under about 8 minutes):
#   info.txt             janus info (backends, platforms, driver)
#   rhi_tests.txt        janus_rhi_tests, 4 shards per backend in parallel, one backend per process
#   renderer_tests.txt   (vulkan, gl_egl, gles), then janus_renderer_tests in 4 shards running all
#                        three (JANUS_TEST_BACKENDS from run.sh); a crashed
#                        shard's last test is named in the summary; renderer_tests_images/ holds
#                        the images failing renderer tests wrote
#   forward/             janus bench forward at 1920x1080 (issue 10 items 5 and 6: the cut-off
#                        error table and the per-pass GPU times)
#   shadows/             janus bench shadows at 1920x1080, maps 1024 to 8192 on each backend (fallback path)
#   gi/                  janus bench gi on the cornell box (docs/GI.md, "Goals"): bricks against
#                        per-surfel, the parallel SH reduction against the serial sum, and the grid
#                        density, whose times llvmpipe cannot judge
#   gi_rooms/            janus bench gi on the built-in gi-rooms scene, visibility test on and off
#   parity_helmet/      janus parity of DamagedHelmet at 512x512 (cross-driver: --against it here)
#   parity_helmet_sky/  the same under the sky at 128x128: the two-compiler parity rule on hardware
#   parity_msaa/         janus parity of the default scene at 512x512 with --msaa 4: the driver's
#                        resolve (Vulkan's resolve attachment, GL's blit) on all five, and in
#                        parity.json each configuration's msaa-resolve and forward GPU ms
#   msaa/                janus bench msaa at 960x540 (fallback path): error against a 4x4-supersampled
#                        reference and frame GPU ms for 1, 2, 4, 8 samples and 2x2 supersampling
#   msaa_probes/         janus bench msaa of the built-in probes scene (fallback path): its two reflection
#                        probes' captures with 1, 2, 4, 8 samples against 4x4-supersampled captures
#   gl_only/             DamagedHelmet at 256x256 in the GL configurations alone, one process that
#   gl_only_against/     starts no Vulkan, and all five --against them at tolerance 0: GL alone must
#                        draw as GL after Vulkan
#   hello_rhi_*.txt      examples/hello_rhi on each backend and path with validation on (a user's
#   render_scene/        program on a real driver), and examples/render_scene: vulkan/compute
#                        against gl/compute by the parity rule (two compilers: rounding allowed)
#   bench_renderer.{json,txt}  janus_bench_renderer: the renderer's recording ns per mesh draw
#                        (shadow map, prepass, forward; 1024 boxes), 3 repetitions per configuration
#   bench_rhi_footprint.{json,md}  the null-driver rows with JANUS_BENCH_NULL_FOOTPRINT=128, and
#   bench_rhi_footprint2048.{json,md}  with 2048 (a frame's writes evict the second-level cache)
#   bench_rhi.p*.json    janus_bench_rhi in 10 fresh processes of 5 interleaved repetitions each (item 4;
#                        the paired runs included); bench_rhi.md is their tables when python3 is there (else here:
#                        scripts/bench.sh --from-json bench_rhi.p0.json --from-json ...); a
#                        process's "exit 3": some of its runs failed, which the table names
#   bench_rhi_validated.{json,md}  the main pairs for 20 frames with JANUS_BENCH_VALIDATE=1: every side
#                        checked by the driver's debug output / the validation layer, and the
#                        driver's performance messages in each side's frames counted (a driver
#                        recompiling or moving something every frame would say so there)
#   bench_rhi_frames100.json  the main pairs in frames of 100 operations (--janus_ops_per_frame),
#                        so that bench_rhi.md also splits each side into per frame and per
#                        operation; with --bench-only every sixth process runs so instead
#   cpu.txt              lscpu, which logical CPUs share a core, and each CPU's clock, at the start
#                        and at the end (the benchmark's runs name the CPU they ran on)
#   summary.txt          one line per step: its exit status, time and the suites' totals
# and packs them into OUT/gpu-check.tar.gz (the device returns at most 8 files), with
# summary.txt also beside it.
#
# The archive is rewritten after every step, so a run cut off by the device's time limit still
# returns what it finished; --budget (seconds, default 480) shortens the last steps' limits so
# that the whole run ends inside it.
#
# Options: --out DIR (required), --build-dir DIR (run local binaries instead of .gpu/run.sh),
# --budget SECONDS, --quick (small sizes and short runs: for trying the script, not for numbers),
# --tests-only (info and the two suites: to check fixes when little device time is left),
# --bench-only (info, the footprint steps and as many janus_bench_rhi processes as the budget holds,
# each of the main pairs, their paired runs and the null-driver rows only, about 10 s with the draw_dynamic rows: for a verdict
# on the overhead ratios, whose spread between processes is wide).
set -uo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="" build_dir="" quick=0 budget=480 tests_only=0 bench_only=0
while [[ $# -gt 0 ]]; do
  case "$1" in
    --out) out="$2"; shift 2 ;;
    --build-dir) build_dir="$(realpath -m "$2")"; shift 2 ;;
    --quick) quick=1; shift ;;
    --budget) budget="$2"; shift 2 ;;
    --tests-only) tests_only=1; shift ;;
    --bench-only) bench_only=1; shift ;;
    -h|--help) sed -n '2,/^set /{/^#/p}' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
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
    janus_bench_renderer) "$build_dir/bench/janus_bench_renderer" "$@" ;;
    hello_rhi|render_scene) "$build_dir/examples/$program/$program" "$@" ;;
    *) "$build_dir/tests/$program" "$@" ;;
  esac
}
export -f run   # `timeout` runs it through bash -c
export build_dir repo_root
# .gpu is over the device's 64 MiB with Embree: it travels as .gpu-pack/gpu.tar.gz
# (scripts/gpu_pack.sh here, carry [".gpu-pack"]) and is unpacked here, always: a warm machine
# keeps the last call's ignored folders, so a .gpu already there may be an older build.
if [[ -z "$build_dir" && -f "$repo_root/.gpu-pack/gpu.tar.gz" ]]; then
  rm -rf "$repo_root/.gpu"
  tar -xzf "$repo_root/.gpu-pack/gpu.tar.gz" -C "$repo_root"
fi
if [[ -z "$build_dir" && ! -f "$repo_root/.gpu/run.sh" ]]; then
  echo "gpu_check.sh: no .gpu/run.sh: pack a build first (bash scripts/gpu_pack.sh build, then carry .gpu-pack)" >&2
  exit 2
fi

results="$(mktemp -d)"
mkdir -p "$out"
trap 'rm -rf "$results"' EXIT
summary="$results/summary.txt"
{
  # The device's copy of .git can lag behind the tree it was sent with: the commit the build was
  # packed at is in .gpu-pack/commit when written there (docs/TESTING.md, "On a GPU machine").
  # Local binaries (--build-dir) are the tree's, whatever an old pack says.
  commit=""
  [[ -z "$build_dir" ]] && commit=$(cat "$repo_root/.gpu-pack/commit" 2>/dev/null)
  [[ -n "$commit" ]] || commit=$(git -C "$repo_root" rev-parse --short HEAD 2>/dev/null || echo '?')
  echo "gpu_check.sh, build of $commit, on $(hostname), $(date -u +%FT%TZ)"
  command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
} > "$summary"
# The CPU the timings run on: its model, which logical CPUs share a core, and the clock of each
# (again at the end). The H200 machine's CPU ran the same code at two speeds 1.5x apart from run
# to run (docs/BENCHMARKS.md, session 25); janus_bench_rhi's runs say which CPU they ran on.
cpu_report() {
  echo "== $1"
  lscpu 2>/dev/null
  grep -H . /sys/devices/system/cpu/cpu*/topology/thread_siblings_list 2>/dev/null
  grep "MHz" /proc/cpuinfo 2>/dev/null
}
cpu_report "at the start" > "$results/cpu.txt"

# What has finished so far, into OUT: the device returns OUT even when its time limit ends the run.
publish() {
  cp "$summary" "$out/summary.txt.$BASHPID" && mv "$out/summary.txt.$BASHPID" "$out/summary.txt"
  # Shards still running write into their suite's .tmp folder: left out. (tar exits 1 when a file
  # changed while read; the archive is still whole.)
  tar -czf "$out/gpu-check.tar.gz.$BASHPID" --exclude='./*.tmp' -C "$results" . 2>/dev/null
  [[ -s "$out/gpu-check.tar.gz.$BASHPID" ]] && mv "$out/gpu-check.tar.gz.$BASHPID" "$out/gpu-check.tar.gz"
  rm -f "$out/gpu-check.tar.gz.$BASHPID"
}

# step NAME LIMIT_SECONDS PROGRAM ARGS...: `run`s it, output into NAME.txt, a summary line with
# status and time. The limit shrinks to what is left of the budget; a step with under 10 s left
# is skipped.
step() {
  local name="$1" limit="$2"; shift 2
  local start=$SECONDS status left=$((budget - SECONDS))
  if ((left < 10)); then echo "$name: skipped (budget of $budget s spent)" >> "$summary"; return 124; fi
  ((limit > left)) && limit=$left
  timeout --kill-after=10 "$limit" bash -c 'run "$@"' run "$@" > "$results/$name.txt" 2>&1
  status=$?
  local verdict="exit $status"
  [[ $status == 124 || $status == 137 ]] && verdict="TIMED OUT after ${limit} s"
  echo "$name: $verdict, $((SECONDS - start)) s" >> "$summary"
  publish
  return $status
}

# A gtest suite in 4 parallel shards; the totals of all shards go to the summary. The full
# output is kept (not --gtest_brief): its "[ RUN      ]" lines are flushed before each test, so a
# shard that crashes names the test it crashed in. Images the renderer tests write on a failure
# (under $TMPDIR/janus-renderer-tests) come back in NAME_images/.
# per_backend=1: 4 shards for each backend, each process with that backend alone. A driver can
# behave differently when another API's driver started first in the process: NVIDIA's GL lost
# buffer contents only where its Vulkan driver had not started (session 19), which processes
# running every backend in turn hid.
sharded_suite() {
  local name="$1" limit="$2" program="$3" per_backend="${4:-0}"
  local shards=4 pids=() i shard_names=() backends=("") backend
  [[ $per_backend == 1 ]] && IFS=, read -ra backends <<< "${JANUS_TEST_BACKENDS:-vulkan,gl_egl,gles}"
  local tmp="$results/$name.tmp"
  mkdir -p "$tmp"
  local filter='*'
  [[ $quick == 1 ]] && filter='*Orientation*:*Clear*'
  for backend in "${backends[@]}"; do
    for ((i = 0; i < shards; ++i)); do
      local shard="$name${backend:+.$backend}.shard$i"
      shard_names+=("$shard")
      # JANUS_TEST_BACKENDS as the environment has it (run.sh's default) unless one per process;
      # the tests that are not per backend (not Backends/...) run with the first backend only.
      local shard_filter="$filter"
      [[ -n $backend && $backend != "${backends[0]}" ]] && shard_filter="Backends/${filter//:/:Backends/}"
      ( [[ -n $backend ]] && export JANUS_TEST_BACKENDS=$backend
        TMPDIR="$tmp" GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX=$i \
          step "$shard" "$limit" "$program" --gtest_filter="$shard_filter" ) &
      pids+=($!)
    done
  done
  for pid in "${pids[@]}"; do wait "$pid"; done
  for shard in "${shard_names[@]}"; do
    # A shard that ended without its summary line crashed (or timed out) in its last test started.
    if ! grep -q '^\[==========\] .* ran\.' "$results/$shard.txt"; then
      echo "$shard: ended in $(grep '^\[ RUN      \]' "$results/$shard.txt" | tail -1 | cut -c14-)" >> "$summary"
    fi
  done
  for shard in "${shard_names[@]}"; do cat "$results/$shard.txt"; done > "$results/$name.txt"
  for shard in "${shard_names[@]}"; do rm -f "$results/$shard.txt"; done
  [[ -d "$tmp/janus-renderer-tests" ]] && mv "$tmp/janus-renderer-tests" "$results/${name}_images"
  rm -rf "$tmp"
  local passed failed
  passed=$(grep -ho '^\[  PASSED  \] [0-9]*' "$results/$name.txt" | awk '{s += $4} END {print s + 0}')
  failed=$(grep -c '^\[  FAILED  \] .* ms)$' "$results/$name.txt")
  echo "$name: $passed passed, $failed failed (failures: grep FAILED $name.txt)" >> "$summary"
  publish
}

step info 60 janus info
if [[ $bench_only == 0 ]]; then
  sharded_suite rhi_tests 200 janus_rhi_tests 1
  sharded_suite renderer_tests 240 janus_renderer_tests
fi
if [[ $tests_only == 1 ]]; then
  publish
  cat "$summary"
  exit 0
fi
if [[ $quick == 1 ]]; then
  bench_processes=1 bench_options=(--benchmark_filter='vulkan' --benchmark_min_time=0.05)
  gl_only_scene=(--size 32x32)
else
  # Ten fresh processes (about 12 s each): on the H200 one process's ratio ranged from 1.06x to
  # 1.71x for the same binary (0.99x to 1.88x for Vulkan draws in session 19), on the H100 from
  # 0.88x to 1.57x (docs/BENCHMARKS.md, "On hardware"), so only a median over many means
  # anything. Within each, five repetitions of 200 frames per benchmark in random order
  # (bench.sh --interleave): raw and RHI share the same seconds of the machine.
  bench_processes=10 bench_options=(--benchmark_repetitions=5 --janus_frames=200 --benchmark_enable_random_interleaving=true)
  gl_only_scene=("$repo_root/../shared/scenes/DamagedHelmet/glTF/DamagedHelmet.gltf" --size 256x256)
fi
if [[ $bench_only == 1 ]]; then
  # Until the budget is spent (the loop below stops 25 s before it). The main pairs, their paired
  # runs and the null-driver rows only: the table's verdict needs processes more than the
  # explanatory rows (which a full run's processes give), and without those rows a process takes
  # about a third less time.
  bench_processes=$((quick == 1 ? 2 : 100))
  ((quick == 1)) || bench_options+=(--benchmark_filter='/(raw|rhi|paired|raw_null_driver|rhi_null_driver)/')
elif [[ $quick == 1 ]]; then
  step forward 120 janus bench forward --quick --out "$results/forward"
  step gi 60 janus bench gi "$repo_root/../shared/scenes/cornell-box/cornellBox.gltf" --quick --out "$results/gi"
else
  step forward 150 janus bench forward --size 1920x1080 --out "$results/forward"
  # The shadow map's accuracy vs time on hardware (docs/SHADOWS.md): llvmpipe rasterises the map on
  # the CPU, so where the pass's cost turns from overhead to texels is a GPU's to say.
  step shadows 60 janus bench shadows --size 1920x1080 --paths fallback --sizes 1024,2048,4096,8192 --out "$results/shadows"
  # Probe GI's goals that a CPU "GPU" cannot settle (docs/GI.md, "Goals"): a workgroup's
  # reduction against a serial sum, and bricks against per-surfel, in GPU time.
  step gi 90 janus bench gi "$repo_root/../shared/scenes/cornell-box/cornellBox.gltf" --sweeps surfels,bricks,reduction,spacing \
    --backends vulkan,gl --runs 5 --out "$results/gi"
  # The visibility test's worth where light can leak through a wall, and its cost, on hardware.
  step gi_rooms 45 janus bench gi gi-rooms --sweeps visibility --backends vulkan,gl --runs 5 --out "$results/gi_rooms"
  # Images for a cross-driver comparison here: janus parity ... --against parity_helmet
  step parity_helmet 60 janus parity "$repo_root/../shared/scenes/DamagedHelmet/glTF/DamagedHelmet.gltf" \
    --size 512x512 --out "$results/parity_helmet"
  # The scene whose gl-vs-vulkan rounding set the two-compiler parity rule (janus/renderer/parity.h):
  # parity.json's pairs say which needed it (twoCompilers, roundingPixels).
  step parity_helmet_sky 60 janus parity "$repo_root/../shared/scenes/DamagedHelmet/glTF/DamagedHelmet.gltf" \
    --env "$repo_root/../shared/scenes/env/chinese_garden_1k.hdr" --size 128x128 --out "$results/parity_helmet_sky"
  # Multisampling on a real driver (docs/LIGHTING.md, "Anti-aliasing"): the five agree, and what the
  # resolve costs where hardware does it (llvmpipe, steady: 0.7 ms at 256x256; this is a first frame).
  step parity_msaa 60 janus parity --size 512x512 --msaa 4 --out "$results/parity_msaa"
  # Anti-aliasing's accuracy vs time where the samples are hardware's: 2 and 8 samples too (llvmpipe
  # has 1 and 4 only), the frame's cost per count, against a 4x4-supersampled reference.
  step msaa 45 janus bench msaa --size 960x540 --runs 3 --paths fallback --out "$results/msaa"
  # Multisampled reflection-probe captures (docs/PROBES.md): their error per count and what they cost an update.
  step msaa_probes 40 janus bench msaa probes --runs 3 --paths fallback --supersample none --out "$results/msaa_probes"
fi
if [[ $bench_only == 0 ]]; then
  # GL in a process that never starts Vulkan (NVIDIA's GL lost buffer contents only there, session
  # 19; the renderer suite and the parity steps start Vulkan first): the GL configurations alone,
  # then all five against them, which must match exactly on one driver.
  step gl_only 60 janus parity "${gl_only_scene[@]}" --configs gl/compute,gl/fallback,gles/fallback --out "$results/gl_only"
  step gl_only_against 60 janus parity "${gl_only_scene[@]}" --out "$results/gl_only_against" --against "$results/gl_only" \
    --against-tolerance 0
fi
if [[ $bench_only == 0 ]]; then
  # The examples as a user runs them (docs/RHI.md): a real driver rejects what Mesa forgives.
  for configuration in vulkan/compute vulkan/fallback gl/compute gl/fallback gles/fallback; do
    step "hello_rhi_${configuration/\//_}" 30 hello_rhi --backend "${configuration%/*}" --path "${configuration#*/}" --validation
  done
  step render_scene 60 render_scene --a vulkan/compute --b gl/compute --size 128 --out "$results/render_scene"
fi
# The renderer's own recording cost per mesh draw on this driver (docs/BENCHMARKS.md, "Renderer").
step bench_renderer 60 janus_bench_renderer --benchmark_repetitions=$((quick == 1 ? 1 : 3)) \
  --janus_frames=$((quick == 1 ? 2 : 30)) --benchmark_out="$results/bench_renderer.json" --benchmark_out_format=json
# The null-driver rows again, each stub also writing a push buffer's worth per call
# (JANUS_BENCH_NULL_FOOTPRINT, 128 bytes: 256 per draw): if the RHI's own ns per draw grow with it
# on that CPU, the driver's cache traffic is part of what the RHI costs there (it did not here;
# docs/BENCHMARKS.md, session 21). Before the processes below, which take what is left.
# 2048 bytes (4 MiB per frame of 1000 draws) evicts the second-level cache every frame, as a driver
# whose per-frame data outgrows it would: the RHI's sets and commands then come from the third
# level (here, on an AMD core, its own ns grew by about 2 per GL draw; session 23).
if ((quick == 0)); then
  for footprint in 128 2048; do
    name=bench_rhi_footprint$([[ $footprint == 128 ]] || echo "$footprint")
    JANUS_BENCH_NULL_FOOTPRINT=$footprint step "$name" 60 janus_bench_rhi --benchmark_filter=null_driver \
      "${bench_options[@]}" --benchmark_out="$results/$name.json" --benchmark_out_format=json
    if command -v python3 >/dev/null && [[ -s "$results/$name.json" ]]; then
      bash "$repo_root/scripts/bench.sh" --from-json "$results/$name.json" > "$results/$name.md" 2>&1
    fi
  done
fi
# The benchmark under validation (timings meaningless): the sides draw without a driver error, and
# bench_rhi_validated.md lists the driver's performance messages in each side's frames.
if ((bench_only == 0)); then
  JANUS_BENCH_VALIDATE=1 step bench_rhi_validated 60 janus_bench_rhi --benchmark_filter='/(raw|rhi)/' \
    --janus_frames=$((quick == 1 ? 2 : 20)) --benchmark_out="$results/bench_rhi_validated.json" --benchmark_out_format=json
  if command -v python3 >/dev/null && [[ -s "$results/bench_rhi_validated.json" ]]; then
    bash "$repo_root/scripts/bench.sh" --from-json "$results/bench_rhi_validated.json" > "$results/bench_rhi_validated.md" 2>&1
  fi
fi
# Frames of 100 operations beside the 1000 of the processes below: a cost paid once per frame (for
# the RHI also execute()'s setup, and e.g. GL's glUseProgram(0) after each list) weighs ten times
# more there, so bench.sh splits per frame from per draw and gives RHI/raw of the per-draw part
# alone. The main pairs only; 1000 frames, so a repetition times as many draws as one of 200.
frames_options=(--benchmark_filter='/(raw|rhi)/' --janus_ops_per_frame=100)
if ((quick == 1)); then
  frames_options+=(--janus_frames=5)
else
  frames_options+=(--benchmark_repetitions=5 --janus_frames=1000 --benchmark_enable_random_interleaving=true)
fi
from_json=()
if ((bench_only == 0)); then
  step bench_rhi_frames100 60 janus_bench_rhi "${frames_options[@]}" \
    --benchmark_out="$results/bench_rhi_frames100.json" --benchmark_out_format=json
  [[ -s "$results/bench_rhi_frames100.json" ]] && from_json+=(--from-json "$results/bench_rhi_frames100.json")
fi
for ((p = 0; p < bench_processes; ++p)); do
  ((bench_only == 0 || budget - SECONDS >= 25)) || break
  options=("${bench_options[@]}")
  ((bench_only == 1 && p % 6 == 5)) && options=("${frames_options[@]}")
  step "bench_rhi.p$p" 60 janus_bench_rhi "${options[@]}" \
    --benchmark_out="$results/bench_rhi.p$p.json" --benchmark_out_format=json
  [[ -s "$results/bench_rhi.p$p.json" ]] && from_json+=(--from-json "$results/bench_rhi.p$p.json")
done
if command -v python3 >/dev/null && [[ ${#from_json[@]} -gt 0 ]]; then
  bash "$repo_root/scripts/bench.sh" "${from_json[@]}" > "$results/bench_rhi.md" 2>&1
fi
cpu_report "at the end" >> "$results/cpu.txt"
publish
cat "$summary"
