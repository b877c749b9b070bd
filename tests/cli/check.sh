#!/usr/bin/env bash
# `janus check`: usage and input errors; the shared scenes (../shared/scenes) at 48x48 with
# check.json's structure, counts, detected features, thumbnails and contact sheets checked pixel
# by pixel; a small folder of our own (a malformed .gltf, a .glb, a duplicate) with gles made
# unavailable; divergence at --tolerance 0 --edge-pixels 0. Needs the backends; about 45 s on llvmpipe.
source "$(dirname "$0")/common.bash" "$@"

SCENES="$REPO_ROOT/../shared/scenes"
BOX_DIR="$SCENES/khronos/BoxVertexColors/glTF"
CORNELL="$SCENES/cornell-box/cornellBox.gltf"

# ---- help, usage and input errors (no device is opened) --------------------------------------
run_janus check --help
[[ $rc == 0 ]] || fail "janus check --help: exit $rc"
for text in --out --size --tolerance --edge-pixels --gl-platform --validation --allow-outside-paths --env '^  0  ' '^  1  ' '^  3  ' '^  4  '; do
  grep -Eq -- "$text" "$TMP/stdout" || fail "janus check --help does not mention $text"
done

mkdir -p "$TMP/empty/sub" "$TMP/assets/good"
echo "not a model" >"$TMP/empty/sub/readme.txt"
touch "$TMP/a-file"
expect_error 2 "at least one PATH"               check --out "$TMP/never"
expect_error 2 "--out DIR is required"           check "$BOX_DIR"
expect_error 2 "--size '0x0'"                    check "$BOX_DIR" --size 0x0 --out "$TMP/never"
expect_error 2 "--tolerance '256'"               check "$BOX_DIR" --tolerance 256 --out "$TMP/never"
expect_error 3 "PATH '.*missing' does not exist" check "$TMP/missing" --out "$TMP/never"
expect_error 3 "no .gltf or .glb file under '.*empty'" check "$TMP/empty" --out "$TMP/never"
expect_error 3 "PATH '.*readme.txt' is not a .gltf or .glb file" check "$TMP/empty/sub/readme.txt" --out "$TMP/never"
expect_error 3 "--out '.*a-file' is a file"      check "$BOX_DIR" --out "$TMP/a-file"
expect_error 3 "PATH '.*missing' does not exist" check "$BOX_DIR" "$TMP/missing" --out "$TMP/never"
[[ -e $TMP/never ]] && fail "a failed check left output behind"

# ---- helpers ---------------------------------------------------------------------------------
# check_report DIR WIDTH HEIGHT RC: check.json is consistent with itself, with RC, and with the
# files beside it: thumbnails, and contact sheets whose every cell is decoded and compared with
# the thumbnail it should hold, or with the placeholder colours.
check_report() {
  local dir=$1 width=$2 height=$3 status=$4 problems
  if [[ ! -f $dir/check.json || ! -f $dir/check.md ]]; then
    fail "$dir: check.json or check.md missing"
    return 0
  fi
  problems=$(python3 - "$dir" "$width" "$height" "$status" "$CLI_DIR" <<'PY'
import json, math, os, struct, sys, zlib
sys.path.insert(0, sys.argv[5])
import pngio

out, width, height, rc = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
j = json.load(open(os.path.join(out, "check.json")))
problems = []
def check(ok, message):
    if not ok: problems.append(message)

def read_png(path):   # rows of (r, g, b) tuples
    w, h, rgba = pngio.read_png(path)
    return w, h, [[tuple(r[x * 4:x * 4 + 3]) for x in range(w)] for r in rgba]

file_states = {"rendered", "diverged", "failed", "refused"}
config_states = {"rendered", "failed", "unavailable", "not-run"}
files = j["files"]
check(j["width"] == width and j["height"] == height, f"size {j['width']}x{j['height']}, expected {width}x{height}")
check(j["exitCode"] == rc, f"exitCode {j['exitCode']} but janus exited {rc}")
check(j["passed"] == (rc == 0), f"passed {j['passed']} but janus exited {rc}")
counts = {s: sum(f["status"] == s for f in files) for s in file_states}
check(j["counts"] == dict(counts, files=len(files)), f"counts {j['counts']} do not match the files {counts}")
check(j["passed"] == (counts["failed"] == 0 and counts["diverged"] == 0), "passed does not follow from the counts")
check([f["index"] for f in files] == list(range(len(files))), "indices are not 0..N-1 in order")
check(len({f["path"] for f in files}) == len(files), "a file is listed twice")
check(len(j["configurations"]) == 5, "not five configurations")
available = [c["available"] for c in j["configurations"]]
names = [c["configuration"] for c in j["configurations"]]
tolerance, edge_pixels = j["tolerance"], j["edgePixels"]
for f in files:
    what = f["path"]
    check(f["status"] in file_states, f"{what}: status {f['status']}")
    check(isinstance(f["features"], list) and isinstance(f["extensionsUsed"], list) and isinstance(f["extensionsRequired"], list), f"{what}: feature lists missing")
    check([c["configuration"] for c in f["configurations"]] == names, f"{what}: configurations not listed in order")
    for c, on in zip(f["configurations"], available):
        check(c["status"] in config_states, f"{what}: configuration status {c['status']}")
        check((c["status"] == "unavailable") == (not on), f"{what}: {c['configuration']} is {c['status']} but available={on}")
        if f["status"] == "refused":
            check(c["status"] in ("not-run", "unavailable"), f"{what}: refused but {c['configuration']} {c['status']}")
        if c["status"] == "rendered":
            check(os.path.isfile(os.path.join(out, c["image"])), f"{what}: thumbnail {c.get('image')} missing")
        if c["status"] == "failed":
            check(c.get("error"), f"{what}: {c['configuration']} failed without an error")
    states = [c["status"] for c in f["configurations"]]
    if f["status"] == "refused":
        check(f.get("reason") and f["parity"] is None, f"{what}: refused without a reason, or with a parity result")
    else:
        p = f["parity"]
        rendered = states.count("rendered")
        check(p["pairsCompared"] == rendered * (rendered - 1) // 2 == len(p["pairs"]), f"{what}: {p['pairsCompared']} pairs compared for {rendered} renders")
        over = [q for q in p["pairs"] if q["maxChannelDifference"] > tolerance and q["differingPixels"] > edge_pixels]
        check(all(q["passed"] == (q["maxChannelDifference"] <= tolerance or q["differingPixels"] <= edge_pixels) for q in p["pairs"]),
              f"{what}: a pair's passed disagrees with the tolerance and the edge pixels")
        check(all(os.path.isfile(os.path.join(out, q["heatmap"])) for q in over), f"{what}: a heat map of a diverging pair is missing")
        if p["pairs"]:
            check(p["maxChannelDifference"] == max(q["maxChannelDifference"] for q in p["pairs"]), f"{what}: wrong max diff")
        expected = "failed" if "failed" in states else "diverged" if over else "rendered"
        check(f["status"] == expected, f"{what}: status {f['status']}, expected {expected}")

# Contact sheets: ceil(sqrt(N)) columns, ceil(N / columns) rows, each cell the tile plus a frame.
n, sheet = len(files), j["contactSheet"]
columns = math.ceil(math.sqrt(n))
rows = math.ceil(n / columns)
border = sheet["border"]
cell_w, cell_h = width + 2 * border, height + 2 * border
check((sheet["columns"], sheet["rows"], sheet["width"], sheet["height"]) == (columns, rows, columns * cell_w, rows * cell_h),
      f"contact sheet layout {sheet} for {n} files")
frames = {"rendered": (40, 40, 40), "refused": (40, 40, 40), "diverged": (255, 140, 0), "failed": (220, 0, 0)}
for k, config in enumerate(j["configurations"]):
    stem = config["configuration"].replace("/", "-")
    path = os.path.join(out, f"contact-{stem}.png")
    if not config["available"]:
        check("contactSheet" not in config and config.get("reason"), f"{stem}: unavailable without a reason, or with a sheet")
        continue
    check(config.get("contactSheet") == f"contact-{stem}.png", f"{stem}: contactSheet is {config.get('contactSheet')}")
    try:
        w, h, pixels = read_png(path)
    except Exception as e:
        problems.append(f"{path}: {e}")
        continue
    check((w, h) == (columns * cell_w, rows * cell_h), f"{path}: {w}x{h}, expected {columns * cell_w}x{rows * cell_h}")
    if (w, h) != (columns * cell_w, rows * cell_h):
        continue
    for i, f in enumerate(files):
        x0, y0 = (i % columns) * cell_w, (i // columns) * cell_h
        c = f["configurations"][k]
        check(pixels[y0][x0] == frames[f["status"]], f"{stem}: cell {i} frame {pixels[y0][x0]}, expected {frames[f['status']]} ({f['status']})")
        tile = [row[x0 + border:x0 + border + width] for row in pixels[y0 + border:y0 + border + height]]
        if c["status"] == "rendered":
            check(read_png(os.path.join(out, c["image"]))[2] == tile, f"{stem}: cell {i} is not {c['image']}")
        else:
            expected = (110, 110, 110) if f["status"] == "refused" else (110, 0, 0)
            check(tile[height * 3 // 4][width // 4] == expected, f"{stem}: cell {i} ({c['status']}) is not the placeholder {expected}")
    for i in range(n, columns * rows):   # empty cells
        x0, y0 = (i % columns) * cell_w, (i // columns) * cell_h
        check(pixels[y0 + cell_h // 2][x0 + cell_w // 2] == (0, 0, 0), f"{stem}: empty cell {i} is not black")

# check.md: a row per file, in order, and a section per file that is not plainly rendered.
md = open(os.path.join(out, "check.md")).read()
for i, f in enumerate(files):
    check(f"| {i + 1} | {f['path']} | {f['status']} |" in md, f"check.md has no row for #{i + 1} {f['path']}")
    if f["status"] != "rendered":
        check(f"### {i + 1}. `{f['path']}`: {f['status']}" in md, f"check.md has no section for {f['path']}")
print("\n".join(problems))
PY
  )
  if [[ -n $problems ]]; then
    while IFS= read -r line; do fail "$dir: $line"; done <<<"$problems"
  fi
}

# file_check DIR NAME EXPRESSION DESCRIPTION: EXPRESSION about `f`, the entry whose path ends in NAME.
file_check() {
  local dir=$1 name=$2 expression=$3 description=$4
  json_check "$dir/check.json" "[f for f in j['files'] if f['path'].endswith('/$name')] and all(($expression) for f in j['files'] if f['path'].endswith('/$name'))" "$name: $description"
}

# ---- the shared scenes ----------------------------------------------------------------------
if [[ ! -d $SCENES ]]; then
  fail "$SCENES is missing (the shared scenes are cloned beside the repository)"
  finish
fi
out="$TMP/shared"
start=$SECONDS
run_janus check "$SCENES" --size 48x48 --out "$out"
echo "check on the shared scenes: exit $rc in $((SECONDS - start)) s"
if [[ $rc != 0 && $rc != 1 ]]; then fail "check on the shared scenes: exit $rc; stderr: $(cat "$TMP/stderr")"; fi
check_report "$out" 48 48 "$rc"

# Every glTF under the folder, each once, in sorted order.
expected=$(cd "$SCENES/.." && find "$(basename "$SCENES")" -type f \( -iname '*.gltf' -o -iname '*.glb' \) | LC_ALL=C sort | sed "s|^|$SCENES/../|")
listed=$(python3 -c 'import json,sys; print("\n".join(f["path"] for f in json.load(open(sys.argv[1]))["files"]))' "$out/check.json")
expected_real=$(while read -r p; do realpath "$p"; done <<<"$expected")
listed_real=$(while read -r p; do realpath "$p"; done <<<"$listed")
[[ $expected_real == "$listed_real" ]] || fail "check.json does not list every glTF under $SCENES once, sorted: $listed"
json_check "$out/check.json" 'j["counts"]["files"] >= 24' "fewer than 24 files found under the shared scenes"
json_check "$out/check.json" 'all(c["available"] for c in j["configurations"])' "a configuration is unavailable with EGL (every one should run here)"
# One line per file on stdout, as it goes, and the summary.
[[ $(grep -Ec '^\[ *[0-9]+/[0-9]+\] ' "$TMP/stdout") == $(python3 -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["files"]))' "$out/check.json") ]] ||
  fail "not one progress line per file: $(cat "$TMP/stdout")"
grep -Eq '^check (PASSED|FAILED): ' "$TMP/stdout" || fail "no summary line"

# What the files use (from their JSON), whatever the loader makes of them today.
file_check "$out" BoxVertexColors.gltf '"COLOR_0" in f["features"]' "COLOR_0 not detected"
file_check "$out" VertexColorTest.gltf '"COLOR_0" in f["features"]' "COLOR_0 not detected"
file_check "$out" SimpleSkin.gltf '"skins" in f["features"] and "animations" in f["features"]' "skins + animations not detected"
file_check "$out" AnimatedMorphCube.gltf '"morph-targets" in f["features"]' "morph targets not detected"
file_check "$out" SimpleSparseAccessor.gltf '"sparse-accessors" in f["features"]' "sparse accessors not detected"
file_check "$out" MeshPrimitiveModes.gltf 'set(f["features"]) >= {"points", "lines", "line-loop", "line-strip", "triangle-strip", "triangle-fan"}' "non-triangle modes not detected"
file_check "$out" MultiUVTest.gltf '"TEXCOORD_1" in f["features"]' "TEXCOORD_1 not detected"
file_check "$out" TextureTransformTest.gltf 'f["extensionsUsed"] == ["KHR_texture_transform"]' "KHR_texture_transform not listed"
file_check "$out" UnlitTest.gltf 'f["extensionsRequired"] == ["KHR_materials_unlit"]' "required KHR_materials_unlit not listed"
file_check "$out" OrientationTest.gltf 'f["features"] == [] and f["extensionsUsed"] == []' "features found in a plain file"
# Models the renderer has long supported render everywhere and agree.
for model in BoxTextured.gltf DamagedHelmet.gltf BoxInterleaved.gltf; do
  file_check "$out" "$model" 'f["status"] == "rendered" and f["parity"]["pairsCompared"] == 10' "does not render and agree on all five configurations"
done

# ---- a folder of our own: malformed, .glb, duplicate; gles unavailable (OSMesa has no GLES) ---
cp "$BOX_DIR"/* "$TMP/assets/good/"
echo '{ "asset": { "version": "2.0" }, "meshes": [ ' >"$TMP/assets/broken.gltf"
echo "notes" >"$TMP/assets/notes.txt"
python3 - "$BOX_DIR/BoxVertexColors.gltf" "$BOX_DIR/buffer.bin" "$TMP/assets/box.glb" <<'PY'
import json, struct, sys
gltf, binary = json.load(open(sys.argv[1])), open(sys.argv[2], "rb").read()
gltf["buffers"] = [{"byteLength": len(binary)}]
gltf["extensionsUsed"] = ["KHR_materials_sheen"]   # not implemented, not required: loads with a warning
text = json.dumps(gltf).encode()
text += b" " * (-len(text) % 4)
binary += b"\0" * (-len(binary) % 4)
body = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(binary), b"BIN\0") + binary
open(sys.argv[3], "wb").write(struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body)
PY
small="$TMP/small"
run_janus check "$TMP/assets" "$TMP/assets/good/BoxVertexColors.gltf" --size 32x24 --gl-platform osmesa --out "$small"
[[ $rc == 0 ]] || fail "check on a folder with a refused file and an unavailable configuration: exit $rc, expected 0; $(cat "$TMP/stdout" "$TMP/stderr")"
check_report "$small" 32 24 "$rc"
json_check "$small/check.json" '[f["path"].rsplit("/assets/", 1)[1] for f in j["files"]] == ["box.glb", "broken.gltf", "good/BoxVertexColors.gltf"]' "not the three files once each, sorted"
json_check "$small/check.json" '[f["status"] for f in j["files"]] == ["rendered", "refused", "rendered"]' "statuses are not rendered, refused, rendered"
json_check "$small/check.json" '"malformed" in j["files"][1]["reason"] and j["files"][1]["features"] == [] and j["files"][1]["featuresError"]' "the malformed file's reason or featuresError is missing"
json_check "$small/check.json" 'j["files"][0]["features"] == j["files"][2]["features"] and "COLOR_0" in j["files"][0]["features"]' "the .glb's features differ from the .gltf's"
json_check "$small/check.json" '[c["available"] for c in j["configurations"]] == [True, True, True, True, False] and "OpenGL ES" in j["configurations"][4]["reason"]' "gles/fallback is not unavailable under OSMesa, with the reason"
json_check "$small/check.json" 'all(f["configurations"][4]["status"] == "unavailable" for f in j["files"]) and all(f["parity"]["pairsCompared"] == 6 for f in j["files"] if f["status"] != "refused")' "the unavailable configuration is not skipped"
json_check "$small/check.json" 'len(j["files"][0]["warnings"]) == 1 and "KHR_materials_sheen" in j["files"][0]["warnings"][0] and j["files"][2]["warnings"] == []' "the loader's warning about the .glb's extension is not in check.json"
grep -q "^## Loader warnings" "$small/check.md" && grep -q "ignoring glTF extension 'KHR_materials_sheen'" "$small/check.md" || fail "check.md does not list the loader's warning"
[[ -e $small/contact-gles-fallback.png ]] && fail "a contact sheet was written for the unavailable gles/fallback"
grep -q "gles/fallback unavailable" "$TMP/stdout" || fail "the console does not say gles/fallback is unavailable"
grep -Eq '^\[2/3\] refused +.*broken.gltf: .*malformed' "$TMP/stdout" || fail "no progress line with the refusal: $(cat "$TMP/stdout")"

# ---- divergence: --tolerance 0 --edge-pixels 0 fails exactly when some pair differs at all ------
run_janus check "$CORNELL" --size 48x48 --tolerance 0 --edge-pixels 0 --out "$TMP/strict"
check_report "$TMP/strict" 48 48 "$rc"
differs=$(python3 -c 'import json,sys; f=json.load(open(sys.argv[1]))["files"][0]; print(int((f["parity"]["maxChannelDifference"] or 0) > 0))' "$TMP/strict/check.json" || echo unknown)
if [[ $differs == 1 ]]; then
  [[ $rc == 1 ]] || fail "a pair differs at --tolerance 0 but check exited $rc"
  json_check "$TMP/strict/check.json" 'j["files"][0]["status"] == "diverged" and j["counts"]["diverged"] == 1' "the differing file is not 'diverged'"
  grep -q "^| .* vs .* | [1-9]" "$TMP/strict/check.md" || fail "check.md lists no diverging pair"
elif [[ $differs == 0 ]]; then
  [[ $rc == 0 ]] || fail "no pair differs but check --tolerance 0 exited $rc"
else
  fail "could not read $TMP/strict/check.json"
fi

finish
