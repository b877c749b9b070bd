#!/usr/bin/env bash
# `janus bench forward --quick`: every output file, a row per backend/path/count/mode with a
# speed-up against naive, efficiencies in (0, 1], the cut-off error table. Needs the backends.
source "$(dirname "$0")/common.bash" "$@"

expect_error 2 "--modes 'naive,auto': each mode must be naive, tiles-2d or tiles-depth" \
  bench forward --quick --modes naive,auto --out "$TMP/bench"
expect_error 2 "--lights 'x' must be a comma-separated list" bench forward --lights x --out "$TMP/bench"

expect_success bench forward --quick --backends vulkan,gl --out "$TMP/bench"
for file in forward.md forward.json forward.png; do
  [[ -s $TMP/bench/$file ]] || fail "bench forward wrote no $file"
done
grep -q "^| backend | path | lights | mode |" "$TMP/bench/forward.md" || fail "forward.md has no table"
# 2 backends; vulkan and gl both have compute: 2 paths x 2 counts x 3 modes each.
json_check "$TMP/bench/forward.json" 'len(j["rows"]) == 24' "forward.json does not have 24 rows"
json_check "$TMP/bench/forward.json" \
  'all(0 < r["efficiency"]["ratio"] <= 1 for r in j["rows"] if r["lights"] > 0)' "an efficiency is outside (0, 1]"
json_check "$TMP/bench/forward.json" \
  'all(r["speedupVsNaive"] > 0 for r in j["rows"]) and all(r["speedupVsNaive"] == 1 for r in j["rows"] if r["mode"] == "naive")' \
  "speed-ups against naive are missing"
json_check "$TMP/bench/forward.json" 'len(j["cutoffs"]) == 4 and all(c["maxAbsError"] >= 0 for c in j["cutoffs"])' \
  "cut-off error table missing"
check_png "$TMP/bench/forward.png" 900 560
finish
