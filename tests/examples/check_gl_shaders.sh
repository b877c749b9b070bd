#!/usr/bin/env bash
# janus_check_gl_shaders --out DIR [--no-es] FILE.spv... (what janus_embed_shaders runs on a user's
# shaders): accepts modules whose GL and ES translations glslang parses, rejects one whose ESSL 300
# translation ES 3.0 cannot compile (exit 1, naming the shader, the translation and glslang's
# error), and refuses what is not a SPIR-V module (exit 2, saying why).
source "$(dirname "$0")/common.bash"
PROGRAM=$1
generated=$2   # Janus's own compiled shaders (build/shaders/generated)

# A vertex shader: four translations (GLSL 430 and ESSL 300, each with and without clip control).
run 0 'accepts all 4 GL translations of 1 shader$' --out "$tmp/a" "$generated/bench_triangle_vert.spv"
[[ -s $tmp/a/bench_triangle_vert.es300-clipfix.vert ]] || fail "no ESSL translation written to the output folder"
# forward.frag reads storage buffers: not for ES 3.0 (Janus builds it NO_ES).
run 1 'forward_frag \(es300\): glslang rejects' --out "$tmp/b" "$generated/forward_frag.spv"
grep -q "'std430' : not supported" "$tmp/log" || fail "the rejection does not show glslang's error: $(cat "$tmp/log")"
run 0 'accepts all 1 GL translations of 1 shader$' --out "$tmp/c" --no-es "$generated/forward_frag.spv"
# Compute shaders never get an ES translation.
run 0 'accepts all 1 GL translations of 1 shader$' --out "$tmp/d" "$generated/bench_increment_comp.spv"
# A fragment shader sampling after a discard: accepted, with the derivative warning createShader
# would give with validation on.
cat >"$tmp/late_sample.frag" <<'GLSL'
#version 450
layout(set = 0, binding = 0) uniform sampler2D tex;
layout(location = 0) in vec2 uv;
layout(location = 0) out vec4 color;
void main() {
    if (uv.x > 0.5) discard;
    color = texture(tex, uv);
}
GLSL
glslangValidator -V --target-env vulkan1.2 -o "$tmp/late_sample.frag.spv" "$tmp/late_sample.frag" >/dev/null
run 0 "warning: .*late_sample.frag.spv: an implicit-LOD texture lookup of 'tex' .* after a discard" --out "$tmp/f" "$tmp/late_sample.frag.spv"
grep -q 'accepts all 2 GL translations of 1 shader$' "$tmp/log" || fail "the shader with a warning was not accepted: $(cat "$tmp/log")"
printf 'void main() {}\n' >"$tmp/source.frag"
run 2 "source.frag' is not a SPIR-V module \\(15 bytes" --out "$tmp/e" "$tmp/source.frag"
printf 'void main() { return; }\n' >"$tmp/text.spv"
run 2 "text.spv' is not a SPIR-V module \\(its first word is 0x64696f76.*glslangValidator -V" --out "$tmp/e" "$tmp/text.spv"
# A real module with one instruction's word count damaged: refused by the validator, not a crash.
python3 - "$generated/bench_uniform_color_frag.spv" "$tmp/damaged.spv" <<'PY'
import struct, sys
data = bytearray(open(sys.argv[1], "rb").read())
words = list(struct.unpack("<%dI" % (len(data) // 4), data))
words[5] = (words[5] & 0xFFFF) | (0x7FFF << 16)   # the first instruction claims 32767 words
open(sys.argv[2], "wb").write(struct.pack("<%dI" % len(words), *words))
PY
run 2 "damaged.spv' is not a valid SPIR-V module" --out "$tmp/e" "$tmp/damaged.spv"
run 2 "cannot read '$tmp/none.spv'" --out "$tmp/e" "$tmp/none.spv"
run 2 'no SPIR-V file given' --out "$tmp/e"
run 2 'unknown option' --out "$tmp/e" --es "$generated/bench_triangle_vert.spv"

finish "janus_check_gl_shaders: user files checked as expected"
