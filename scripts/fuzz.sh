#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan, own build folder) and runs one of them.
#
#   scripts/fuzz.sh TARGET SECONDS [libFuzzer flags...]     TARGET: gltf | scene_file | image | gi_bake
#
# The corpus is fuzz/corpus/TARGET (small hand-made seeds) plus seeds generated from
# ../shared/scenes into the build folder, where new inputs are kept between runs. Prints the
# executions reached; on a finding (crash, sanitizer report, leak, OOM, timeout) prints it, leaves
# the input in $JANUS_FUZZ_BUILD_DIR/findings/TARGET/ and exits non-zero. Reproduce one with
#   $JANUS_FUZZ_BUILD_DIR/fuzz/janus_fuzz_TARGET path/to/input
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${JANUS_FUZZ_BUILD_DIR:-$root/build-fuzz}
targets=(gltf scene_file image gi_bake)

usage() { echo "usage: scripts/fuzz.sh TARGET SECONDS [libFuzzer flags...]  (TARGET: ${targets[*]})" >&2; exit 2; }
(($# >= 2)) || usage
target=$1 seconds=$2
shift 2
[[ " ${targets[*]} " == *" $target "* ]] || usage
[[ $seconds =~ ^[0-9]+$ ]] || usage

bash "$root/scripts/setup.sh" --fuzz
if [[ ! -f $build/CMakeCache.txt ]]; then
  # Tests and benchmarks are not built here; only the fuzz targets and the loader they link.
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DJANUS_FUZZ=ON -DJANUS_BUILD_TESTS=OFF -DJANUS_BUILD_BENCH=OFF >/dev/null
fi
cmake --build "$build" --parallel "${JANUS_JOBS:-$(nproc)}" --target "janus_fuzz_$target" janus_fuzz_seeds

corpus=$build/corpus/$target
seeds=$build/seeds
if [[ ! -d $seeds/$target ]]; then   # made once; again when a target has none yet
  shared=$root/../shared/scenes
  [[ -d $shared ]] || { echo "fuzz: $shared is missing; fuzzing with the committed seeds only" >&2; shared=$root/fuzz/corpus; }
  "$build/fuzz/janus_fuzz_seeds" "$shared" "$root/tests/renderer/data" "$seeds"
fi
mkdir -p "$corpus" "$build/findings/$target"
# A symbolizer turns report addresses into file:line (Debian's llvm keeps it out of PATH).
for s in llvm-symbolizer /usr/lib/llvm-*/bin/llvm-symbolizer; do
  if command -v "$s" >/dev/null; then export ASAN_SYMBOLIZER_PATH=$(command -v "$s"); break; fi
done
# -rss_limit_mb / -timeout: an input that makes the loader take over 2 GiB or 10 s is a finding.
# detect_leaks stays on: the loader must not leak on any error path. -close_fd_mask=3 silences
# the loader's warnings (unknown extensions...); libFuzzer and sanitizer reports still print.
log=$build/findings/$target/last-run.log
dict=$root/fuzz/$target.dict
[[ -f $dict ]] || dict=
set +e
ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1} UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1} \
  "$build/fuzz/janus_fuzz_$target" "$corpus" "$seeds/$target" "$root/fuzz/corpus/$target" \
  ${dict:+-dict="$dict"} -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 \
  -artifact_prefix="$build/findings/$target/" -print_final_stats=1 -close_fd_mask=3 "$@" 2>&1 | tee "$log" |
  grep --line-buffered -v '^\(#[0-9]*[[:space:]]*\(NEW\|REDUCE\|pulse\)\|[[:space:]]NEW_FUNC\)'
rc=${PIPESTATUS[0]}
set -e
execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
echo "fuzz: $target ran ${seconds}s: ${execs:-?} executions (${rate:-?}/s), corpus $(ls "$corpus" | wc -l) new inputs in $corpus"
if ((rc != 0)); then
  echo "fuzz: FINDING in $target (exit $rc); input and log in $build/findings/$target/" >&2
  exit 1
fi
