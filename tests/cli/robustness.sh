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

finish
