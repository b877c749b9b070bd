#!/usr/bin/env bash
# Input and output errors (exit 3): missing or malformed scenes, unwritable output paths. Each is
# detected before a device opens, so this needs no backend.
source "$(dirname "$0")/common.bash" "$@"

out="$TMP/out.png"
printf '{"asset": {"version": "2.0"}, "nodes": [' >"$TMP/truncated.gltf"
printf 'not json at all' >"$TMP/garbage.json"
printf 'glTF\x02\x00\x00\x00garbage' >"$TMP/garbage.glb"
printf '{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 7}]}' >"$TMP/dangling.gltf"
touch "$TMP/a-file"

expect_error 3 "scene file '.*no-such-scene.gltf' does not exist" render "$TMP/no-such-scene.gltf" --out "$out"
expect_error 3 "scene file '.*no-such-scene.gltf' does not exist" parity "$TMP/no-such-scene.gltf" --out "$TMP/parity"
expect_error 3 "truncated.gltf"   render "$TMP/truncated.gltf" --out "$out"
expect_error 3 "garbage.json"     render "$TMP/garbage.json" --out "$out"
expect_error 3 "garbage.glb"      render "$TMP/garbage.glb" --out "$out"
expect_error 3 "dangling.gltf.*mesh" render "$TMP/dangling.gltf" --out "$out"
expect_error 3 "is a directory"   render "$TMP" --out "$out"

# Environment maps: --env naming a missing file, and a scene file whose "map" is missing (named
# as resolved against the scene's folder). An existing sky passes the check (the scene then fails).
sky="$REPO_ROOT/../shared/scenes/env/chinese_garden_1k.hdr"
box="$REPO_ROOT/../shared/scenes/BoxTextured/glTF/BoxTextured.gltf"
printf '{"gltf": "%s", "environment": {"map": "skies/missing-sky.hdr"}}' "$box" >"$TMP/nosky.json"
mkdir "$TMP/dir.hdr"
expect_error 3 "--env '.*no-such-sky.hdr' does not exist" render --env "$TMP/no-such-sky.hdr" --out "$out"
expect_error 3 "--env '.*no-such-sky.exr' does not exist" parity --env "$TMP/no-such-sky.exr" --out "$TMP/parity"
expect_error 3 "--env '.*' is a directory"                render --env "$TMP/dir.hdr" --out "$out"
expect_error 3 "nosky.json.*$TMP/skies/missing-sky.hdr' does not exist" render "$TMP/nosky.json" --out "$out"
expect_error 3 "scene file '.*no-such-scene.gltf' does not exist" render "$TMP/no-such-scene.gltf" --env "$sky" --out "$out"

# A glTF whose buffer lies outside its folder is refused, naming the URI and the flag that allows
# it (render.sh renders it with --allow-outside-paths).
boxdir="$REPO_ROOT/../shared/scenes/BoxTextured/glTF"
mkdir "$TMP/models"
cp "$boxdir/BoxTextured0.bin" "$TMP/"
cp "$boxdir/CesiumLogoFlat.png" "$TMP/models/"
sed 's|"BoxTextured0.bin"|"../BoxTextured0.bin"|' "$boxdir/BoxTextured.gltf" >"$TMP/models/outside.gltf"
expect_error 3 "outside.gltf: buffer 0: URI '../BoxTextured0.bin' leaves the glTF's folder.*--allow-outside-paths" \
  render "$TMP/models/outside.gltf" --out "$out"
expect_error 3 "outside.gltf: buffer 0: URI '../BoxTextured0.bin' leaves the glTF's folder" parity "$TMP/models/outside.gltf" --out "$TMP/parity"

# Unwritable outputs: missing directory, a file where a directory should be, a directory as file.
expect_error 3 "cannot write --out '.*missing/out.png': directory '.*missing' does not exist" render --out "$TMP/missing/out.png"
expect_error 3 "cannot write --out '.*a-file/out.png'.*not a directory" render --out "$TMP/a-file/out.png"
expect_error 3 "cannot write --hdr '.*missing/out.exr'"    render --out "$out" --hdr "$TMP/missing/out.exr"
expect_error 3 "cannot write --report '.*missing/r.json'"  render --out "$out" --report "$TMP/missing/r.json"
mkdir "$TMP/taken.png"
expect_error 3 "--out '.*taken.png' is a directory" render --out "$TMP/taken.png"
expect_error 3 "--out '.*a-file' is a file"         parity --out "$TMP/a-file"
expect_error 3 "cannot create --out directory"      parity --out "$TMP/a-file/sub"

if [[ -e $out ]]; then fail "a failed render left $out behind"; fi
if [[ -e $TMP/parity ]]; then fail "a parity with a bad scene created its --out directory"; fi
finish
