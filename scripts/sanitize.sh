#!/usr/bin/env bash
# ASan + UBSan build of the whole project (gcc, its own build folder) and the whole test suite
# under it. Run before each release, not in CI: see docs/TESTING.md ("Fuzzing and sanitizers")
# for why and for the last measured time.
#
#   scripts/sanitize.sh [ctest arguments...]     e.g. scripts/sanitize.sh -R 'Scene|Gltf'
#
# Reports in Mesa's drivers and the Vulkan layers (not our code) are suppressed, narrowly and
# each with its reason, in sanitizers/*.supp; anything else fails the test that triggered it.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${JANUS_SANITIZE_BUILD_DIR:-$root/build-asan}
jobs=${JANUS_JOBS:-$(nproc)}

bash "$root/scripts/setup.sh"
start=$SECONDS
# Benchmarks are not tests and would only add build time.
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DJANUS_SANITIZE=ON -DJANUS_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" --parallel "$jobs"
built=$SECONDS

supp=$root/sanitizers
# verify_asan_link_order=0: lavapipe is preloaded (below) ahead of the ASan runtime.
export ASAN_OPTIONS="detect_leaks=1:verify_asan_link_order=0:suppressions=$supp/asan.supp${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$supp/ubsan.supp${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
# The Vulkan loader unloads lavapipe at vkDestroyInstance; what its globals still pointed to
# (one-time driver state) then looks leaked, from a module LSan can no longer name. Preloaded, the
# driver stays until exit and that memory stays reachable: no suppression needed. The ASan runtime
# itself is not preloaded: the tools tests run (cmake, gcc, python3) would then report their own
# leaks.
lavapipe=$(ls /usr/lib/*/libvulkan_lvp.so 2>/dev/null | head -1)
if [[ -n $lavapipe ]]; then export LD_PRELOAD="$lavapipe${LD_PRELOAD:+ $LD_PRELOAD}"; fi
# The validation layer, which the loader unloads at every vkDestroyInstance, is kept loaded the same
# way through a small preloaded library (sanitizers/keep_vulkan_layers.c), so its module is named.
keep_layers=$build/libjanus_keep_vulkan_layers.so
cc -shared -fPIC -o "$keep_layers" "$supp/keep_vulkan_layers.c" -ldl
export LD_PRELOAD="$keep_layers${LD_PRELOAD:+ $LD_PRELOAD}"
set +e
ctest --test-dir "$build" --output-on-failure --timeout 1800 -j "$jobs" "$@"
rc=$?
set -e
echo "sanitize: build $((built - start)) s, tests $((SECONDS - built)) s, total $((SECONDS - start)) s; ctest exit $rc"
exit $rc
