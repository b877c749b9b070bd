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
finish
