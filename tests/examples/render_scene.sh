#!/usr/bin/env bash
# examples/render_scene: the default scene on vulkan/compute and gles/fallback must agree by the
# parity rule and leave both images and the heat map; a missing scene is exit 3 naming it, the
# compute path on gles exit 4 naming the capability, a bad configuration exit 2.
source "$(dirname "$0")/common.bash"
PROGRAM=$1
run 0 '^vulkan/compute vs gles/fallback: agree$' --size 64 --out "$tmp/default"
for image in a.png b.png difference.png; do
  [[ -s $tmp/default/$image ]] || fail "render_scene wrote no $image"
done
grep -q '^  forward ' "$tmp/log" || fail "render_scene printed no forward pass: $(cat "$tmp/log")"
run 0 '^gl/compute vs vulkan/fallback: agree$' --a gl/compute --b vulkan/fallback --size 64 --out "$tmp/gl"
run 3 'no-such-scene\.gltf' "$tmp/no-such-scene.gltf" --out "$tmp/missing"
run 4 "gles/compute needs capability 'compute'" --b gles/compute --size 64 --out "$tmp/refused"
run 2 "'gles' is not BACKEND/PATH" --b gles

finish "render_scene: the configurations agree"
