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
grep -Eq "probes: +64 \([0-9]+ valid\)" "$TMP/stdout" || fail "bake printed no probe count: $(cat "$TMP/stdout")"
[[ -s "$TMP/cornell.bake" ]] || fail "bake wrote no file"

expect_success render "$CORNELL" --size 64x64 --out "$TMP/baked-now.png"
grep -q "baking the scene's irradiance volume now" "$TMP/stderr" || fail "render did not say it bakes at start-up"
expect_success render "$CORNELL" --size 64x64 --gi-bake "$TMP/cornell.bake" --out "$TMP/from-file.png" --report "$TMP/from-file.json"
cmp -s "$TMP/baked-now.png" "$TMP/from-file.png" || fail "the image from the bake file differs from the one baked at start-up"
json_check "$TMP/from-file.json" 'not any(p["name"] == "gi-bake" for p in j["passes"])' "a bake file still baked at start-up"

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
finish
