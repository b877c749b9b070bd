#!/usr/bin/env bash
# `janus render` on the built-in scene: PNG, HDR (EXR and PFM) and JSON report on every backend,
# and the compute path on gles refused with the capability named. Needs the backends.
source "$(dirname "$0")/common.bash" "$@"

# Default configuration (vulkan/compute) with every output, under validation.
expect_success render --size 64x48 --out "$TMP/vulkan.png" --hdr "$TMP/vulkan.exr" --report "$TMP/vulkan.json" --validation
check_png "$TMP/vulkan.png" 64 48
grep -q "vulkan.png" "$TMP/stdout" || fail "render does not say where the PNG went"
grep -Eq "^  view +pass +GPU ms +CPU ms +draws +dispatches$" "$TMP/stdout" || fail "render prints no per-pass summary"
grep -Eq "^  main +forward " "$TMP/stdout" || fail "the per-pass summary does not name the view of each pass"
json_check "$TMP/vulkan.json" 'j["backend"] == "vulkan" and j["path"] == "compute" and j["width"] == 64 and j["height"] == 48' \
  "report does not describe vulkan/compute at 64x48"
json_check "$TMP/vulkan.json" 'len(j["passes"]) > 0 and all(p["name"] and p["cpuMs"] >= 0 for p in j["passes"])' "report has no passes"
json_check "$TMP/vulkan.json" 'sum(p["dispatches"] for p in j["passes"]) > 0' "the compute path ran no dispatch"
json_check "$TMP/vulkan.json" '[v["name"] for v in j["views"]] == ["main"] and all(p["view"] == ("" if p["name"] == "shadow-map" else "main") for p in j["passes"])' "report does not list the main view and the view of every pass"
if [[ ! -f $TMP/vulkan.exr ]] || [[ $(head -c 4 "$TMP/vulkan.exr" | od -An -tx1 | tr -d ' ') != 762f3101 ]]; then
  fail "--hdr did not write an OpenEXR file"
fi

# Every other configuration the project supports renders too.
for config in vulkan:fallback gl:compute gl:fallback gles:fallback; do
  backend=${config%%:*}
  path=${config##*:}
  expect_success render --backend "$backend" --path "$path" --size 32x32 --out "$TMP/$backend-$path.png" --report "$TMP/$backend-$path.json"
  check_png "$TMP/$backend-$path.png" 32 32
  json_check "$TMP/$backend-$path.json" "j['backend'] == '$backend' and j['path'] == '$path'" "report names the wrong configuration"
done

# --allow-outside-paths lets a glTF read a buffer outside its folder (input_errors.sh: refused without).
boxdir="$REPO_ROOT/../shared/scenes/BoxTextured/glTF"
mkdir "$TMP/models"
cp "$boxdir/BoxTextured0.bin" "$TMP/"
cp "$boxdir/CesiumLogoFlat.png" "$TMP/models/"
sed 's|"BoxTextured0.bin"|"../BoxTextured0.bin"|' "$boxdir/BoxTextured.gltf" >"$TMP/models/outside.gltf"
expect_success render "$TMP/models/outside.gltf" --allow-outside-paths --size 16x16 --out "$TMP/outside.png"
check_png "$TMP/outside.png" 16 16

# PFM: "PF", the size, a negative (little-endian) scale, then 3 floats per pixel.
expect_success render --backend gl --path fallback --size 16x8 --out "$TMP/pfm.png" --hdr "$TMP/hdr.pfm"
problem=$(python3 - "$TMP/hdr.pfm" <<'PY'
import os, sys
data = open(sys.argv[1], "rb").read() if os.path.exists(sys.argv[1]) else b""
header = b"PF\n16 8\n-1.0\n"
if not data.startswith(header):
    print("bad header", data[:16])
elif len(data) != len(header) + 16 * 8 * 3 * 4:
    print("wrong length", len(data))
PY
)
[[ -z $problem ]] || fail "PFM: $problem"

# The other GL platform: desktop GL renders through OSMesa; OSMesa has no GLES, which is exit 4.
expect_success render --backend gl --path fallback --gl-platform osmesa --size 24x16 --out "$TMP/osmesa.png"
check_png "$TMP/osmesa.png" 24 16
expect_error 4 "OpenGL ES|gles" render --backend gles --path fallback --gl-platform osmesa --size 16x16 --out "$TMP/gles-osmesa.png"

# The compute path on gles: exit 4, naming the capability and the way out.
expect_error 4 "gles.*'compute'.*--path fallback" render --backend gles --path compute --size 16x16 --out "$TMP/gles-compute.png"
[[ ! -e $TMP/gles-compute.png ]] || fail "a refused render wrote its PNG"

finish

# --msaa: the samples resolved before the tonemap (the report's msaa-resolve pass), on gles too;
# a count no target allows is exit 4 naming the counts, one that is no count a usage error; tiled
# culling with depth bounds cannot read multisampled depth (exit 4 naming tiles-2d).
expect_success render --size 32x32 --msaa 4 --out "$TMP/msaa.png" --report "$TMP/msaa.json" --validation
check_png "$TMP/msaa.png" 32 32
json_check "$TMP/msaa.json" '"msaa-resolve" in [p["name"] for p in j["passes"]] and j["msaaSamples"] == 4' "--msaa 4 ran no msaa-resolve pass or its report does not say 4 samples"
expect_success render --backend gles --path fallback --size 32x32 --msaa 4 --out "$TMP/msaa-gles.png" --report "$TMP/msaa-gles.json"
json_check "$TMP/msaa-gles.json" '"msaa-resolve" in [p["name"] for p in j["passes"]]' "--msaa 4 on gles ran no msaa-resolve pass"
expect_error 2 "--msaa '3' is not allowed" render --size 16x16 --msaa 3 --out "$TMP/msaa3.png"
# --frames: the report is the last frame's (a static scene draws its shadow map in the first only).
expect_success render --size 16x16 --frames 3 --out "$TMP/frames.png" --report "$TMP/frames.json"
json_check "$TMP/frames.json" '"shadow-map" not in [p["name"] for p in j["passes"]] and "forward" in [p["name"] for p in j["passes"]] and j["frames"] == 3' \
  "--frames 3 should report the third frame, which draws no shadow map"
grep -q "frames: 3 (--frames" "$TMP/stdout" || fail "--frames 3 did not say how many frames ran: $(cat "$TMP/stdout")"
json_check "$TMP/msaa.json" '"shadow-map" in [p["name"] for p in j["passes"]] and j["frames"] == 1' "one frame should report the shadow map's first drawing"
expect_error 2 "--frames 0 is not allowed; render 1..1000 frames" render --size 16x16 --frames 0 --out "$TMP/frames0.png"
# --alpha-to-coverage: on by default with samples (the report says so), off on request, nothing else.
json_check "$TMP/msaa.json" 'j["alphaToCoverage"] is True' "alpha to coverage should be on by default with --msaa 4"
expect_success render --size 16x16 --msaa 4 --alpha-to-coverage off --out "$TMP/a2c-off.png" --report "$TMP/a2c-off.json"
json_check "$TMP/a2c-off.json" 'j["alphaToCoverage"] is False' "--alpha-to-coverage off was not followed"
expect_success render --size 16x16 --alpha-to-coverage on --out "$TMP/a2c-one.png" --report "$TMP/a2c-one.json"
json_check "$TMP/a2c-one.json" 'j["alphaToCoverage"] is False and j["msaaSamples"] == 1' "alpha to coverage cannot apply with one sample"
expect_error 2 "--alpha-to-coverage 'maybe' is not allowed; use on or off" render --size 16x16 --msaa 4 --alpha-to-coverage maybe --out "$TMP/a2c.png"
expect_success info --json
max_samples=$(python3 -c "import json,sys; j=json.load(open('$TMP/stdout')); print(max(max(b['formats']['rgba16f']['sampleCounts']) for b in j['backends'] if b['available']))")
if (( max_samples < 16 )); then
  expect_error 4 "msaa 16 is not possible on this vulkan device: .* allow 1, " render --size 16x16 --msaa 16 --out "$TMP/msaa16.png"
fi
expect_error 4 "tiles-depth.*tiles-2d" render many-lights --culling tiles-depth --msaa 4 --size 16x16 --out "$TMP/msaa-depth.png"

# --probe-msaa: every probe's capture takes the samples (the update rows and the capture views say
# so, and each face resolves), the main view keeps one; a bad count is a usage error, a count the
# device lacks exit 4 naming the flag.
expect_success render probes --size 32x24 --probe-msaa 4 --out "$TMP/probe-msaa.png" --report "$TMP/probe-msaa.json" --validation
grep -q "nothing to do" "$TMP/stderr" && fail "a scene with probes should not be told --probe-msaa does nothing"
json_check "$TMP/probe-msaa.json" 'j["probeUpdates"] and all(u["msaaSamples"] == 4 for u in j["probeUpdates"]) and j["msaaSamples"] == 1' "--probe-msaa 4 did not reach every probe update (or changed the main view)"
grep -q "samples" "$TMP/stdout" || fail "the probe update table has no samples column"
expect_success render probes --size 32x24 --out "$TMP/probe-one.png" --report "$TMP/probe-one.json"
json_check "$TMP/probe-one.json" 'all(u["msaaSamples"] == 1 for u in j["probeUpdates"]) and all(v["samples"] == 1 for v in j["views"])' "probes take one sample unless asked"
expect_error 2 "--probe-msaa '6' is not allowed; use 1, 2, 4, 8 or 16" render probes --size 16x16 --probe-msaa 6 --out "$TMP/probe6.png"
expect_success render --size 16x16 --probe-msaa 4 --out "$TMP/no-probes.png"
grep -q "warning: probe msaa 4 has nothing to do: scene '.*' has no reflection probes" "$TMP/stderr" ||
  fail "--probe-msaa on a scene without probes should say it does nothing: $(cat "$TMP/stderr")"
if (( max_samples < 16 )); then
  expect_error 4 "probe msaa 16 is not possible on this vulkan device" render probes --size 16x16 --probe-msaa 16 --out "$TMP/probe16.png"
fi
