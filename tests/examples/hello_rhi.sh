#!/usr/bin/env bash
# examples/hello_rhi on every backend and feature path it claims, with validation on: the GPU's
# count of the triangle's pixels must equal the host's, and the triangle's centre its tint (row 0
# on top everywhere). Asking for compute on gles is refused (exit 4) naming the capability; a bad
# command line is exit 2.
set -euo pipefail
hello=$1
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
out=$(mktemp)
trap 'rm -f "$out"' EXIT

run() {   # run EXPECTED_RC PATTERN ARGS...: exit status and a line matching PATTERN (stdout or stderr)
  local expected=$1 pattern=$2 rc=0
  shift 2
  "$hello" "$@" >"$out" 2>&1 || rc=$?
  if [[ $rc != "$expected" ]]; then fail "hello_rhi $*: exit $rc, expected $expected: $(cat "$out")"; return; fi
  grep -Eq -- "$pattern" "$out" || fail "hello_rhi $*: no line matching '$pattern' in: $(cat "$out")"
}

counted='the triangle covers ([0-9]+) of 4096 pixels; counted on the host: '
for backend in vulkan gl; do
  run 0 "^$backend .*, compute path: $counted" --backend "$backend" --validation
  run 0 "^$backend .*, compute path: $counted" --backend "$backend" --path compute --validation
  run 0 "^$backend .*, fallback path: $counted" --backend "$backend" --path fallback --validation
done
run 0 "^gles .*, fallback path: $counted" --backend gles --validation
run 4 "capability 'compute'.*gles" --backend gles --path compute
# Every configuration counts the same pixels (one triangle, no edge through a pixel centre).
counts=$(for backend in vulkan gl gles; do "$hello" --backend "$backend" --path fallback; done | sed -E 's/.*triangle covers ([0-9]+) of.*/\1/' | sort -u)
[[ $(wc -l <<<"$counts") == 1 ]] || fail "the backends counted different pixels: $counts"
run 2 "unknown backend 'metal'" --backend metal
run 2 "unknown path 'gpu'" --path gpu
run 2 "unexpected argument '--size'" --size 8

if ((failures)); then echo "$failures failure(s)" >&2; exit 1; fi
echo "hello_rhi: every backend and path agrees"
