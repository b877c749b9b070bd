#!/usr/bin/env bash
# `janus info`: lists all three backends (available or with the reason), as a table and as JSON.
source "$(dirname "$0")/common.bash" "$@"

expect_success info
for backend in vulkan gl gles; do
  grep -Eq "^  $backend: (available|unavailable)$" "$TMP/stdout" || fail "janus info does not list backend $backend"
done
# An unavailable backend must say why.
if grep -q ': unavailable$' "$TMP/stdout" && ! grep -q '^    reason: .' "$TMP/stdout"; then
  fail "janus info lists an unavailable backend without a reason"
fi
# The EGL devices section: listed by index, or said to be none.
grep -Eq '^EGL devices( \(JANUS_EGL_DEVICE=<index or name>\)$|: none listed)' "$TMP/stdout" || fail "janus info has no EGL devices section"

expect_success info --json
cp "$TMP/stdout" "$TMP/info.json"
json_check "$TMP/info.json" '[b["name"] for b in j["backends"]] == ["vulkan", "gl", "gles"]' "backends are not vulkan, gl, gles"
json_check "$TMP/info.json" 'j["glPlatform"] == "egl"' "glPlatform is not egl by default"
json_check "$TMP/info.json" 'all(isinstance(b["available"], bool) for b in j["backends"])' "'available' is not a bool"
json_check "$TMP/info.json" 'all(b["available"] or b["reason"] for b in j["backends"])' "an unavailable backend has no reason"
# The EGL devices JANUS_EGL_DEVICE can name, by index (0, 1, ...) with their names.
json_check "$TMP/info.json" 'isinstance(j["eglDevices"], list) and all(d["index"] == i and isinstance(d["names"], list) for i, d in enumerate(j["eglDevices"]))' \
  "'eglDevices' is not a list of devices by index with their names"
# Driver settings that change results (docs/ARCHITECTURE.md "Driver settings"): a string on every
# available backend, empty unless the driver is NVIDIA's GL, whose row names the variable.
json_check "$TMP/info.json" 'all(isinstance(b["driverSettings"], str) for b in j["backends"] if b["available"])' "'driverSettings' is not a string"
json_check "$TMP/info.json" 'all(b["driverSettings"] == "" or (b["name"] != "vulkan" and "__GL_OpenGLImageSettings" in b["driverSettings"]) for b in j["backends"] if b["available"])' \
  "'driverSettings' is set where no setting applies, or does not name the variable"
capabilities='["compute", "storage-buffers", "storage-images", "render-to-3d-slice", "render-to-cube-face-mip", "float-render-targets", "float32-blend", "timestamp-queries", "independent-blend", "cube-arrays", "texture-views", "concurrent-device-calls"]'
json_check "$TMP/info.json" "all(sorted(b['capabilities']) == sorted($capabilities) for b in j['backends'] if b['available'])" \
  "an available backend does not report every capability"
json_check "$TMP/info.json" 'all(b["apiVersion"] and b["device"] and b["shadingLanguage"] and b["limits"]["maxTextureSize2D"] > 0 for b in j["backends"] if b["available"])' \
  "an available backend lacks API version, device, shading language or limits"
json_check "$TMP/info.json" 'all(b["limits"]["maxTextureArrayLayers"] >= 256 for b in j["backends"] if b["available"])' \
  "an available backend reports no maxTextureArrayLayers (at least 256 on GL 4.3 / ES 3.0 / Vulkan)"
json_check "$TMP/info.json" 'all(b["limits"]["maxViewportSize"] >= 4096 and b["limits"]["viewportBoundsRange"][0] < 0 < b["limits"]["viewportBoundsRange"][1] for b in j["backends"] if b["available"])' \
  "an available backend reports no viewport limits (at least 4096, bounds around 0)"
# The format table: every format, with its kind and every format capability as a bool.
formats='["rgba8", "rgba8_srgb", "rgba16f", "rgba32f", "r11g11b10f", "r32ui", "rgba32ui", "r32f", "d32f"]'
format_caps='["sampled", "filterable", "compare-filterable", "render-target", "blendable", "storage", "copyable", "generate-mips"]'
json_check "$TMP/info.json" "all(sorted(b['formats']) == sorted($formats) for b in j['backends'] if b['available'])" \
  "an available backend does not list every format"
json_check "$TMP/info.json" "all(all(isinstance(f[c], bool) for c in $format_caps) and f['kind'] and f['bytesPerPixel'] > 0 for b in j['backends'] if b['available'] for f in b['formats'].values())" \
  "a format lacks its kind, size or a capability"
json_check "$TMP/info.json" "all(b['formats']['rgba8']['render-target'] and b['formats']['rgba8']['sampled'] for b in j['backends'] if b['available'])" \
  "rgba8 is not reported renderable and sampled"

# With the table: when any backend starts, the capability table lists every capability.
run_janus info
if grep -q ': available$' "$TMP/stdout"; then
  for capability in compute storage-buffers storage-images render-to-3d-slice render-to-cube-face-mip float-render-targets float32-blend timestamp-queries independent-blend cube-arrays texture-views concurrent-device-calls; do
    grep -Eq "^  $capability +" "$TMP/stdout" || fail "janus info capability table lacks $capability"
  done
  for backend in vulkan gl gles; do
    if grep -q "^  $backend: available$" "$TMP/stdout"; then
      grep -q "^Formats on $backend " "$TMP/stdout" || fail "janus info prints no format table for $backend"
    fi
  done
  grep -Eq "^  d32f +depth +4 " "$TMP/stdout" || fail "janus info format table lacks d32f (kind, size)"
  grep -Eq "^  max texture array layers +[0-9]" "$TMP/stdout" || fail "janus info limits table lacks max texture array layers"
  grep -Eq "^  viewport bounds +\[-[0-9]" "$TMP/stdout" || fail "janus info limits table lacks the viewport bounds"
fi

expect_success info --gl-platform osmesa --json
cp "$TMP/stdout" "$TMP/info-osmesa.json"
json_check "$TMP/info-osmesa.json" 'j["glPlatform"] == "osmesa" and len(j["backends"]) == 3' "--gl-platform osmesa is not reported"

finish
