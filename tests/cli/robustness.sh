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

finish
