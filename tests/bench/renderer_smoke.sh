#!/usr/bin/env bash
# janus_bench_renderer, two frames of every configuration on a small grid with validation on
# (JANUS_BENCH_VALIDATE): each run checks that every mesh pass drew one draw per instance and that
# no validation message came, and must report its per-draw counters. Timings mean nothing here.
# Usage: renderer_smoke.sh JANUS_BENCH_RENDERER
set -euo pipefail
binary=$1
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

status=0
JANUS_BENCH_VALIDATE=1 "$binary" --janus_instances=20 --janus_frames=2 --benchmark_out_format=json \
  --benchmark_out="$scratch/bench.json" >"$scratch/stdout" 2>"$scratch/stderr" || status=$?
[[ $status == 0 ]] || { cat "$scratch/stderr" >&2; echo "FAIL: janus_bench_renderer exited with status $status" >&2; exit 1; }
python3 - "$scratch/bench.json" <<'PY'
import json, sys
runs = json.load(open(sys.argv[1]))["benchmarks"]
names = sorted("/".join(run["run_name"].split("/")[:3]) for run in runs)
expected = ["record_scene/gl/compute", "record_scene/gles/fallback", "record_scene/vulkan/compute"]
if names != expected:
    sys.exit(f"FAIL: ran {names}, expected {expected}")
for run in runs:
    if run.get("error_occurred"):
        sys.exit(f"FAIL: {run['run_name']}: {run.get('error_message')}")
    for counter in ("shadow_ns_per_draw", "prepass_ns_per_draw", "forward_ns_per_draw"):
        if not run.get(counter, 0) > 0:
            sys.exit(f"FAIL: {run['run_name']} reports no {counter}")
    if run.get("draws_per_pass") != 21:
        sys.exit(f"FAIL: {run['run_name']}: {run.get('draws_per_pass')} draws per pass, expected 21 (20 boxes and the ground)")
print(f"renderer bench smoke: {len(runs)} configurations ran")
PY
