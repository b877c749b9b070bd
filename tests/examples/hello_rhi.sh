#!/usr/bin/env bash
# examples/hello_rhi on every backend and feature path it claims, with validation on: the GPU's
# count of the triangle's pixels must equal the host's, and the triangle's centre its tint (row 0
# on top everywhere). Asking for compute on gles is refused (exit 4) naming the capability; a bad
# command line is exit 2.
source "$(dirname "$0")/common.bash"
PROGRAM=$1
counted='the triangle covers ([0-9]+) of 4096 pixels; counted on the host: '
for backend in vulkan gl; do
  run 0 "^$backend .*, compute path: $counted" --backend "$backend" --validation
  run 0 "^$backend .*, compute path: $counted" --backend "$backend" --path compute --validation
  run 0 "^$backend .*, fallback path: $counted" --backend "$backend" --path fallback --validation
done
run 0 "^gles .*, fallback path: $counted" --backend gles --validation
run 4 "capability 'compute'.*gles" --backend gles --path compute
# Every configuration counts the same pixels (one triangle, no edge through a pixel centre).
counts=$(for backend in vulkan gl gles; do "$PROGRAM" --backend "$backend" --path fallback; done | sed -E 's/.*triangle covers ([0-9]+) of.*/\1/' | sort -u)
[[ $(wc -l <<<"$counts") == 1 ]] || fail "the backends counted different pixels: $counts"
run 2 "unknown backend 'metal'" --backend metal
run 2 "unknown path 'gpu'" --path gpu
run 2 "unexpected argument '--size'" --size 8

finish "hello_rhi: every backend and path agrees"
