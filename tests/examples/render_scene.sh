#!/usr/bin/env bash
# examples/render_scene: the default scene on vulkan/compute and gles/fallback must agree by the
# parity rule and leave both images and the heat map; a missing scene is exit 3 naming it, the
# compute path on gles exit 4 naming the capability, a bad configuration exit 2.
set -euo pipefail
render=$1
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

run() {   # run EXPECTED_RC PATTERN ARGS...
  local expected=$1 pattern=$2 rc=0
  shift 2
  "$render" "$@" >"$tmp/log" 2>&1 || rc=$?
  if [[ $rc != "$expected" ]]; then fail "render_scene $*: exit $rc, expected $expected: $(cat "$tmp/log")"; return; fi
  grep -Eq -- "$pattern" "$tmp/log" || fail "render_scene $*: no line matching '$pattern' in: $(cat "$tmp/log")"
}

run 0 '^vulkan/compute vs gles/fallback: agree$' --size 64 --out "$tmp/default"
for image in a.png b.png difference.png; do
  [[ -s $tmp/default/$image ]] || fail "render_scene wrote no $image"
done
grep -q '^  forward ' "$tmp/log" || fail "render_scene printed no forward pass: $(cat "$tmp/log")"
run 0 '^gl/compute vs vulkan/fallback: agree$' --a gl/compute --b vulkan/fallback --size 64 --out "$tmp/gl"
run 3 'no-such-scene\.gltf' "$tmp/no-such-scene.gltf" --out "$tmp/missing"
run 4 "gles/compute needs capability 'compute'" --b gles/compute --size 64 --out "$tmp/refused"
run 2 "'gles' is not BACKEND/PATH" --b gles

if ((failures)); then echo "$failures failure(s)" >&2; exit 1; fi
echo "render_scene: the configurations agree"
