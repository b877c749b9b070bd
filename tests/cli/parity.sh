#!/usr/bin/env bash
# `janus parity` on the built-in scene at 64x64: all five configurations agree within one step,
# and every image, heat map and parity.json is written. Needs the backends.
source "$(dirname "$0")/common.bash" "$@"

out="$TMP/parity"
expect_success parity --size 64x64 --out "$out" --validation
if [[ $rc != 0 ]]; then cat "$TMP/stdout" >&2; fi

configs=(vulkan-compute vulkan-fallback gl-compute gl-fallback gles-fallback)
for config in "${configs[@]}"; do
  check_png "$out/$config.png" 64 64
done
pairs=0
for ((i = 0; i < ${#configs[@]}; ++i)); do
  for ((k = i + 1; k < ${#configs[@]}; ++k)); do
    check_png "$out/diff-${configs[i]}-vs-${configs[k]}.png" 64 64
    grep -Eq "^  ${configs[i]} vs ${configs[k]} +" "$TMP/stdout" || fail "no table row for ${configs[i]} vs ${configs[k]}"
    pairs=$((pairs + 1))
  done
done
[[ $pairs == 10 ]] || fail "expected 10 pairs, counted $pairs"

json_check "$out/parity.json" 'j["passed"] is True and j["tolerance"] == 1 and j["edgePixels"] == 4 and j["width"] == 64 and j["height"] == 64' "parity.json does not record a pass at 64x64, tolerance 1, 4 edge pixels"
json_check "$out/parity.json" 'len(j["configurations"]) == 5 and all(c["ran"] for c in j["configurations"])' "not every configuration ran"
json_check "$out/parity.json" 'all(c.get("driverSettings", "x") != "" for c in j["configurations"])' "an empty 'driverSettings' was recorded"
json_check "$out/parity.json" 'len(j["pairs"]) == 10 and all(p["compared"] and p["maxChannelDifference"] <= 1 for p in j["pairs"])' "a pair exceeds one step"

# The same renders fail a zero tolerance without edge pixels exactly when some pair differs at all.
run_janus parity --size 64x64 --tolerance 0 --edge-pixels 0 --out "$TMP/strict"
identical=$(python3 -c 'import json,sys; print(int(all(p.get("maxChannelDifference") == 0 for p in json.load(open(sys.argv[1]))["pairs"])))' "$out/parity.json" || echo unknown)
if [[ $identical == unknown ]] || [[ $identical == 1 && $rc != 0 ]] || [[ $identical == 0 && $rc != 1 ]]; then
  fail "parity --tolerance 0 exited $rc although pairs are identical=$identical"
fi

finish
