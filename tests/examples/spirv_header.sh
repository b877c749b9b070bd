#!/usr/bin/env bash
# The one compile step of every shader (janus_glslang_steps, cmake/JanusEmbedShaders.cmake): the
# header it writes from a .spv holds exactly the module's words (glslang's own --vn header is the
# reference), and a file that is not a whole little-endian SPIR-V module stops the build by name.
# Usage: spirv_header.sh CMAKE GLSLANG_VALIDATOR SOURCE_DIR
source "$(dirname "$0")/common.bash"
cmake_exe=$1 glslang=$2 source_dir=$3
script="$source_dir/cmake/JanusEmbedShaders.cmake"
write_header() {   # SPV HEADER ARRAY
  "$cmake_exe" "-DJANUS_SPIRV_FILE=$1" "-DJANUS_SPIRV_HEADER=$2" "-DJANUS_SPIRV_ARRAY=$3" -P "$script"
}
words() { grep -oE '0x[0-9a-fA-F]{8}' "$1"; }

for shader in examples/hello_rhi/shaders/count_covered.comp shaders/renderer/forward.frag; do
  name=$(basename "$shader" | tr . _)
  "$glslang" -V --target-env vulkan1.2 -I"$source_dir/shaders" -I"$source_dir/shaders/include" \
    -o "$tmp/$name.spv" "$source_dir/$shader" >/dev/null
  "$glslang" -V --target-env vulkan1.2 -I"$source_dir/shaders" -I"$source_dir/shaders/include" \
    --vn reference -o "$tmp/$name.reference.h" "$source_dir/$shader" >/dev/null
  if ! write_header "$tmp/$name.spv" "$tmp/$name.h" "$name" >"$tmp/log" 2>&1; then
    fail "$shader: the header step failed: $(cat "$tmp/log")"
    continue
  fi
  count=$(words "$tmp/$name.h" | wc -l)
  [[ $((count * 4)) == $(stat -c %s "$tmp/$name.spv") ]] || fail "$shader: $count words for $(stat -c %s "$tmp/$name.spv") bytes"
  cmp -s <(words "$tmp/$name.h") <(words "$tmp/$name.reference.h") || fail "$shader: the words differ from glslang's --vn header"
  grep -q "^const uint32_t $name\[\] = {" "$tmp/$name.h" || fail "$shader: no array named $name"
  [[ ! -e "$tmp/$name.h.tmp" ]] || fail "$shader: the temporary file was left behind"
  # The header compiles and holds the module (its first word, the magic number).
  printf '#include <cstdint>\n#include "%s"\nstatic_assert(sizeof(%s) == %d);\nint main() { return %s[0] == 0x07230203u ? 0 : 1; }\n' \
    "$tmp/$name.h" "$name" $((count * 4)) "$name" >"$tmp/$name.cpp"
  if c++ -std=c++20 -o "$tmp/$name.exe" "$tmp/$name.cpp" 2>"$tmp/log"; then
    "$tmp/$name.exe" || fail "$shader: the compiled header's first word is not the magic number"
  else
    fail "$shader: the header does not compile: $(cat "$tmp/log")"
  fi
done

# Not whole words, empty, the other endianness, not SPIR-V: refused by name, no header written.
printf 'abcdef' >"$tmp/partial.spv"
: >"$tmp/empty.spv"
printf '\x07\x23\x02\x03\x00\x01\x05\x00' >"$tmp/big_endian.spv"
printf 'not spirv' >"$tmp/text.spv"
# refuse NAME PATTERN: the header step on $tmp/NAME.spv exits 1 with PATTERN in its message
# (CMake folds long messages, so the lines are joined first).
refuse() {
  local rc=0
  write_header "$tmp/$1.spv" "$tmp/$1.h" a >"$tmp/log" 2>&1 || rc=$?
  [[ $rc == 1 ]] || fail "$1.spv: exit $rc, expected 1: $(cat "$tmp/log")"
  tr '\n' ' ' <"$tmp/log" | tr -s ' ' | grep -Eq -- "$2" || fail "$1.spv: no '$2' in: $(cat "$tmp/log")"
}
refuse partial "partial.spv: not a SPIR-V module \(12 hex digits, not whole 32-bit words\)"
refuse empty "empty.spv: not a SPIR-V module \(0 hex digits"
refuse big_endian "big_endian.spv: not a little-endian SPIR-V module \(first word 0x03022307, not 0x07230203\)"
refuse text "text.spv: not a"
for bad in partial empty big_endian text; do
  [[ ! -e "$tmp/$bad.h" && ! -e "$tmp/$bad.h.tmp" ]] || fail "$bad.spv: a header was written"
done

finish "spirv header: words identical to glslang's for 2 shaders; 4 malformed files refused by name"
