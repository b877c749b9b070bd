#!/usr/bin/env bash
# Forward+ flags of `janus render` / `janus parity` on the built-in many-lights scene: the
# light-culling line, the JSON report's lightCulling object, the heat-map debug view, and usage
# errors that name the flag and its allowed values. Needs the backends.
source "$(dirname "$0")/common.bash" "$@"

# Usage errors first (no device needed): each names the flag and what is allowed.
expect_error 2 "--culling 'bogus' is not a culling mode; use auto, naive, tiles-2d or tiles-depth" \
  render --culling bogus --out "$TMP/x.png"
expect_error 2 "--tile-size '20' is not allowed; use 16, 32, 64, 128 or 256" render --tile-size 20 --out "$TMP/x.png"
expect_error 2 "--max-lights-per-tile '0' is not allowed; use a whole number 1..1024 or auto" \
  render --max-lights-per-tile 0 --out "$TMP/x.png"
expect_error 2 "--intensity-cutoff '-1' is not allowed" render --intensity-cutoff -1 --out "$TMP/x.png"
expect_error 2 "--debug 'heat' is not a debug view; use none, tiles, gi, gi-light or shadow" render --debug heat --out "$TMP/x.png"
expect_error 2 "many-lights scene takes a light count 0..16384" render many-lights:lots --out "$TMP/x.png"
expect_error 2 "--culling 'x' is not a culling mode" parity --culling x --out "$TMP/parity"

# Tiled, depth-aware, on the CPU builder: the culling line and the report say so.
expect_success render many-lights:64 --path fallback --culling tiles-depth --tile-size 32 --size 64x64 \
  --out "$TMP/tiles.png" --report "$TMP/tiles.json" --validation
grep -Eq "light culling: tiles-depth \(cpu builder\), 64 local \+ 1 directional lights, 2x2 tiles of 32 px" "$TMP/stdout" ||
  fail "render printed no (or a wrong) light-culling line: $(grep 'light culling' "$TMP/stdout")"
json_check "$TMP/tiles.json" 'j["lightCulling"]["localLights"] == 64 and j["lightCulling"]["tileSize"] == 32' \
  "report has no lightCulling object for 64 lights and 32 px tiles"
# The default list cap is automatic: the light count, so no tile can drop one; the line says so.
grep -Eq "2x2 tiles of 32 px, cap 64 \(auto\), .*no overflow" "$TMP/stdout" ||
  fail "the culling line does not show the automatic cap: $(grep 'light culling' "$TMP/stdout")"
json_check "$TMP/tiles.json" 'j["lightCulling"]["maxLightsPerTile"] == 64 and j["lightCulling"]["maxLightsPerTileAuto"]' \
  "the report does not show the automatic cap of 64"
# --max-lights-per-tile auto asks for it by name (a scene file's "quality" may set a number).
expect_success render many-lights:64 --path fallback --culling tiles-depth --size 64x64 --out "$TMP/auto.png" \
  --max-lights-per-tile auto --report "$TMP/auto.json"
json_check "$TMP/auto.json" 'j["lightCulling"]["maxLightsPerTile"] == 64 and j["lightCulling"]["maxLightsPerTileAuto"]' \
  "--max-lights-per-tile auto did not give the automatic cap"

# Naive: no tiles in the line.
expect_success render many-lights:8 --culling naive --size 32x32 --out "$TMP/naive.png" --no-shadows
grep -Eq "light culling: naive, 8 local" "$TMP/stdout" || fail "naive culling line missing"

# The heat map differs from the shaded image.
expect_success render many-lights:64 --path fallback --culling tiles-2d --size 64x64 --out "$TMP/heat.png" --debug tiles
check_png "$TMP/heat.png" 64 64
cmp -s "$TMP/heat.png" "$TMP/tiles.png" && fail "--debug tiles wrote the same image as the shaded render"

# Parity takes the same flags.
expect_success parity many-lights:32 --culling tiles-depth --size 32x32 --out "$TMP/parity"
finish
