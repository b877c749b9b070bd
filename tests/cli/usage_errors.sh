#!/usr/bin/env bash
# Help texts and usage errors (exit 2). Needs no backend: every case fails before a device opens.
source "$(dirname "$0")/common.bash" "$@"

# --help for janus and every command: exit 0, a usage line, and the exit-code table.
for command in "" info render parity bench "bench forward"; do
  # shellcheck disable=SC2086  # the empty command must vanish
  run_janus $command --help
  if [[ $rc != 0 ]]; then fail "janus $command --help: exit $rc"; fi
  grep -q '^Usage: ' "$TMP/stdout" || fail "janus $command --help: no 'Usage:' line"
  for code in 0 1 2 3 4 5; do
    grep -Eq "^  $code  " "$TMP/stdout" || fail "janus $command --help: exit code $code not documented"
  done
done
run_janus render --help
for option in --backend --path --size --out --hdr --report --gl-platform --validation; do
  grep -q -- "$option" "$TMP/stdout" || fail "janus render --help does not mention $option"
done
for scene in 'many-lights\[:N\]' probes; do   # the built-in scenes a user can name
  grep -q -- "$scene" "$TMP/stdout" || fail "janus render --help does not mention the built-in scene $scene"
done
run_janus parity --help
for option in --size --out --tolerance --gl-platform --culling --tile-size --max-lights-per-tile --intensity-cutoff --no-shadows --env --env-intensity; do
  grep -q -- "$option" "$TMP/stdout" || fail "janus parity --help does not mention $option"
done
run_janus render --help
for option in --culling --tile-size --max-lights-per-tile --intensity-cutoff --no-shadows --debug --env --env-intensity; do
  grep -q -- "$option" "$TMP/stdout" || fail "janus render --help does not mention $option"
done
run_janus bench forward --help
for option in --lights --modes --paths --backends --cutoffs --size --frames --warmup --out --quick; do
  grep -q -- "$option" "$TMP/stdout" || fail "janus bench forward --help does not mention $option"
done

expect_success --version
grep -Eq '^janus [0-9]+\.[0-9]+\.[0-9]+$' "$TMP/stdout" || fail "janus --version printed: $(cat "$TMP/stdout")"

out="$TMP/out.png"
expect_error 2 "no command given"            # no command at all
expect_error 2 "unknown command 'frobnicate'" frobnicate
expect_error 2 "--bogus"                     render --bogus --out "$out"
expect_error 2 "--bogus"                     parity --bogus --out "$TMP/parity"
expect_error 2 "--bogus"                     info --bogus
# An empty value is a mistake to name, not the option left out (these were taken as not given).
for option in --env --env-intensity --time --animation --scene --camera; do
  expect_error 2 "^janus: error: $option: is empty; give a value or leave the option out" render "$option" "" --out "$out"
done
expect_error 2 "^janus: error: --env-intensity: is empty" parity --env-intensity "" --out "$TMP/parity"
expect_error 2 "unknown backend 'metal'.*vulkan, gl, gles" render --backend metal --out "$out"
expect_error 2 "unknown --path 'fast'.*compute or fallback" render --path fast --out "$out"
expect_error 2 "unknown --gl-platform 'wayland'.*egl or osmesa" render --gl-platform wayland --out "$out"
expect_error 2 "unknown --gl-platform 'wayland'"  info --gl-platform wayland
expect_error 2 "unknown --gl-platform 'wayland'"  parity --gl-platform wayland --out "$TMP/parity"

# Sizes: empty, absurd, malformed, half-given, negative.
expect_error 2 "--size '0x0'.*at least 1"          render --size 0x0 --out "$out"
expect_error 2 "--size '64x0'.*at least 1"         render --size 64x0 --out "$out"
expect_error 2 "--size '100000x100000'.*too large" render --size 100000x100000 --out "$out"
expect_error 2 "--size '99999999999999999999x1'.*too large" render --size 99999999999999999999x1 --out "$out"
expect_error 2 "--size 'abc'.*WIDTHxHEIGHT"        render --size abc --out "$out"
expect_error 2 "--size '64x'.*WIDTHxHEIGHT"        render --size 64x --out "$out"
expect_error 2 "--size '-5x5'.*WIDTHxHEIGHT"       render --size=-5x5 --out "$out"
expect_error 2 "--size '1.5x2'.*WIDTHxHEIGHT"      render --size 1.5x2 --out "$out"
expect_error 2 "--size '0x0'"                      parity --size 0x0 --out "$TMP/parity"
expect_error 2 "--size '100000x100000'"            parity --size 100000x100000 --out "$TMP/parity"

# Required and typed outputs.
expect_error 2 "--out FILE.png is required" render
expect_error 2 "--out DIR is required"      parity
expect_error 2 "--out '.*out.jpg' must name a .png file" render --out "$TMP/out.jpg"
expect_error 2 "--hdr '.*out.hdr' must name a .exr or .pfm file" render --out "$out" --hdr "$TMP/out.hdr"
expect_error 2 "--tolerance 'abc'"  parity --tolerance abc --out "$TMP/parity"
expect_error 2 "--tolerance '256'"  parity --tolerance 256 --out "$TMP/parity"
expect_error 2 "--tolerance '-1'"   parity --tolerance=-1 --out "$TMP/parity"

# Environment options: the sky must be .hdr or .exr; the intensity a finite number >= 0.
expect_error 2 "--env '.*sky.png' must name an equirectangular .hdr or .exr image" render --env "$TMP/sky.png" --out "$out"
expect_error 2 "--env '.*sky' must name"            parity --env "$TMP/sky" --out "$TMP/parity"
expect_error 2 "--env-intensity '-1' is not allowed" render --env-intensity=-1 --out "$out"
expect_error 2 "--env-intensity 'inf'"               render --env-intensity inf --out "$out"
expect_error 2 "--env-intensity 'bright'"            parity --env-intensity bright --out "$TMP/parity"
expect_error 2 "--time '1e300' is too large"         render --time 1e300 --out "$out"

# Nothing may have been written by any of the failures above.
if [[ -e $out || -e $TMP/parity ]]; then fail "a failed command left output behind"; fi

finish
