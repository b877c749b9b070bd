#!/usr/bin/env bash
# `janus parity --against DIR`: each configuration compared with another run's image of the same
# configuration (a run on another machine; here, on this one): identical renders pass, a changed
# image fails naming its configuration unless --against-tolerance allows the change, and a
# directory that is no parity run, or of another size, is a clear error. Needs the backends.
source "$(dirname "$0")/common.bash" "$@"

expect_success parity --size 32x32 --out "$TMP/machine-a"
expect_success parity --size 32x32 --out "$TMP/machine-b" --against "$TMP/machine-a"
grep -q "against $TMP/machine-a (tolerance 1 step(s))" "$TMP/stdout" || fail "no against table: $(cat "$TMP/stdout")"
json_check "$TMP/machine-b/parity.json" 'j["against"]["tolerance"] == 1 and len(j["against"]["configurations"]) == 5 and all(c["compared"] and c["passed"] for c in j["against"]["configurations"])' "the same machine's renders do not all match"
check_png "$TMP/machine-b/against-gl-fallback.png" 32 32

# A driver that draws one region 20 steps brighter in gl-fallback's image.
python3 - "$TMP/machine-a/gl-fallback.png" "$CLI_DIR" <<'PY'
import sys
sys.path.insert(0, sys.argv[2])
from pngio import read_png, write_png
w, h, rows = read_png(sys.argv[1])
for y in range(4, 8):
    for x in range(4 * 4, 8 * 4):
        if x % 4 != 3: rows[y][x] = min(255, rows[y][x] + 20)
write_png(sys.argv[1], w, h, rows)
PY
run_janus parity --size 32x32 --out "$TMP/machine-c" --against "$TMP/machine-a"
[[ $rc == 1 ]] || fail "a changed image in --against must fail parity (exit 1), got $rc"
grep -Eq "^  gl-fallback +20 .*FAIL" "$TMP/stdout" || fail "the against table does not fail gl-fallback by 20 steps: $(cat "$TMP/stdout")"
json_check "$TMP/machine-c/parity.json" '[c["configuration"] for c in j["against"]["configurations"] if not c["passed"]] == ["gl-fallback"] and j["passed"] is False' "only gl-fallback must fail against machine-a"
expect_success parity --size 32x32 --out "$TMP/machine-d" --against "$TMP/machine-a" --against-tolerance 20
grep -q "warning" "$TMP/stderr" && fail "runs with the same settings should compare without a warning: $(cat "$TMP/stderr")"
# Another sample count than the other run's changes every edge: said before the comparison fails.
run_janus parity --size 32x32 --msaa 4 --out "$TMP/machine-msaa" --against "$TMP/machine-b"
grep -q "warning: --against: .*machine-b rendered with msaaSamples 1, this run with 4" "$TMP/stderr" ||
  fail "--against with another --msaa should warn: $(cat "$TMP/stderr")"
json_check "$TMP/machine-msaa/parity.json" 'j["msaaSamples"] == 4 and j["probeCaptureSamples"] == []' "parity.json should record the samples (and no probe captures)"

# An image the other run lists as rendered but that is missing is an input error naming it, not
# "not in --against".
rm "$TMP/machine-a/gles-fallback.png"
expect_error 3 "--against: .*parity.json lists gles-fallback.png as rendered, but '.*/machine-a/gles-fallback.png' is missing" \
  parity --size 32x32 --out "$TMP/machine-e" --against "$TMP/machine-a" --against-tolerance 20
# Configurations the other machine did not render (not "ran" in its parity.json) are said, not failed.
python3 - "$TMP/machine-a/parity.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
for c in j["configurations"]:
    if (c["backend"], c["path"]) == ("gles", "fallback"):
        c["ran"] = False
        c["error"] = "not on that machine"
        del c["image"]
json.dump(j, open(sys.argv[1], "w"))
PY
expect_success parity --size 32x32 --out "$TMP/machine-e" --against "$TMP/machine-a" --against-tolerance 20
grep -Eq "^  gles-fallback +- +- +- +not in --against" "$TMP/stdout" || fail "a missing image is not reported: $(cat "$TMP/stdout")"

# --against-tolerance is checked and named as itself, and needs --against.
expect_error 2 "^janus: error: --against-tolerance '300' is not a whole number" \
  parity --size 32x32 --out "$TMP/x" --against "$TMP/machine-a" --against-tolerance 300
expect_error 2 "--against-tolerance applies to --against DIR, which is not given" parity --size 32x32 --out "$TMP/x" --against-tolerance 5

# A second run into the same --out that cannot run some configurations leaves none of the first
# run's images behind (here: OSMesa has no GLES, so gles-fallback does not run).
run_janus parity --size 32x32 --out "$TMP/machine-e" --gl-platform osmesa
[[ $rc == 1 ]] || fail "parity under OSMesa without gles: exit $rc, expected 1"
[[ -e $TMP/machine-e/gles-fallback.png || -e $TMP/machine-e/diff-gl-fallback-vs-gles-fallback.png || -e $TMP/machine-e/against-vulkan-compute.png ]] &&
  fail "a stale image of the previous run is left in --out: $(ls "$TMP/machine-e")"
check_png "$TMP/machine-e/gl-fallback.png" 32 32

expect_error 3 "--against '.*nowhere' is not a directory" parity --size 32x32 --out "$TMP/x" --against "$TMP/nowhere"
mkdir -p "$TMP/empty"
expect_error 3 "--against '.*empty' has no parity.json" parity --size 32x32 --out "$TMP/x" --against "$TMP/empty"
expect_error 3 "--against: .*parity.json was rendered at 32x32, this run at 24x24; use the same --size" parity --size 24x24 --out "$TMP/x" --against "$TMP/machine-a"
expect_error 2 "--against and --out are the same directory" parity --size 32x32 --out "$TMP/machine-a" --against "$TMP/machine-a"

finish
