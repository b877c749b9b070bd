#!/usr/bin/env bash
# `janus bench forward --quick`: every output file, a row per backend/path/count/mode with a
# speed-up against naive, efficiencies in (0, 1], the cut-off error table, the tile knobs. `janus bench probes
# --quick`: per-mip errors against the reference and the GPU time per configuration, errors that
# fall with more samples. Needs the backends.
source "$(dirname "$0")/common.bash" "$@"

expect_error 2 "--modes 'naive,auto': each mode must be naive, tiles-2d or tiles-depth" \
  bench forward --quick --modes naive,auto --out "$TMP/bench"
expect_error 2 "--lights 'x' must be a comma-separated list" bench forward --lights x --out "$TMP/bench"
# Empty lists, a zero frame count and a bad cut-off are usage errors before any device opens (an
# empty --lights crashed); --quick does not hide a bad explicit value, nor does it override one.
for option in --lights --modes --paths --backends --cutoffs; do
  expect_error 2 "^janus: error: $option '' is empty; give at least one entry" bench forward "$option" "" --out "$TMP/bench"
  expect_error 2 "$option ',' is empty" bench forward --quick "$option" , --out "$TMP/bench"
done
expect_error 2 "--frames 0 is not allowed" bench forward --frames 0 --out "$TMP/bench"
expect_error 2 "--cutoffs 'nan': each cut-off must be a finite number > 0" bench forward --cutoffs nan --out "$TMP/bench"
expect_error 2 "--cutoffs '0.01,0'" bench forward --cutoffs 0.01,0 --out "$TMP/bench"
expect_error 2 "--size 'abc' is not WIDTHxHEIGHT" bench forward --quick --size abc --out "$TMP/bench"
expect_error 2 "--lights '0,99999' must be" bench forward --quick --lights 0,99999 --out "$TMP/bench"
expect_error 2 "--tile-sizes '16,48' must be a comma-separated list of power-of-two integers 16..256" \
  bench forward --quick --tile-sizes 16,48 --out "$TMP/bench"
expect_error 2 "--tile-caps '0' must be a comma-separated list of integers 1..1024" bench forward --tile-caps 0 --out "$TMP/bench"
[[ -e $TMP/bench ]] && fail "a bench forward usage error created --out"
# Nothing can run: gles has no compute path.
expect_error 4 "bench forward: no configuration could run \\(gles/compute: " \
  bench forward --quick --backends gles --paths compute --out "$TMP/bench-none"
[[ -e $TMP/bench-none/forward.json ]] && fail "bench forward wrote forward.json though nothing ran"
# An explicit option wins over --quick's default: 8 lights, not 0 and 64.
expect_success bench forward --quick --lights 8 --modes naive --backends vulkan --paths fallback --size 32x16 --out "$TMP/bench-explicit"
json_check "$TMP/bench-explicit/forward.json" '[r["lights"] for r in j["rows"]] == [8] and j["size"] == [32, 16]' \
  "bench forward --quick ignored the explicit --lights 8 / --size 32x16"


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
# The tile knobs (64 lights): 16 and 64 px tiles at the default cap (automatic: the 64 lights), and
# a cap of 4 at 16 px, per backend and path. Conservative culling renders exactly what naive does until a list is full; a
# cap of 4 drops lights (counted) and makes an error; bigger tiles test more lights per pixel.
json_check "$TMP/bench/forward.json" 'sorted((k["knob"], k["tileSize"], k["maxLightsPerTile"]) for k in j["tileKnobs"]) ==
  sorted([("tile size", 16, 64), ("tile size", 64, 64), ("list cap", 16, 4)] * 4) and
  all(k["maxLightsPerTileAuto"] == (k["knob"] == "tile size") for k in j["tileKnobs"])' "the tile knob rows are not the quick sweep"
json_check "$TMP/bench/forward.json" 'all(k["maxAbsError"] == 0 and k["droppedLights"] == 0 for k in j["tileKnobs"] if k["overflowTiles"] == 0) and
  all(k["overflowTiles"] > 0 and k["droppedLights"] > 0 and k["maxAbsError"] > 0 for k in j["tileKnobs"] if k["maxLightsPerTile"] == 4)' \
  "a tile knob row without overflow differs from naive, or the cap of 4 dropped nothing"
json_check "$TMP/bench/forward.json" 'all((k["densestTileLights"] > k["maxLightsPerTile"]) == (k["overflowTiles"] > 0) for k in j["tileKnobs"])' \
  "the densest tile's count should exceed the cap exactly where tiles overflow"
json_check "$TMP/bench/forward.json" 'all(next(k for k in j["tileKnobs"] if (k["backend"], k["path"], k["tileSize"]) == (t["backend"], t["path"], 64))["efficiency"] <
  t["efficiency"] for t in j["tileKnobs"] if t["knob"] == "tile size" and t["tileSize"] == 16)' "64 px tiles should cull less tightly than 16 px ones"
grep -q "^## Tile size and list cap (64 lights" "$TMP/bench/forward.md" || fail "forward.md has no tile knob section"

# bench probes: usage errors before any device opens; a missing sky is an input error.
expect_error 2 "--samples '8,2000' must be a comma-separated list of integers 1..1024" \
  bench probes --samples 8,2000 --out "$TMP/probes"
expect_error 2 "--sizes '48' must be a comma-separated list of power-of-two integers" bench probes --sizes 48 --out "$TMP/probes"
expect_error 2 "unknown --path 'warp'" bench probes --quick --paths compute,warp --out "$TMP/probes"
expect_error 3 "--env '.*nope.hdr' does not exist" bench probes --quick --env "$TMP/nope.hdr" --out "$TMP/probes"
expect_error 2 "--bright-texels 2000 must be 0..1023" bench probes --bright-texels 2000 --out "$TMP/probes"

# vulkan: compute and fallback; gles: fallback only (compute is skipped and says why).
expect_success bench probes --quick --backends vulkan,gles --paths compute,fallback --out "$TMP/probes"
for file in probes.md probes.json probes.png; do
  [[ -s $TMP/probes/$file ]] || fail "bench probes wrote no $file"
done
grep -q "^| backend | path | samples | GPU ms | mip 1 (r 0.20) |" "$TMP/probes/probes.md" || fail "probes.md has no table"
P=$TMP/probes/probes.json
json_check "$P" 'sorted((c["backend"], c["path"], c["samplesPerMip"]) for c in j["configurations"]) == sorted(
  (b, p, n) for b, p in [("vulkan", "compute"), ("vulkan", "fallback"), ("gles", "fallback")] for n in (16, 64))' \
  "probes.json does not have samples 16 and 64 for vulkan/compute, vulkan/fallback, gles/fallback"
json_check "$P" 'all(c["faceSize"] == 32 and c["gpuMs"] > 0 and len(c["mips"]) == 5 and all(
  m["rmse"] > 0 and m["maxRel"] > 0 and m["texelsCompared"] > 0 for m in c["mips"])
  for c in j["configurations"])' "a configuration lacks gpuMs or per-mip rmse/maxRel for mips 1..5"
json_check "$P" 'len(j["skipped"]) >= 1 and any(s.startswith("gles/compute") for s in j["skipped"])' "gles/compute not reported as skipped"
# More samples, less error: on mip 1 (roughness 0.2) the 64-sample RMSE is below the 16-sample one
# on every configuration (measured 1.7 % -> 0.9 %, docs/IBL.md).
json_check "$P" 'all(
  next(c for c in j["configurations"] if (c["backend"], c["path"], c["samplesPerMip"]) == (b, p, 64))["mips"][0]["rmse"] <
  next(c for c in j["configurations"] if (c["backend"], c["path"], c["samplesPerMip"]) == (b, p, 16))["mips"][0]["rmse"]
  for b, p in [("vulkan", "compute"), ("vulkan", "fallback"), ("gles", "fallback")])' "mip 1 error does not fall from 16 to 64 samples"
# The synthetic sky has no bright texels: the split (on by default) finds none.
json_check "$P" 'j["brightTexels"] == 64 and all(c["brightFound"] == 0 and not c["brightOverflow"] for c in j["configurations"])' \
  "probes.json: the synthetic sky should have no bright texels"
check_png "$TMP/probes/probes.png" 900 560

# The shared sky (a sun) at the default samples ("default": 21, 34, 55, 89, 89, 89): the split finds
# the sun and every mip stays within a few % of the reference (docs/IBL.md, "Bright texels").
SKY=$REPO_ROOT/../shared/scenes/env/chinese_garden_1k.hdr
if [[ -f $SKY ]]; then
  expect_success bench probes --backends vulkan --paths compute --sizes 32 --samples default,16 --runs 1 --env "$SKY" --out "$TMP/garden"
  G=$TMP/garden/probes.json
  json_check "$G" 'sorted(str(c["samplesPerMip"]) for c in j["configurations"]) == ["16", "default"]' "garden: rows 16 and default"
  json_check "$G" 'all(c["brightFound"] >= 1 and not c["brightOverflow"] for c in j["configurations"])' "garden: the sun was not found"
  json_check "$G" 'all(m["rmse"] < 0.05 for c in j["configurations"] if c["samplesPerMip"] == "default" and
    c["samplesPerMipList"] == [21, 34, 55, 89, 89, 89] for m in c["mips"])' "garden: default samples above 5 % RMSE on some mip"
  grep -q "^| vulkan | compute | default |" "$TMP/garden/probes.md" || fail "garden probes.md has no default row"
fi
finish
