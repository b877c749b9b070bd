#!/usr/bin/env bash
# Probe GI in the CLI (docs/GI.md): `janus bake` writes a bake `janus render --gi-bake` reuses
# (the same image as baking at start-up), `--debug gi` (with its gi-probes pass), and clear errors for scenes without a
# volume and for bake files that do not fit. Needs the backends and the shared cornell box.
source "$(dirname "$0")/common.bash" "$@"
CORNELL="$REPO_ROOT/../shared/scenes/cornell-box/cornellBox.gltf"
[[ -f "$CORNELL" ]] || fail "the shared cornell box is missing: $CORNELL"

# Usage and input errors first.
expect_error 2 "--out FILE is required" bake "$CORNELL"
expect_error 3 "has no irradiance volume to bake" bake --out "$TMP/none.bake"
expect_error 2 "--gi-bake '$TMP/missing.bake' is not a file" render "$CORNELL" --gi-bake "$TMP/missing.bake" --out "$TMP/x.png"

expect_success bake "$CORNELL" --out "$TMP/cornell.bake"
grep -Eq "probes: +64 \([0-9]+ valid, [0-9]+ moved out of geometry\)" "$TMP/stdout" || fail "bake printed no probe count: $(cat "$TMP/stdout")"
[[ -s "$TMP/cornell.bake" ]] || fail "bake wrote no file"

expect_success render "$CORNELL" --size 64x64 --out "$TMP/baked-now.png"
grep -q "baking the scene's irradiance volume now" "$TMP/stderr" || fail "render did not say it bakes at start-up"
expect_success render "$CORNELL" --size 64x64 --gi-bake "$TMP/cornell.bake" --out "$TMP/from-file.png" --report "$TMP/from-file.json"
cmp -s "$TMP/baked-now.png" "$TMP/from-file.png" || fail "the image from the bake file differs from the one baked at start-up"
json_check "$TMP/from-file.json" 'not any(p["name"] == "gi-bake" for p in j["passes"])' "a bake file still baked at start-up"

# The built-in gi-rooms scene: a volume to bake and render by name.
expect_success bake gi-rooms --out "$TMP/rooms.bake"
grep -Eq "probes: +48 \(48 valid" "$TMP/stdout" || fail "bake gi-rooms printed no 48 probes: $(cat "$TMP/stdout")"
expect_success render gi-rooms --size 64x48 --gi-bake "$TMP/rooms.bake" --out "$TMP/rooms.png" --report "$TMP/rooms.json"
json_check "$TMP/rooms.json" 'any(p["name"].startswith("forward") for p in j["passes"])' "gi-rooms rendered no forward pass"

expect_success render "$CORNELL" --size 64x64 --debug gi --out "$TMP/gi.png" --report "$TMP/gi.json"
cmp -s "$TMP/gi.png" "$TMP/baked-now.png" && fail "--debug gi wrote the shaded image"
json_check "$TMP/gi.json" 'any(p["name"] == "gi-probes" for p in j["passes"])' "--debug gi drew no probes"

# A damaged bake: one flipped byte in the middle.
cp "$TMP/cornell.bake" "$TMP/damaged.bake"
size=$(stat -c %s "$TMP/damaged.bake")
printf '\xff' | dd of="$TMP/damaged.bake" bs=1 seek=$((size / 2)) conv=notrunc status=none
expect_error 3 "checksum mismatch" render "$CORNELL" --size 32x32 --gi-bake "$TMP/damaged.bake" --out "$TMP/x.png"
# Another scene's bake (the default scene has no volume, so give the cornell box a denser one).
printf '{"gltf": "%s", "irradianceVolume": {"probes": 2}}\n' "$CORNELL" > "$TMP/other.json"
expect_error 3 "baked from another scene" render "$TMP/other.json" --size 32x32 --gi-bake "$TMP/cornell.bake" --out "$TMP/x.png"
# bench gi: usage and input errors first; then a quick sweep on the cornell box, checked for what
# every row must have and for one physical fact: one bounce is further from the converged reference
# than the default's four (docs/GI.md, "Accuracy vs time").
expect_error 2 "--sweeps: unknown sweep 'colour'" bench gi "$CORNELL" --sweeps surfels,colour --out "$TMP/gi-bench"
expect_error 2 "--out DIR is required" bench gi "$CORNELL" --quick
expect_error 3 "has no irradiance volume" bench gi --quick --out "$TMP/gi-bench"
expect_success bench gi "$CORNELL" --quick --out "$TMP/gi-bench"
for file in gi.md gi.json gi.png; do
  [[ -s $TMP/gi-bench/$file ]] || fail "bench gi wrote no $file"
done
B=$TMP/gi-bench/gi.json
json_check "$B" 'sorted({c["sweep"] for c in j["configurations"]}) == sorted(["default", "surfels", "bricks", "brick-size",
  "surfels-per-brick", "spacing", "order", "bounces", "probes-per-frame", "reduction", "normal-bias", "validity", "relocation", "visibility"])' "gi.json lacks a sweep"
json_check "$B" 'all(c["relight"]["totalMs"] > 0 and c["relight"]["frames"] >= 1 and c["bakeMs"] > 0 and c["validProbes"] > 0 and
  0 < c["probeError"]["relativeRmse"] < 1 and 0 < c["imageErrorConverged"]["relativeRmse"] < 2 for c in j["configurations"])' \
  "a gi.json row lacks times or has an absurd error"
# The image with the reference's probes written in: every row has it, and another grid reads other probes.
json_check "$B" 'all(0 < c["imageErrorReferenceProbes"]["relativeRmse"] < 2 for c in j["configurations"]) and
  next(c for c in j["configurations"] if c["sweep"] == "spacing")["imageErrorReferenceProbes"] !=
  next(c for c in j["configurations"] if c["sweep"] == "default")["imageErrorReferenceProbes"]' \
  "a gi.json row lacks the image with the reference's probes, or another grid gave the default's"
json_check "$B" 'next(c for c in j["configurations"] if c["sweep"] == "bounces")["probeErrorConverged"]["relativeRmse"] >
  next(c for c in j["configurations"] if c["sweep"] == "default")["probeErrorConverged"]["relativeRmse"]' \
  "one bounce should be further from the converged reference than the default bounces"
json_check "$B" 'all(c["relight"]["frames"] == 4 * c["volume"]["bounces"] for c in j["configurations"] if c["sweep"] == "probes-per-frame")' \
  "16 probes per frame should spread each bounce cycle of a 64-probe relight over 4 frames"
# The normal-bias row looks the volume up without a bias (its image differs from the default's 0.1
# m); a lower back-face fraction can only invalidate more probes.
json_check "$B" 'next(c for c in j["configurations"] if c["sweep"] == "normal-bias")["volume"]["normalBias"] == 0 and
  next(c for c in j["configurations"] if c["sweep"] == "normal-bias")["imageError"] !=
  next(c for c in j["configurations"] if c["sweep"] == "default")["imageError"]' \
  "the normal-bias row's bias is not 0, or its image is the default's"
json_check "$B" 'next(c for c in j["configurations"] if c["sweep"] == "validity")["validProbes"] <=
  next(c for c in j["configurations"] if c["sweep"] == "default")["validProbes"]' \
  "a back-face fraction of 0.25 left more probes valid than the default 0.5"
# The visibility row turns the test off: the volume says so, and the image differs from the default's.
json_check "$B" 'next(c for c in j["configurations"] if c["sweep"] == "visibility")["volume"]["visibility"] is False and
  next(c for c in j["configurations"] if c["sweep"] == "visibility")["imageError"] !=
  next(c for c in j["configurations"] if c["sweep"] == "default")["imageError"]' \
  "the visibility row does not turn the test off, or its image is the default's"
json_check "$B" 'any(g["goal"] == "visibility test" and g["imageRmseWith"] != g["imageRmseWithout"] and g["relightMsWith"] > 0 for g in j["goals"])' \
  "gi.json's goals lack the visibility test's line"
json_check "$B" 'any(g["goal"] == "defaults vs converged reference" and 0 < g["imageRmseReferenceProbes"] < 2 for g in j["goals"])' \
  "the defaults' goal lacks the image with the reference's probes"
grep -q "^## Goals" "$TMP/gi-bench/gi.md" || fail "gi.md has no goals section"
check_png "$TMP/gi-bench/gi.png" 900 560
finish
