#!/usr/bin/env bash
# How the GL backends get a context: janus on a machine without OSMesa (a preload library,
# JANUS_TEST_HIDE_OSMESA_PRELOAD, set by tests/CMakeLists.txt, makes dlopen fail for libOSMesa).
source "$(dirname "$0")/common.bash" "$@"

# entry BACKEND: the python expression for that backend's entry in `janus info --json`.
entry() { echo "[b for b in j['backends'] if b['name'] == '$1'][0]"; }

# ---- without OSMesa ------------------------------------------------------------------------------
expect_success info --json
cp "$TMP/stdout" "$TMP/info.json"
if [[ -z ${JANUS_TEST_HIDE_OSMESA_PRELOAD:-} || ! -f $JANUS_TEST_HIDE_OSMESA_PRELOAD ]]; then
  fail "JANUS_TEST_HIDE_OSMESA_PRELOAD does not name the preload library (run through ctest)"
  finish
fi
hidden() { LD_PRELOAD="$JANUS_TEST_HIDE_OSMESA_PRELOAD${LD_PRELOAD:+ $LD_PRELOAD}" "$@"; }

# janus starts, and lists every backend.
hidden expect_success info --json
cp "$TMP/stdout" "$TMP/hidden-egl.json"
json_check "$TMP/hidden-egl.json" '[b["name"] for b in j["backends"]] == ["vulkan", "gl", "gles"]' \
  "without OSMesa, janus info does not list vulkan, gl, gles"
json_check "$TMP/hidden-egl.json" "$(entry gl)['available'] == $(python3 -c "import json, sys; j = json.load(open(sys.argv[1])); print($(entry gl)['available'])" "$TMP/info.json")" \
  "without OSMesa, gl on EGL is not as available as with it"

hidden expect_success info --gl-platform osmesa --json
cp "$TMP/stdout" "$TMP/hidden-osmesa.json"
json_check "$TMP/hidden-osmesa.json" '[b["name"] for b in j["backends"]] == ["vulkan", "gl", "gles"]' \
  "without OSMesa, janus info --gl-platform osmesa does not list vulkan, gl, gles"
json_check "$TMP/hidden-osmesa.json" "not $(entry gl)['available'] and 'OSMesa is not installed (libOSMesa.so.8: cannot open shared object file' in $(entry gl)['reason'] and 'install libosmesa6 or use --gl-platform egl' in $(entry gl)['reason']" \
  "without OSMesa, gl does not say that OSMesa is not installed"
json_check "$TMP/hidden-osmesa.json" "$(entry vulkan)['available'] == $(python3 -c "import json, sys; j = json.load(open(sys.argv[1])); print($(entry vulkan)['available'])" "$TMP/info.json")" \
  "without OSMesa, vulkan's availability changed"

hidden expect_error 4 "OSMesa is not installed .*install libosmesa6 or use --gl-platform egl" \
  render --backend gl --path fallback --gl-platform osmesa --size 8x8 --out "$TMP/hidden.png"
[[ -e $TMP/hidden.png ]] && fail "a render without OSMesa wrote an image"
# EGL needs no OSMesa.
hidden expect_success render --backend gl --path fallback --size 8x8 --out "$TMP/hidden-egl.png"
check_png "$TMP/hidden-egl.png" 8 8

finish
