#!/usr/bin/env bash
# `janus render --time SECONDS --animation NAME|INDEX` (and parity's), and the scene file's "time"
# and "animation": a tiny glTF whose rigid node two animations move renders differently at two
# times, t = 0 without --time, and every bad value is a clear error. Needs the backends.
source "$(dirname "$0")/common.bash" "$@"

# A unit quad (node "box") that animation 0, "slide", moves from x = -1 to x = 1 over 1 s and
# animation 1, "hop", lifts from y = 0 to y = 1; a camera from +Z sees both ends.
python3 - "$TMP" <<'PY'
import base64, json, struct, sys
out = sys.argv[1]
positions = [-0.3, -0.3, 0, 0.3, -0.3, 0, 0.3, 0.3, 0, -0.3, 0.3, 0]
indices = [0, 1, 2, 0, 2, 3, 0, 0]            # two triangles, padded to 4 bytes
times = [0.0, 1.0]
slide = [-1, 0, 0, 1, 0, 0]
hop = [0, 0, 0, 0, 1, 0]
data = struct.pack("12f", *positions) + struct.pack("8H", *indices) + struct.pack("2f", *times) + struct.pack("6f", *slide) + struct.pack("6f", *hop)
views = [(0, 48), (48, 12), (64, 8), (72, 24), (96, 24)]
gltf = {
    "asset": {"version": "2.0"},
    "scene": 0,
    "scenes": [{"nodes": [0]}],
    "nodes": [{"name": "box", "mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0.1, 1]}, "emissiveFactor": [1, 0.5, 0.1], "doubleSided": True}],
    "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
    "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": n} for o, n in views],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-0.3, -0.3, 0], "max": [0.3, 0.3, 0]},
        {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
        {"bufferView": 2, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1]},
        {"bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC3"},
        {"bufferView": 4, "componentType": 5126, "count": 2, "type": "VEC3"},
    ],
    "animations": [
        {"name": "slide", "samplers": [{"input": 2, "output": 3}], "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}]},
        {"name": "hop", "samplers": [{"input": 2, "output": 4}], "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}]},
    ],
}
json.dump(gltf, open(f"{out}/anim.gltf", "w"))
camera = {"position": [0, 0, 4], "target": [0, 0, 0], "fovYDegrees": 60}
json.dump({"gltf": "anim.gltf", "camera": camera}, open(f"{out}/anim.json", "w"))
json.dump({"gltf": "anim.gltf", "camera": camera, "time": 1}, open(f"{out}/anim-at-1.json", "w"))
json.dump({"gltf": "anim.gltf", "camera": camera, "animation": "hop", "time": 0.5}, open(f"{out}/anim-hop.json", "w"))
json.dump({"gltf": "anim.gltf", "camera": camera, "time": -1}, open(f"{out}/anim-negative.json", "w"))
json.dump({"gltf": "anim.gltf", "camera": camera, "animation": "walk"}, open(f"{out}/anim-walk.json", "w"))
PY

same() { cmp -s "$1" "$2"; }
render() {   # render OUT.png ARGS...: a 32x32 render on the default configuration
  local out=$1
  shift
  expect_success render "$@" --size 32x32 --out "$TMP/$out"
  check_png "$TMP/$out" 32 32
}

# Without --time the scene is at t = 0 of animation 0; a later time moves the node.
render default.png "$TMP/anim.json"
grep -Eq "^  pose: +animation 0 'slide' at 0 s \(of 1 s; 2 animations in the scene\)$" "$TMP/stdout" ||
  fail "render does not print the pose: $(cat "$TMP/stdout")"
render t0.png "$TMP/anim.json" --time 0
render t1.png "$TMP/anim.json" --time 1
grep -Eq "^  pose: +animation 0 'slide' at 1 s" "$TMP/stdout" || fail "render --time 1 does not print its pose"
same "$TMP/default.png" "$TMP/t0.png" || fail "a render without --time differs from --time 0"
same "$TMP/t0.png" "$TMP/t1.png" && fail "the renders at t = 0 and t = 1 are identical: the animation did not move the node"
render late.png "$TMP/anim.json" --time 7.5   # past the end: holds the last keyframe
same "$TMP/t1.png" "$TMP/late.png" || fail "a time past the end does not hold the last keyframe"

# --animation by name or index; the scene file's keys, which the options override.
render hop.png "$TMP/anim.json" --time 0.5 --animation hop
grep -Eq "^  pose: +animation 1 'hop' at 0.5 s" "$TMP/stdout" || fail "render --animation hop does not print its pose"
render hop-index.png "$TMP/anim.json" --time 0.5 --animation 1
same "$TMP/hop.png" "$TMP/hop-index.png" || fail "--animation hop and --animation 1 differ"
same "$TMP/hop.png" "$TMP/t0.png" && fail "--animation hop at 0.5 s looks like slide at 0 s"
render file-hop.png "$TMP/anim-hop.json"
same "$TMP/hop.png" "$TMP/file-hop.png" || fail "the scene file's \"animation\"/\"time\" differ from --animation/--time"
render file-at-1.png "$TMP/anim-at-1.json"
same "$TMP/t1.png" "$TMP/file-at-1.png" || fail "the scene file's \"time\": 1 differs from --time 1"
render file-override.png "$TMP/anim-at-1.json" --time 0
same "$TMP/t0.png" "$TMP/file-override.png" || fail "--time 0 does not override the scene file's \"time\""
render file-keep-time.png "$TMP/anim-hop.json" --animation slide   # the file's time (0.5) stays
render slide-half.png "$TMP/anim.json" --time 0.5
same "$TMP/slide-half.png" "$TMP/file-keep-time.png" || fail "--animation alone does not keep the scene file's \"time\""

# Bad values: usage errors (exit 2) naming the option and the problem, before anything renders.
expect_error 2 "--time '-1' is not allowed; give a finite number of seconds >= 0" render "$TMP/anim.json" --time -1 --out "$TMP/bad.png"
expect_error 2 "--time 'nan' is not allowed" render "$TMP/anim.json" --time nan --out "$TMP/bad.png"
expect_error 2 "--time 'inf' is not allowed" render "$TMP/anim.json" --time inf --out "$TMP/bad.png"
expect_error 2 "--time 'soon' is not a number" render "$TMP/anim.json" --time soon --out "$TMP/bad.png"
expect_error 2 "--animation 'walk': no animation is named 'walk'; the scene's animations: 0 'slide', 1 'hop'" \
  render "$TMP/anim.json" --animation walk --out "$TMP/bad.png"
expect_error 2 "--animation '2': animation index 2 is out of range: the scene has 2 animations" \
  render "$TMP/anim.json" --animation 2 --out "$TMP/bad.png"
expect_error 2 "--animation '0': .*BoxTextured.gltf has no animations" \
  render "$REPO_ROOT/../shared/scenes/BoxTextured/glTF/BoxTextured.gltf" --animation 0 --out "$TMP/bad.png"
expect_error 2 "--animation 'slide': built-in default scene has no animations" render --animation slide --out "$TMP/bad.png"
expect_error 2 "--time '-0.5' is not allowed" parity "$TMP/anim.json" --time -0.5 --out "$TMP/bad-parity"
expect_error 2 "--animation 'walk': no animation is named 'walk'" parity "$TMP/anim.json" --animation walk --out "$TMP/bad-parity"
[[ ! -e $TMP/bad.png && ! -e $TMP/bad-parity ]] || fail "a refused command wrote output"
# The scene file's own bad keys are scene errors (exit 3) naming the file.
expect_error 3 "anim-negative.json: \"time\" must be a number of seconds >= 0, got -1" render "$TMP/anim-negative.json" --out "$TMP/bad.png"
expect_error 3 "anim-walk.json: \"animation\": no animation is named 'walk'" render "$TMP/anim-walk.json" --out "$TMP/bad.png"

# --time on a scene without animations is allowed (nothing moves).
render static.png "$REPO_ROOT/../shared/scenes/BoxTextured/glTF/BoxTextured.gltf" --time 3
grep -q "pose:" "$TMP/stdout" && fail "a scene without animations prints a pose"

# parity poses every configuration alike and records the pose.
expect_success parity "$TMP/anim.json" --time 0.5 --animation hop --size 16x16 --out "$TMP/parity"
grep -Eq "^pose: animation 1 'hop' at 0.5 s" "$TMP/stdout" || fail "parity does not print its pose"
json_check "$TMP/parity/parity.json" 'j["animation"] == 1 and j["animationName"] == "hop" and j["time"] == 0.5 and j["passed"]' \
  "parity.json does not record the pose (or parity failed)"

finish
