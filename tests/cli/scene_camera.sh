#!/usr/bin/env bash
# `janus render --scene N --camera N` (and parity's): a glTF with two scenes and three cameras
# renders the scene and camera asked for, and bad choices are clear errors. Needs the backends.
source "$(dirname "$0")/common.bash" "$@"

# Scene 0: a red quad seen by camera 0 (orthographic, the first, so the default) and camera 1
# (perspective, close);
# scene 1: a green quad and camera 2 (perspective, far).
python3 - "$TMP" <<'PY'
import base64, json, struct, sys
out = sys.argv[1]
positions = [-0.5, -0.5, 0, 0.5, -0.5, 0, 0.5, 0.5, 0, -0.5, 0.5, 0]
indices = [0, 1, 2, 0, 2, 3, 0, 0]
data = struct.pack("12f", *positions) + struct.pack("8H", *indices)
perspective = {"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100}}
gltf = {
    "asset": {"version": "2.0"},
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 2]}, {"nodes": [3, 4]}],
    "nodes": [{"name": "red quad", "mesh": 0}, {"name": "ortho", "camera": 0, "translation": [0, 0, 3]},
              {"name": "close", "camera": 1, "translation": [0, 0, 1.5]},
              {"name": "green quad", "mesh": 1}, {"name": "far", "camera": 2, "translation": [0, 0, 6]}],
    "cameras": [{"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}}, perspective, dict(perspective, name="far camera")],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]},
               {"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 1}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}, "extensions": {"KHR_materials_unlit": {}}},
                  {"pbrMetallicRoughness": {"baseColorFactor": [0, 1, 0, 1]}, "extensions": {"KHR_materials_unlit": {}}}],
    "extensionsUsed": ["KHR_materials_unlit", "KHR_materials_sheen"],   # sheen: not implemented, a warning
    "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 0]},
                  {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
}
json.dump(gltf, open(f"{out}/two-scenes.gltf", "w"))
PY

# The colour of the centre pixel and the fraction of the image the quad covers.
measure() {
  python3 - "$1" "$CLI_DIR" <<'PY'
import sys
sys.path.insert(0, sys.argv[2])
from pngio import read_png
w, h, rows = read_png(sys.argv[1])
centre = rows[h // 2][(w // 2) * 4:(w // 2) * 4 + 3]
covered = sum(1 for r in rows for x in range(w) if max(r[x * 4:x * 4 + 3]) > 100)
colour = "red" if centre[0] > 150 and centre[1] < 80 else "green" if centre[1] > 150 and centre[0] < 80 else "other"
print(colour, round(covered / (w * h), 2))
PY
}

expect_success render "$TMP/two-scenes.gltf" --size 32x32 --out "$TMP/default.png" --report "$TMP/default.json"
json_check "$TMP/default.json" 'len(j["sceneWarnings"]) == 1 and "ignoring glTF extension '"'"'KHR_materials_sheen'"'"'" in j["sceneWarnings"][0]' "the report does not carry the loader's warning"
grep -q "janus: warning: .*KHR_materials_sheen" "$TMP/stderr" || fail "the loader's warning is not on stderr: $(cat "$TMP/stderr")"
read -r colour cover < <(measure "$TMP/default.png")
[[ $colour == red ]] || fail "the default scene (0) is not the red quad: $colour"
# The default camera is scene 0's first, the orthographic camera 0: ymag 1 shows 2 x 2 units, so
# the 1 x 1 quad covers a quarter of the image.
python3 -c "import sys; sys.exit(0 if abs(float(sys.argv[1]) - 0.25) <= 0.02 else 1)" "$cover" ||
  fail "the default camera is not the orthographic one (ymag 1): cover $cover"
expect_success render "$TMP/two-scenes.gltf" --camera 0 --size 32x32 --out "$TMP/camera0.png"
cmp -s "$TMP/default.png" "$TMP/camera0.png" || fail "--camera 0 differs from the default camera"
expect_success parity "$TMP/two-scenes.gltf" --size 24x24 --out "$TMP/parity-ortho"
# Camera 1, 1.5 from the quad with a 0.8 rad field of view, sees it large.
expect_success render "$TMP/two-scenes.gltf" --camera 1 --size 32x32 --out "$TMP/camera1.png"
read -r colour cover < <(measure "$TMP/camera1.png")
python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) > 0.5 else 1)" "$cover" || fail "--camera 1 is not the close one: cover $cover"

expect_success render "$TMP/two-scenes.gltf" --scene 1 --size 32x32 --out "$TMP/scene1.png"
read -r colour far_cover < <(measure "$TMP/scene1.png")
[[ $colour == green ]] || fail "--scene 1 does not render the green quad: $colour"
python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) < float(sys.argv[2]) / 4 else 1)" "$far_cover" "$cover" ||
  fail "--scene 1 does not look through its far camera: cover $far_cover vs $cover"

expect_success render "$TMP/two-scenes.gltf" --scene 1 --camera 2 --size 32x32 --out "$TMP/scene1-camera2.png"
cmp -s "$TMP/scene1.png" "$TMP/scene1-camera2.png" || fail "--camera 2 differs from scene 1's only camera"
expect_success parity "$TMP/two-scenes.gltf" --scene 1 --size 24x24 --out "$TMP/parity"

expect_error 3 "scene 4 does not exist: the file has 2 scene\(s\) \(0 to 1\)" render "$TMP/two-scenes.gltf" --scene 4 --out "$TMP/x.png"
expect_error 3 "camera 2 \('far camera'\) is used by no node of the loaded scene" render "$TMP/two-scenes.gltf" --camera 2 --out "$TMP/x.png"
expect_error 2 "--scene 'one' is not an index" render "$TMP/two-scenes.gltf" --scene one --out "$TMP/x.png"
expect_error 2 "--camera -1|--camera '-1' is not an index" render "$TMP/two-scenes.gltf" --camera -1 --out "$TMP/x.png"
expect_error 2 "--camera picks a glTF file's scene or camera; the built-in default scene has one of each" render --camera 1 --out "$TMP/x.png"

finish
