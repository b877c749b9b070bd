#!/usr/bin/env bash
# The shadow map in the CLI (docs/SHADOWS.md): `--debug shadow` shows the main directional light's
# visibility (0..1 in the HDR image; white with a warning where there is no map), and `janus bench
# shadows` measures its error against the Embree reference per map size on every configuration:
# checked for what every row must have and for what must hold physically (a larger map is closer to
# the reference; any map beats none; all configurations see the same visibility).
source "$(dirname "$0")/common.bash" "$@"
HELMET="$REPO_ROOT/../shared/scenes/DamagedHelmet/glTF/DamagedHelmet.gltf"

# pfm_check FILE PYTHON_EXPRESSION DESCRIPTION: the expression, with the PFM's RGB values as the
# list `v`, is true.
pfm_check() {
  local file=$1 expression=$2 description=$3
  if ! python3 - "$file" "$expression" <<'PY' 2>"$TMP/pfm-error"; then
import struct, sys
data = open(sys.argv[1], "rb").read()
header, rest = [], data
for _ in range(3):
    line, rest = rest.split(b"\n", 1)
    header.append(line)
assert header[0] == b"PF", header
w, h = map(int, header[1].split())
v = struct.unpack("<%df" % (w * h * 3), rest[: w * h * 12])
sys.exit(0 if eval(sys.argv[2]) else 1)
PY
    fail "$file: $description ($(cat "$TMP/pfm-error"))"
  fi
}

# --debug shadow: visibility, between 0 and 1, both present on the default scene (spheres shadow the ground).
expect_success render --debug shadow --size 64x64 --out "$TMP/shadow.png" --hdr "$TMP/shadow.pfm"
pfm_check "$TMP/shadow.pfm" 'all(0.0 <= x <= 1.0 for x in v) and v.count(1.0) > len(v) // 4 and sum(x < 0.05 for x in v) > 30' \
  "the shadow view is not a 0..1 visibility with lit and shadowed pixels"
expect_success render --debug shadow --size 64x64 --out "$TMP/plain.png"
expect_success render --size 64x64 --out "$TMP/shaded.png"
cmp -s "$TMP/plain.png" "$TMP/shaded.png" && fail "--debug shadow wrote the shaded image"
expect_success render --debug shadow --no-shadows --size 32x32 --out "$TMP/none.png" --hdr "$TMP/none.pfm"
grep -q "no shadow to show: .*shadows turned off" "$TMP/stderr" || fail "--no-shadows --debug shadow did not warn: $(cat "$TMP/stderr")"
pfm_check "$TMP/none.pfm" 'all(x == 1.0 for x in v)' "without a shadow map the view should be white"

# bench shadows: usage and input errors before any device opens.
expect_error 2 "--sizes '48' must be a comma-separated list of power-of-two integers 16..16384" bench shadows --sizes 48 --out "$TMP/b"
expect_error 2 "--sizes '8,64' must be" bench shadows --sizes 8,64 --out "$TMP/b"
expect_error 2 "--runs 0 must be 1..100" bench shadows --runs 0 --out "$TMP/b"
expect_error 2 "--out DIR is required" bench shadows --quick
expect_error 2 "unknown --path 'warp'" bench shadows --quick --paths compute,warp --out "$TMP/b"
if [[ -f $HELMET ]]; then
  printf '{"gltf": "%s", "defaultLight": false}\n' "$HELMET" >"$TMP/unlit.json"
  expect_error 3 "has no directional light that gives light: there is no shadow map to measure" \
    bench shadows "$TMP/unlit.json" --quick --out "$TMP/b"
else
  fail "the shared DamagedHelmet is missing: $HELMET"
fi

# Nothing can run (gles has no compute path): exit 4 naming why, and no results written.
expect_error 4 "bench shadows: no configuration could run \(gles/compute: no compute\)" \
  bench shadows --quick --backends gles --paths compute --out "$TMP/none"
for file in shadows.md shadows.json shadows.png shadows-reference.png; do
  [[ -e $TMP/none/$file ]] && fail "bench shadows wrote $file though nothing ran"
done

# An --out where a file it would write is the scene it reads is refused before anything is written.
mkdir -p "$TMP/named"
printf '{"gltf": "%s"}\n' "$REPO_ROOT/../shared/scenes/cornell-box/cornellBox.gltf" >"$TMP/named/shadows.json"
cp "$TMP/named/shadows.json" "$TMP/named-before.json"
expect_error 2 "--out '.*/named' would overwrite '.*/named/shadows.json', which is the scene file" \
  bench shadows "$TMP/named/shadows.json" --quick --out "$TMP/named"
cmp -s "$TMP/named/shadows.json" "$TMP/named-before.json" || fail "a refused bench shadows changed its scene file"
[[ -e $TMP/named/shadows-reference.png ]] && fail "a refused bench shadows wrote its reference picture"

# Every configuration, two map sizes.
expect_success bench shadows --quick --backends vulkan,gl,gles --paths compute,fallback --out "$TMP/bench"
for file in shadows.md shadows.json; do
  [[ -s $TMP/bench/$file ]] || fail "bench shadows wrote no $file"
done
check_png "$TMP/bench/shadows.png" 900 560
check_png "$TMP/bench/shadows-reference.png" 64 64
for config in vulkan-compute vulkan-fallback gl-compute gl-fallback gles-fallback; do
  check_png "$TMP/bench/shadows-error-$config.png" 64 64
done
[[ -e $TMP/bench/shadows-error-gles-compute.png ]] && fail "gles/compute has no compute, yet an error picture was written"
B=$TMP/bench/shadows.json
json_check "$B" 'sorted({(c["backend"], c["path"]) for c in j["configurations"]}) == sorted([("vulkan", "compute"),
  ("vulkan", "fallback"), ("gl", "compute"), ("gl", "fallback"), ("gles", "fallback")])' "a configuration is missing"
json_check "$B" 'j["skipped"] == ["gles/compute: no compute"] and j["pictureMapSize"] == 512 and j["sceneMapSize"] == 1024' \
  "skipped or picture size wrong"
json_check "$B" 'all(c["error"]["compared"] == j["comparedPixels"] > 1000 for c in j["configurations"])' \
  "every row compares the same pixels, and enough of them"
json_check "$B" 'all(c["shadowMs"] > 0 and c["forwardMs"] > 0 for c in j["configurations"] if c["mapSize"] > 0)' "a row lacks its times"
json_check "$B" 'all(0 <= c["error"]["wrongFraction"] <= c["error"]["meanAbsolute"] * 2 + 1e-9 and
  abs(c["error"]["wrongFraction"] - c["error"]["leakFraction"] - c["error"]["falseShadowFraction"]) < 1e-9 for c in j["configurations"])' \
  "the error fractions do not add up"
# Physics: the 512 map beats the 64 one, which beats none, on every configuration.
json_check "$B" 'all(next(d for d in j["configurations"] if (d["backend"], d["path"], d["mapSize"]) == (c["backend"], c["path"], 512))["error"]["meanAbsolute"] <
  next(d for d in j["configurations"] if (d["backend"], d["path"], d["mapSize"]) == (c["backend"], c["path"], 64))["error"]["meanAbsolute"] <
  c["error"]["meanAbsolute"] for c in j["configurations"] if c["mapSize"] == 0)' "a larger map is not closer to the reference"
json_check "$B" 'len(j["summary"]) == 5 and all(-1.5 < s["errorSlope"] < -0.5 for s in j["summary"])' \
  "the error should fall about as the texel size (log-log slope near -1)"
json_check "$B" 'next(c for c in j["configurations"] if c["mapSize"] == 512)["error"]["meanAbsolute"] < 0.01' \
  "a 512 map on a 64x64 view should be within 1 % of the reference"
# Parity: every configuration sees the same visibility (same map, same PCF taps), within a few edge pixels.
json_check "$B" 'max(c["error"]["meanAbsolute"] for c in j["configurations"] if c["mapSize"] == 512) -
  min(c["error"]["meanAbsolute"] for c in j["configurations"] if c["mapSize"] == 512) < 0.002' "configurations disagree on the visibility"
grep -q "^## What it says" "$TMP/bench/shadows.md" || fail "shadows.md has no summary"
finish
