#!/usr/bin/env bash
# How the GL backends get a context (docs/CLI.md, "Environment variables"): the EGL display named
# in `janus info`, JANUS_EGL_PLATFORM / JANUS_EGL_DEVICE, and janus on a machine without OSMesa
# (a preload library, JANUS_TEST_HIDE_OSMESA_PRELOAD, set by tests/CMakeLists.txt, makes dlopen
# fail for libOSMesa).
source "$(dirname "$0")/common.bash" "$@"

# entry BACKEND: the python expression for that backend's entry in `janus info --json`.
entry() { echo "[b for b in j['backends'] if b['name'] == '$1'][0]"; }

# ---- the EGL display is named ------------------------------------------------------------------
expect_success info --json
cp "$TMP/stdout" "$TMP/info.json"
json_check "$TMP/info.json" "all(b['platform'] == 'egl (surfaceless)' or b['platform'].startswith('egl (device ') or b['platform'] == 'egl (default display)' for b in j['backends'] if b['name'] != 'vulkan' and b['available'])" \
  "an available GL backend does not name its EGL display"
run_janus info
if grep -q '^  gl: available$' "$TMP/stdout"; then
  grep -Eq '^    platform +egl \((surfaceless|device [0-9]+: .+|default display)\)$' "$TMP/stdout" \
    || fail "janus info does not print the EGL display: $(grep platform "$TMP/stdout")"
fi

# ---- JANUS_EGL_PLATFORM forces one display ---------------------------------------------------------
# Forced displays either start (and say so) or are unavailable saying why; never another display.
JANUS_EGL_PLATFORM=surfaceless expect_success info --json
cp "$TMP/stdout" "$TMP/surfaceless.json"
json_check "$TMP/surfaceless.json" "all((b['platform'] == 'egl (surfaceless)') if b['available'] else ('surfaceless' in b['reason']) for b in j['backends'] if b['name'] != 'vulkan')" \
  "JANUS_EGL_PLATFORM=surfaceless gave another display or an unexplained failure"

JANUS_EGL_PLATFORM=device expect_success info --json
cp "$TMP/stdout" "$TMP/device.json"
json_check "$TMP/device.json" "all((b['platform'].startswith('egl (device ')) if b['available'] else ('device' in b['reason']) for b in j['backends'] if b['name'] != 'vulkan')" \
  "JANUS_EGL_PLATFORM=device gave another display or an unexplained failure"
# Mesa offers a software device even without a GPU: where it is listed, the device display must render.
if python3 -c "import json, sys; j = json.load(open(sys.argv[1])); sys.exit(0 if $(entry gl)['available'] else 1)" "$TMP/device.json"; then
  JANUS_EGL_PLATFORM=device expect_success render --backend gl --path fallback --size 16x8 --out "$TMP/device-gl.png"
  check_png "$TMP/device-gl.png" 16 8
  JANUS_EGL_PLATFORM=device expect_success render --backend gles --path fallback --size 16x8 --out "$TMP/device-gles.png"
  check_png "$TMP/device-gles.png" 16 8
  JANUS_EGL_DEVICE=0 expect_success info --json
  cp "$TMP/stdout" "$TMP/device0.json"
  json_check "$TMP/device0.json" "$(entry gl)['platform'].startswith('egl (device 0: ')" "JANUS_EGL_DEVICE=0 did not pick device 0"
  # Mesa's software device answers to "software" (janus info names it "... software renderer").
  if grep -q "software renderer" "$TMP/device0.json"; then
    JANUS_EGL_DEVICE=software expect_success render --backend gles --path fallback --size 16x8 --out "$TMP/software-gles.png"
    check_png "$TMP/software-gles.png" 16 8
  fi
else
  echo "note: this EGL has no usable device display: $(python3 -c "import json, sys; j = json.load(open(sys.argv[1])); print($(entry gl)['reason'])" "$TMP/device.json")"
fi
JANUS_EGL_DEVICE=4096 expect_error 4 "JANUS_EGL_DEVICE=4096|EGL_EXT_platform_device" render --backend gl --path fallback --size 8x8 --out "$TMP/no-device.png"
# By name: a name no device has is an error listing the devices' names (exit 4: backend unavailable).
JANUS_EGL_DEVICE=renderD999 expect_error 4 "JANUS_EGL_DEVICE='renderD999' names no EGL device|EGL_EXT_platform_device" \
  render --backend gl --path fallback --size 8x8 --out "$TMP/no-named-device.png"

# A value janus does not know: GL is unavailable naming the variable, Vulkan is unaffected.
JANUS_EGL_PLATFORM=wayland expect_success info --json
cp "$TMP/stdout" "$TMP/bad-platform.json"
json_check "$TMP/bad-platform.json" "not $(entry gl)['available'] and 'JANUS_EGL_PLATFORM' in $(entry gl)['reason']" \
  "an unknown JANUS_EGL_PLATFORM does not make gl unavailable naming it"
JANUS_EGL_PLATFORM=wayland expect_error 4 "JANUS_EGL_PLATFORM='wayland'" render --backend gl --path fallback --size 8x8 --out "$TMP/bad.png"

# ---- without OSMesa ------------------------------------------------------------------------------
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
