#!/usr/bin/env bash
# Requests that once crashed, exited 5 (internal error) or gave the wrong exit code, found by
# exploratory testing: each case names the problem with the right exit code. Needs the backends
# for a few cases; tiny sizes, a few seconds on llvmpipe.
source "$(dirname "$0")/common.bash" "$@"

SCENES="$REPO_ROOT/../shared/scenes"
BOX="$SCENES/BoxTextured/glTF"

# ---- tile lists beyond the device's storage buffer range: exit 4 with the options to change -----
# 192x192 tiles x (1 + 1024) entries x 4 bytes = 151 MB: above llvmpipe's 128 MiB storage buffer
# range (compute) and its largest data texture (fallback). Was exit 5 on the compute path.
for config in vulkan:compute gl:compute vulkan:fallback; do
  expect_error 4 "tile light lists .*; use larger tiles or a smaller maxLightsPerTile \\(janus: --tile-size, --max-lights-per-tile\\)" \
    render many-lights:8 --backend "${config%%:*}" --path "${config##*:}" --size 3072x3072 --max-lights-per-tile 1024 \
    --out "$TMP/big.png"
done
[[ -e $TMP/big.png ]] && fail "a refused render wrote its image"

# ---- a write past the file size limit: exit 3 saying so, and no temporary file ---------------------
# janus ignores SIGXFSZ, so the write fails with EFBIG and the error path removes the temporary
# file; before, the signal killed janus (exit 153) and ".a.pfm.tmp-XXXXXX" stayed behind.
mkdir -p "$TMP/limited"
rc=0
(ulimit -f 8 && exec "$JANUS" render --size 128x128 --out "$TMP/limited/a.png" --hdr "$TMP/limited/a.pfm") \
  >"$TMP/stdout" 2>"$TMP/stderr" || rc=$?
[[ $rc == 3 ]] || fail "a write past ulimit -f: exit $rc, expected 3: $(cat "$TMP/stderr")"
grep -q "cannot write '.*/a.pfm': File too large after .* bytes; the file size limit (ulimit -f) is below what the file needs" \
  "$TMP/stderr" || fail "a write past ulimit -f does not say so: $(cat "$TMP/stderr")"
leftover=$(find "$TMP/limited" -name '.*tmp*')
[[ -z $leftover ]] || fail "a write past ulimit -f left $leftover"

# ---- a folder named like a built-in scene does not hide it (only a file of that name wins) -------
# Before, a folder "probes" in the working directory (say, for output) made `render probes` fail
# with "scene 'probes' is a directory".
mkdir -p "$TMP/cwd/probes"
rc=0
(cd "$TMP/cwd" && exec "$JANUS" render probes --size 16x16 --out probes/p.png) >"$TMP/stdout" 2>"$TMP/stderr" || rc=$?
[[ $rc == 0 ]] || fail "render probes beside a folder named probes: exit $rc: $(cat "$TMP/stderr")"
check_png "$TMP/cwd/probes/p.png" 16 16

# ---- paths that are not valid UTF-8 are escaped in JSON (check / parity exited 5) ---------------
bad=$'bad\xffname'
mkdir -p "$TMP/utf"
cp "$BOX/BoxTextured0.bin" "$BOX/CesiumLogoFlat.png" "$TMP/utf/"
cp "$BOX/BoxTextured.gltf" "$TMP/utf/$bad.gltf"
expect_success check "$TMP/utf" --size 16x16 --out "$TMP/check-utf"
json_check "$TMP/check-utf/check.json" 'j["files"][0]["path"].endswith("/bad\\xFFname.gltf") and j["counts"]["rendered"] == 1' \
  "check.json does not name the file with its invalid byte escaped"
run_janus parity "$TMP/utf/$bad.gltf" --size 16x16 --out "$TMP/parity-utf"
[[ $rc == 0 || $rc == 1 ]] || fail "parity on a non-UTF-8 path: exit $rc: $(cat "$TMP/stderr")"
json_check "$TMP/parity-utf/parity.json" 'j["scene"].endswith("/bad\\xFFname.gltf")' \
  "parity.json does not name the scene with its invalid byte escaped"

# ---- outputs never overwrite each other or an input: exit 2 before anything renders -------------
mkdir -p "$TMP/box" "$TMP/cornell"
cp "$BOX"/* "$TMP/box/"
cp "$SCENES/cornell-box/"* "$TMP/cornell/"
B=$TMP/box/BoxTextured.gltf
cp "$B" "$TMP/box-before.gltf"
expect_error 2 "--out '.*/a.png' and --report '.*/a.png' are the same file" render --size 8x8 --out "$TMP/a.png" --report "$TMP/a.png"
expect_error 2 "--hdr '.*/h.pfm' and --report '.*/./h.pfm' are the same file" \
  render --size 8x8 --out "$TMP/a.png" --hdr "$TMP/h.pfm" --report "$TMP/./h.pfm"
touch "$TMP/target.png"
ln -s target.png "$TMP/link.png"
expect_error 2 "--out '.*/link.png' and --report '.*/target.png' are the same file" \
  render --size 8x8 --out "$TMP/link.png" --report "$TMP/target.png"
expect_error 2 "--report '.*/BoxTextured.gltf' is the scene file" render "$B" --size 8x8 --out "$TMP/a.png" --report "$B"
expect_error 2 "--report '.*/BoxTextured0.bin' is a file the glTF reads" render "$B" --size 8x8 --out "$TMP/a.png" --report "$TMP/box/BoxTextured0.bin"
expect_error 2 "--out '.*/CesiumLogoFlat.png' is a file the glTF reads" render "$B" --size 8x8 --out "$TMP/box/CesiumLogoFlat.png"
cp "$SCENES/env/chinese_garden_1k.hdr" "$TMP/sky.hdr"
expect_error 2 "--report '.*/sky.hdr' is the --env file" render --size 8x8 --env "$TMP/sky.hdr" --out "$TMP/a.png" --report "$TMP/sky.hdr"
echo '{"gltf": "box/BoxTextured.gltf"}' >"$TMP/scene.json"
expect_error 2 "--report '.*/BoxTextured.gltf' is the scene's glTF" render "$TMP/scene.json" --size 8x8 --out "$TMP/a.png" --report "$B"
expect_error 2 "--report '.*/scene.json' is the scene file" render "$TMP/scene.json" --size 8x8 --out "$TMP/a.png" --report "$TMP/scene.json"
expect_error 2 "--out '.*/cornellBox.gltf' is the scene file" bake "$TMP/cornell/cornellBox.gltf" --out "$TMP/cornell/cornellBox.gltf"
expect_error 2 "--out '.*/cornellBox.bin' is a file the glTF reads" bake "$TMP/cornell/cornellBox.gltf" --out "$TMP/cornell/cornellBox.bin"
cmp -s "$B" "$TMP/box-before.gltf" || fail "a refused render changed its input scene"
[[ -e $TMP/a.png ]] && fail "a refused render wrote --out"
cmp -s "$TMP/cornell/cornellBox.bin" "$SCENES/cornell-box/cornellBox.bin" || fail "a refused bake changed the scene's buffer"

# Commands that write a folder (parity, check, bench gi) refuse an --out where a file they would
# write or replace is one they read. Before, parity deleted a texture named like its images
# before it rendered, and check and bench gi wrote over such files.
mkdir -p "$TMP/named"
cp "$BOX/BoxTextured0.bin" "$TMP/named/"
cp "$BOX/CesiumLogoFlat.png" "$TMP/named/vulkan-compute.png"
cp "$BOX/CesiumLogoFlat.png" "$TMP/named/contact-gl-fallback.png"
sed 's/CesiumLogoFlat.png/vulkan-compute.png/' "$BOX/BoxTextured.gltf" >"$TMP/named/parity-box.gltf"
sed 's/CesiumLogoFlat.png/contact-gl-fallback.png/' "$BOX/BoxTextured.gltf" >"$TMP/named/check-box.gltf"
expect_error 2 "--out '.*/named' would overwrite '.*/named/vulkan-compute.png', which is a file the glTF reads" \
  parity "$TMP/named/parity-box.gltf" --size 8x8 --out "$TMP/named"
cmp -s "$TMP/named/vulkan-compute.png" "$BOX/CesiumLogoFlat.png" || fail "a refused parity removed or changed the scene's texture"
[[ -e $TMP/named/parity.json ]] && fail "a refused parity wrote parity.json"
expect_error 2 "--out '.*/named' would overwrite '.*/named/contact-gl-fallback.png', which is a file '.*/check-box.gltf' reads" \
  check "$TMP/named" --size 8x8 --out "$TMP/named"
cmp -s "$TMP/named/contact-gl-fallback.png" "$BOX/CesiumLogoFlat.png" || fail "a refused check changed a scene's texture"
[[ -e $TMP/named/check.json ]] && fail "a refused check wrote check.json"
mkdir -p "$TMP/gi-named"
printf '{"gltf": "%s", "irradianceVolume": {"probes": 2}}\n' "$SCENES/cornell-box/cornellBox.gltf" >"$TMP/gi-named/gi.json"
cp "$TMP/gi-named/gi.json" "$TMP/gi-before.json"
expect_error 2 "--out '.*/gi-named' would overwrite '.*/gi-named/gi.json', which is the scene file" \
  bench gi "$TMP/gi-named/gi.json" --quick --out "$TMP/gi-named"
cmp -s "$TMP/gi-named/gi.json" "$TMP/gi-before.json" || fail "a refused bench gi changed its scene file"
# A folder that shares no file with the inputs is fine, also when it holds the scene.
expect_success parity "$TMP/named/check-box.gltf" --size 8x8 --out "$TMP/named"

# ---- inputs that are not regular files: exit 3 naming the file, never a hang or unbounded read ---
ln -s /dev/zero "$TMP/zero.gltf"
mkfifo "$TMP/fifo.gltf" "$TMP/fifo.json" "$TMP/fifo.hdr"
expect_error 3 "PATH '.*/zero.gltf' is a character device, not a regular file" check "$TMP/zero.gltf" --out "$TMP/never"
expect_error 3 "PATH '.*/fifo.gltf' is a FIFO, not a regular file" check "$TMP/fifo.gltf" --out "$TMP/never"
expect_error 3 "scene '.*/zero.gltf' is a character device, not a regular file" render "$TMP/zero.gltf" --out "$TMP/a.png"
expect_error 3 "scene '.*/fifo.json' is a FIFO, not a regular file" render "$TMP/fifo.json" --out "$TMP/a.png"
expect_error 3 "scene '.*/fifo.gltf' is a FIFO" parity "$TMP/fifo.gltf" --out "$TMP/never"
expect_error 3 "scene '.*/fifo.gltf' is a FIFO" bake "$TMP/fifo.gltf" --out "$TMP/x.bake"
expect_error 3 "--env '.*/fifo.hdr' is a FIFO, not a regular file" render --env "$TMP/fifo.hdr" --out "$TMP/a.png"
echo '{"gltf": "zero.gltf"}' >"$TMP/zero-scene.json"
expect_error 3 "zero.gltf: not a regular file" render "$TMP/zero-scene.json" --out "$TMP/a.png"
[[ -e $TMP/never ]] && fail "a refused check or parity created --out"

# ---- bad input in files is exit 3 (or 2 for conflicting options), before any device opens --------
echo "this is not a Radiance HDR image" >"$TMP/fake.hdr"
expect_error 3 "environment map '.*/fake.hdr' \\(given by --env\\) cannot be read" render "$B" --env "$TMP/fake.hdr" --size 8x8 --out "$TMP/a.png"
expect_error 3 "environment map '.*/fake.hdr' \\(given by --env\\) cannot be read" parity "$B" --env "$TMP/fake.hdr" --size 8x8 --out "$TMP/never"
expect_error 3 "environment map '.*/fake.hdr' \\(given by --env\\) cannot be read" check "$B" --env "$TMP/fake.hdr" --size 8x8 --out "$TMP/never"
echo '{"gltf": "box/BoxTextured.gltf", "environment": {"map": "fake.hdr"}}' >"$TMP/fake-sky.json"
expect_error 3 "environment map '.*/fake.hdr' \\(the \"environment.map\" of .*/fake-sky.json\\) cannot be read" \
  render "$TMP/fake-sky.json" --size 8x8 --out "$TMP/a.png"
for quality in '"lightCulling": "bogus"' '"tileSize": 7' '"maxLightsPerTile": 0' '"maxLightsPerTile": "many"' '"shadowMapSize": -5' '"intensityCutoff": -1' '"msaa": 3' '"msaa": "4x"' '"alphaToCoverage": 1'; do
  key=${quality%%\":*}
  key=${key#\"}
  echo "{\"gltf\": \"box/BoxTextured.gltf\", \"quality\": {$quality}}" >"$TMP/quality.json"
  expect_error 3 "scene: .*/quality.json: \"quality\": .*$key" render "$TMP/quality.json" --size 8x8 --out "$TMP/a.png"
done
python3 - "$TMP/lights.json" <<'PY'
import json, sys
lights = [{"type": "point", "position": [i % 100 * 0.01, 0.5, i // 100 * 0.01], "intensity": 1.0} for i in range(20000)]
json.dump({"gltf": "box/BoxTextured.gltf", "lights": lights}, open(sys.argv[1], "w"))
PY
expect_error 3 "lights.json: the scene has 20000 point/spot lights that light something; at most 16384" render "$TMP/lights.json" --out "$TMP/a.png"
expect_error 2 "--intensity-cutoff 0 gives lights without a range an infinite range.*tiles-depth; use --culling naive" \
  render many-lights:8 --intensity-cutoff 0 --culling tiles-depth --out "$TMP/a.png"
echo '{"gltf": "box/BoxTextured.gltf", "quality": {"intensityCutoff": 0}}' >"$TMP/cutoff0.json"
expect_error 2 "\"quality\".\"intensityCutoff\" 0 .* but --culling is tiles-2d; use --culling naive" \
  render "$TMP/cutoff0.json" --culling tiles-2d --out "$TMP/a.png"
[[ -e $TMP/a.png ]] && fail "a refused render wrote --out"

# ---- --gi-bake and --debug gi on a scene without an irradiance volume --------------------------
echo "not a bake" >"$TMP/other.bake"
expect_error 3 "--gi-bake '.*/other.bake': .*BoxTextured.gltf has no irradiance volume" render "$B" --gi-bake "$TMP/other.bake" --size 8x8 --out "$TMP/a.png"
expect_success render "$B" --debug gi --size 8x8 --out "$TMP/gi.png"
grep -q "warning: no GI to show: .* has no irradiance volume" "$TMP/stderr" || fail "--debug gi without a volume does not warn: $(cat "$TMP/stderr")"

# ---- extensions in any case ---------------------------------------------------------------------
cp "$B" "$TMP/box/UPPER.GLTF"
expect_success render "$TMP/box/UPPER.GLTF" --size 8x8 --out "$TMP/upper.png"
echo '{"gltf": "box/UPPER.GLTF"}' >"$TMP/UPPER.JSON"
expect_success render "$TMP/UPPER.JSON" --size 8x8 --out "$TMP/upper-json.png"
python3 - "$B" "$TMP/box/BoxTextured0.bin" "$TMP/box/UPPER.GLB" <<'PY'
import json, struct, sys
gltf, binary = json.load(open(sys.argv[1])), open(sys.argv[2], "rb").read()
gltf["buffers"] = [{"byteLength": len(binary)}]
text = json.dumps(gltf).encode()
text += b" " * (-len(text) % 4)
binary += b"\0" * (-len(binary) % 4)
body = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(binary), b"BIN\0") + binary
open(sys.argv[3], "wb").write(struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body)
PY
expect_success render "$TMP/box/UPPER.GLB" --size 8x8 --out "$TMP/upper-glb.png"
expect_success check "$TMP/box/UPPER.GLB" "$TMP/box/UPPER.GLTF" --size 8x8 --out "$TMP/check-upper"
json_check "$TMP/check-upper/check.json" 'j["counts"]["rendered"] == 2 and j["counts"]["refused"] == 0' "check refused an upper-case .GLB / .GLTF"

# ---- messages name the key and the real problem -------------------------------------------------
echo '{"gltf": "box/BoxTextured.gltf", "name": 5}' >"$TMP/name.json"
expect_error 3 "name.json: \"name\" must be a string, got 5" render "$TMP/name.json" --out "$TMP/a.png"
echo '{"gltf": "box/BoxTextured.gltf", "defaultLight": "no"}' >"$TMP/default-light.json"
expect_error 3 "default-light.json: \"defaultLight\" must be true or false, got \"no\"" render "$TMP/default-light.json" --out "$TMP/a.png"
python3 - "$B" "$TMP/box/huge.gltf" <<'PY'
import json, sys
gltf = json.load(open(sys.argv[1]))
for node in gltf["nodes"]:
    if "mesh" in node:
        node["scale"] = [1e30, 1e30, 1e30]   # finite, but the bounds' extent overflows float
json.dump(gltf, open(sys.argv[2], "w"))
PY
expect_error 3 "huge.gltf: the scene is too large to frame with a camera" render "$TMP/box/huge.gltf" --out "$TMP/a.png"

finish
