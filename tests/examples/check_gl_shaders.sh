#!/usr/bin/env bash
# janus_check_gl_shaders --out DIR [--no-es] FILE.spv... (what janus_embed_shaders runs on a user's
# shaders): accepts modules whose GL and ES translations glslang parses, rejects one whose ESSL 300
# translation ES 3.0 cannot compile (exit 1, naming the shader, the translation and glslang's
# error), and refuses what is not a SPIR-V module (exit 2, saying why).
set -euo pipefail
tool=$1
generated=$2   # Janus's own compiled shaders (build/shaders/generated)
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

run() {   # run EXPECTED_RC PATTERN ARGS...
  local expected=$1 pattern=$2 rc=0
  shift 2
  "$tool" "$@" >"$tmp/log" 2>&1 || rc=$?
  if [[ $rc != "$expected" ]]; then fail "janus_check_gl_shaders $*: exit $rc, expected $expected: $(cat "$tmp/log")"; return; fi
  grep -Eq -- "$pattern" "$tmp/log" || fail "janus_check_gl_shaders $*: no line matching '$pattern' in: $(cat "$tmp/log")"
}

# A vertex shader: four translations (GLSL 430 and ESSL 300, each with and without clip control).
run 0 'accepts all 4 GL translations of 1 shader$' --out "$tmp/a" "$generated/bench_triangle_vert.spv"
[[ -s $tmp/a/bench_triangle_vert.es300-clipfix.vert ]] || fail "no ESSL translation written to the output folder"
# forward.frag reads storage buffers: not for ES 3.0 (Janus builds it NO_ES).
run 1 'forward_frag \(es300\): glslang rejects' --out "$tmp/b" "$generated/forward_frag.spv"
grep -q "'std430' : not supported" "$tmp/log" || fail "the rejection does not show glslang's error: $(cat "$tmp/log")"
run 0 'accepts all 1 GL translations of 1 shader$' --out "$tmp/c" --no-es "$generated/forward_frag.spv"
# Compute shaders never get an ES translation.
run 0 'accepts all 1 GL translations of 1 shader$' --out "$tmp/d" "$generated/bench_increment_comp.spv"
printf 'void main() {}\n' >"$tmp/source.frag"
run 2 "source.frag' is not a SPIR-V module \\(15 bytes" --out "$tmp/e" "$tmp/source.frag"
printf 'void main() { return; }\n' >"$tmp/text.spv"
run 2 "text.spv' is not a SPIR-V module \\(its first word is 0x64696f76.*glslangValidator -V" --out "$tmp/e" "$tmp/text.spv"
run 2 "cannot read '$tmp/none.spv'" --out "$tmp/e" "$tmp/none.spv"
run 2 'no SPIR-V file given' --out "$tmp/e"
run 2 'unknown option' --out "$tmp/e" --es "$generated/bench_triangle_vert.spv"

if ((failures)); then echo "$failures failure(s)" >&2; exit 1; fi
echo "janus_check_gl_shaders: user files checked as expected"
