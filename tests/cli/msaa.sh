#!/usr/bin/env bash
# `janus bench msaa` (docs/LIGHTING.md, "Anti-aliasing"): multisampling and supersampling measured
# against a supersampled reference on every configuration, checked for what every row must have
# and for what must hold: more samples are closer to the reference, every configuration sees the
# same error, the one-sample row is always there, a count the device lacks is skipped, not fatal.
source "$(dirname "$0")/common.bash" "$@"

# Usage and input errors before any device opens.
expect_error 2 "--samples '3' must be a comma-separated list of power-of-two integers 1..16" bench msaa --samples 3 --out "$TMP/b"
expect_error 2 "--samples '4,32' must be" bench msaa --samples 4,32 --out "$TMP/b"
expect_error 2 "--reference-scale 1 must be 2..8" bench msaa --reference-scale 1 --out "$TMP/b"
expect_error 2 "--supersample 4 must stay below --reference-scale 4" bench msaa --supersample 2,4 --out "$TMP/b"
expect_error 2 "--supersample '1' must be a comma-separated list of integers 2..8" bench msaa --supersample 1 --out "$TMP/b"
expect_error 2 "--runs 0 must be 1..100" bench msaa --runs 0 --out "$TMP/b"
expect_error 2 "--out DIR is required" bench msaa --quick
expect_error 2 "unknown --path 'warp'" bench msaa --quick --paths warp --out "$TMP/b"
expect_error 3 "no-such-scene.gltf" bench msaa "$TMP/no-such-scene.gltf" --quick --out "$TMP/b"

# Nothing can run (gles has no compute path): exit 4 naming why, and no results written.
expect_error 4 "bench msaa: no configuration could run \(gles/compute: no compute\)" \
  bench msaa --quick --backends gles --paths compute --out "$TMP/none"
for file in msaa.md msaa.json msaa.png; do
  [[ -e $TMP/none/$file ]] && fail "bench msaa wrote $file though nothing ran"
done

# Every configuration: one sample, 4 samples, supersampled 2x2, against a 4x4 reference.
expect_success bench msaa --quick --backends vulkan,gl,gles --paths compute,fallback --out "$TMP/bench"
for file in msaa.md msaa.json; do
  [[ -s $TMP/bench/$file ]] || fail "bench msaa wrote no $file"
done
check_png "$TMP/bench/msaa.png" 900 560
for config in vulkan-compute vulkan-fallback gl-compute gl-fallback gles-fallback; do
  check_png "$TMP/bench/msaa-error-$config.png" 130 64   # one sample | 2 px | the largest count
done
B=$TMP/bench/msaa.json
json_check "$B" 'sorted({(c["backend"], c["path"]) for c in j["configurations"]}) == sorted([("vulkan", "compute"),
  ("vulkan", "fallback"), ("gl", "compute"), ("gl", "fallback"), ("gles", "fallback")]) and j["skipped"] == ["gles/compute: no compute"]' \
  "a configuration is missing, or one was skipped that should run"
json_check "$B" 'all(sorted((c["method"], c["samples"]) for c in j["configurations"] if (c["backend"], c["path"]) == k) ==
  [("msaa", 1), ("msaa", 4), ("ssaa", 4)] for k in {(c["backend"], c["path"]) for c in j["configurations"]})' "a row is missing"
json_check "$B" 'all(c["frameMs"] > 0 and c["forwardMs"] > 0 and (("resolveMs" in c) == (c["method"] == "msaa" and c["samples"] > 1)) and
  c.get("resolveMs", 1) > 0 for c in j["configurations"])' "a row lacks its times, or a resolve time is where no resolve ran"
# The main view's colour (8 bytes) and depth (4) per sample, plus the resolved colour: 64x64 pixels.
json_check "$B" 'all(c["targetBytes"] == {("msaa", 1): 4096 * 12, ("msaa", 4): 4096 * 4 * 12 + 4096 * 8, ("ssaa", 4): 4 * 4096 * 12}[(c["method"], c["samples"])]
  for c in j["configurations"])' "the targets' memory is wrong"
json_check "$B" 'j["referenceScale"] == 4 and j["aliasedPixels"] > 100' "the default scene at 64x64 should alias on its edges"
json_check "$B" 'all(c["error"]["aliasedLeft"] == j["aliasedPixels"] for c in j["configurations"] if c["samples"] == 1)' \
  "the one-sample row defines the aliased pixels: every one of them is wrong there"
# Accuracy: 4 samples, multisampled or supersampled, beat one, on the edges and over the image. (Which
# of the two wins depends on the scene and the size: 2x2 supersampling also samples the shading, 4x
# multisampling covers edges with a rotated grid.)
json_check "$B" '(lambda error: all(error(c, "msaa", 4)["meanAliased"] < 0.6 * c["error"]["meanAliased"] and
  error(c, "msaa", 4)["meanAll"] < c["error"]["meanAll"] and error(c, "ssaa", 4)["meanAliased"] < 0.6 * c["error"]["meanAliased"]
  and error(c, "ssaa", 4)["meanAll"] < c["error"]["meanAll"]
  for c in j["configurations"] if c["samples"] == 1))(lambda c, method, samples: next(d for d in j["configurations"]
  if (d["backend"], d["path"], d["method"], d["samples"]) == (c["backend"], c["path"], method, samples))["error"])' \
  "more samples should be closer to the supersampled reference"
# Parity: every configuration renders the same scene, so every method's error agrees across them.
json_check "$B" 'all(max(c["error"]["meanAliased"] for c in j["configurations"] if (c["method"], c["samples"]) == m) -
  min(c["error"]["meanAliased"] for c in j["configurations"] if (c["method"], c["samples"]) == m) < 0.005
  for m in {(c["method"], c["samples"]) for c in j["configurations"]})' "configurations disagree on the error"
json_check "$B" 'len(j["summary"]) == 10 and all(s["aliasedErrorRatio"] < 1 for s in j["summary"])' "the summary is incomplete"
grep -q "^## What it says" "$TMP/bench/msaa.md" || fail "msaa.md has no summary"
grep -q "| vulkan | compute | msaa 4 | 4 |" "$TMP/bench/msaa.md" || fail "msaa.md has no msaa 4 row"

# The one-sample row is measured even when not asked for; no supersampling with 'none'; a count the
# device lacks is skipped, naming it (llvmpipe has 1 and 4 only; a GPU may have 8, and then measures it).
expect_success bench msaa --quick --backends vulkan --samples 4,8 --supersample none --out "$TMP/some"
json_check "$TMP/some/msaa.json" '[(c["method"], c["samples"]) for c in j["configurations"]][:2] == [("msaa", 1), ("msaa", 4)] and
  all(c["method"] == "msaa" for c in j["configurations"])' "the one-sample row is missing, or supersampling ran though 'none'"
json_check "$TMP/some/msaa.json" 'any(c["samples"] == 8 for c in j["configurations"]) != any(s.startswith("vulkan/compute: msaa 8 is not possible")
  for s in j["skipped"])' "8 samples were neither measured nor skipped with the reason"
# A scene with an alpha-masked cut-out (a quad whose vertex alpha ramps across it, cut off at 0.55,
# turned 20 degrees): each count is measured with alpha to coverage and without ("cut-off"), and
# alpha to coverage is closer to the reference on the aliased pixels; the default scene, which has
# no masked material, gets no such rows (checked above: three rows per configuration).
python3 - "$TMP/cutout.gltf" <<'PY'
import base64, json, math, struct, sys
positions = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
colors = [(1, 1, 1, (x + 1) / 2) for x, _, _ in positions]
data = b"".join(struct.pack("<3f", *p) for p in positions) + b"".join(struct.pack("<4f", *c) for c in colors)
data += struct.pack("<6H", 0, 1, 2, 0, 2, 3)
s, c = math.sin(math.radians(10)), math.cos(math.radians(10))
json.dump({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0, "rotation": [0, 0, s, c]}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 1}, "indices": 2, "material": 0}]}],
  "materials": [{"alphaMode": "MASK", "alphaCutoff": 0.55, "emissiveFactor": [1, 0, 0],
                 "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]}}],
  "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 64},
                  {"buffer": 0, "byteOffset": 112, "byteLength": 12}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC4"},
                {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]}, open(sys.argv[1], "w"))
PY
expect_success bench msaa "$TMP/cutout.gltf" --quick --backends vulkan,gles --paths fallback --supersample none --out "$TMP/cutout"
C=$TMP/cutout/msaa.json
json_check "$C" 'all(sorted((c["samples"], c.get("alphaToCoverage")) for c in j["configurations"] if c["backend"] == b) ==
  [(1, None), (4, False), (4, True)] for b in ("vulkan", "gles"))' "each count should be measured with and without alpha to coverage"
json_check "$C" 'all(next(c for c in j["configurations"] if c["backend"] == b and c.get("alphaToCoverage") is True)["error"]["meanAliased"] <
  next(c for c in j["configurations"] if c["backend"] == b and c.get("alphaToCoverage") is False)["error"]["meanAliased"] for b in ("vulkan", "gles"))' \
  "alpha to coverage should bring the cut-out's edge closer to the reference"
grep -q "| msaa 4, cut-off | 4 |" "$TMP/cutout/msaa.md" || fail "msaa.md has no cut-off row"

# Reflection-probe captures, where the scene has probes (the built-in `probes`: 'left' 64^2, 'right'
# 128^2): per probe one sample, 4 samples and 2x2 supersampling against a 4x4-supersampled capture,
# and more samples are closer to it on the edges the one-sample capture aliases. The default scene,
# without probes, gets no such section.
json_check "$B" '"captures" not in j' "the default scene has no probes, so no capture rows"
expect_success bench msaa probes --quick --backends vulkan,gles --paths fallback --out "$TMP/probes"
P=$TMP/probes/msaa.json
json_check "$P" 'sorted((c["backend"], c["probe"], c["faceSize"], c["method"], c["samples"]) for c in j["captures"]) == sorted(
  (b, p, f, m, n) for b in ("vulkan", "gles") for p, f in (("left", 64), ("right", 128)) for m, n in (("msaa", 1), ("msaa", 4), ("ssaa", 4)))'   "a capture row is missing"
json_check "$P" 'all(c["captureMs"] > 0 and c["error"]["meanAliased"] > 0 for c in j["captures"])' "a capture row lacks its time or error"
json_check "$P" 'all(c["error"]["aliasedLeft"] > 100 for c in j["captures"] if c["samples"] == 1)' "the one-sample captures should alias"
json_check "$P" 'len(j["captureSummary"]) == 8 and all(s["aliasedErrorRatio"] < 0.7 for s in j["captureSummary"])'   "4 samples (or 2x2 supersampling) should take a capture's aliased texels well towards the reference"
json_check "$P" 'all(abs(c["error"]["meanAliased"] - d["error"]["meanAliased"]) < 0.005 for c in j["captures"] for d in j["captures"]
  if (c["probe"], c["method"], c["samples"]) == (d["probe"], d["method"], d["samples"]))' "the backends disagree on a capture's error"
grep -q "^## Reflection-probe captures" "$TMP/probes/msaa.md" || fail "msaa.md has no captures section"
grep -q "| vulkan | fallback | right | 128 | msaa 4 | 4 |" "$TMP/probes/msaa.md" || fail "msaa.md has no msaa 4 capture row"
# A probe whose reference faces would pass 2048^2 (1024^2 at 4x) is skipped saying so; the others are measured.
printf '{"gltf": "cutout.gltf", "reflectionProbes": [{"name": "big", "resolution": 1024}, {"name": "small", "resolution": 16}]}' > "$TMP/bigprobe.json"
expect_success bench msaa "$TMP/bigprobe.json" --quick --backends vulkan --paths fallback --supersample none --out "$TMP/big"
json_check "$TMP/big/msaa.json" 'any("probe \x27big\x27: its 4096x4096 reference faces would exceed 2048^2" in s for s in j["skipped"]) and
  sorted({c["probe"] for c in j["captures"]}) == ["small"]' "the 1024^2 probe should be skipped with its reason, the 16^2 one measured"
finish
