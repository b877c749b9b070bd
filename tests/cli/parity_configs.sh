#!/usr/bin/env bash
# `janus parity --configs LIST`: only the configurations named are rendered and compared, in this
# process alone (a GL-only process starts no Vulkan driver, which on NVIDIA's drivers is not the
# same as GL after Vulkan: docs/ARCHITECTURE.md, "Driver traits worked around"); a full run then
# compares its images with them through --against. Needs the backends.
source "$(dirname "$0")/common.bash" "$@"

out="$TMP/gl-only"
expect_success parity --size 32x32 --configs gl/compute,gl-fallback,gles/fallback --out "$out"
for config in gl-compute gl-fallback gles-fallback; do check_png "$out/$config.png" 32 32; done
for config in vulkan-compute vulkan-fallback; do
  [[ ! -e "$out/$config.png" ]] || fail "--configs without $config rendered it"
done
check_png "$out/diff-gl-compute-vs-gles-fallback.png" 32 32
json_check "$out/parity.json" 'j["passed"] is True and j["selectedConfigurations"] == ["gl-compute", "gl-fallback", "gles-fallback"] and len(j["configurations"]) == 3 and len(j["pairs"]) == 3' "parity.json does not describe the three GL configurations and their three pairs"

# One configuration: nothing to compare, and that is said.
expect_success parity --size 32x32 --configs gles/fallback --out "$TMP/one"
grep -q "one configuration: no pairs to compare" "$TMP/stdout" || fail "a single configuration does not say it has no pairs: $(cat "$TMP/stdout")"

# All five, against the GL-only images: the same driver in another process draws the same.
expect_success parity --size 32x32 --out "$TMP/all" --against "$out" --against-tolerance 0
json_check "$TMP/all/parity.json" 'sorted(c["configuration"] for c in j["against"]["configurations"] if c["compared"] and c["passed"]) == ["gl-compute", "gl-fallback", "gles-fallback"]' "the GL configurations do not match their GL-only images exactly"

expect_error 2 "--configs: 'metal' is not a configuration; the configurations are vulkan/compute, vulkan/fallback, gl/compute, gl/fallback, gles/fallback" \
  parity --size 32x32 --configs gl/compute,metal --out "$TMP/bad"
expect_error 2 "--configs 'gl/compute,' has an empty item" parity --size 32x32 --configs gl/compute, --out "$TMP/bad"
expect_error 2 "--configs '' has an empty item" parity --size 32x32 --configs "" --out "$TMP/bad"
[[ ! -e "$TMP/bad" ]] || fail "a refused --configs created its --out directory"

finish
