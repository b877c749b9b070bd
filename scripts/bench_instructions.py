#!/usr/bin/env python3
"""Instructions per draw / dispatch of janus_bench_rhi's raw and RHI sides, counted by callgrind.

Usage (through scripts/bench.sh): scripts/bench.sh instructions [--build-dir DIR] [--filter REGEX] [--runs N]

CPU time on a shared machine moves by +-20 % between runs; the instructions the benchmark thread
executes to record and submit a frame do not. For each benchmark this runs janus_bench_rhi under
`valgrind --tool=callgrind`, collecting only inside `timedSubmit` (the timed part of a frame),
twice with different run lengths, and divides the difference in instructions by the difference
in operations: the first frames (descriptor set creation, pipeline compilation, the heap's warm-up)
cancel out and what is left is the steady-state cost per operation. Instructions are not time
(cache misses are not counted), so this complements the timed table of `scripts/bench.sh`.
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile

# (work, backend, raw side). The raw_command_memory rows compare with raw Vulkan recording into the
# RHI's command-pool memory: what the RHI's own code adds, the allocator's effect taken out.
PAIRS = [("draw", "vulkan", "raw"), ("dispatch", "vulkan", "raw"), ("draw", "vulkan", "raw_command_memory"),
         ("dispatch", "vulkan", "raw_command_memory"), ("draw", "gl", "raw"), ("dispatch", "gl", "raw"),
         ("draw", "gles", "raw")]
OPS_PER_FRAME = 1000   # kDefaultOpsPerFrame in bench/bench_common.h (no --janus_ops_per_frame here)
RUN_SECONDS = (1, 4)   # --benchmark_min_time of the two runs (under valgrind: about 3 and 10 frames)
TARGET = 1.1


def callgrind(binary, name, seconds, out):
    """Runs one benchmark under callgrind; returns (instructions, frames) collected in timedSubmit."""
    command = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", "--toggle-collect=*timedSubmit*",
               binary, f"--benchmark_filter=^{re.escape(name)}/", f"--benchmark_min_time={seconds}"]
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if result.returncode != 0 or not os.path.exists(out):
        raise RuntimeError(f"{name}: callgrind run failed ({result.returncode}):\n{result.stderr[-2000:]}")
    if "ERROR OCCURRED" in result.stdout:
        raise RuntimeError(f"{name}: the benchmark reported an error:\n{result.stdout[-2000:]}")
    instructions, frames, names, callee = 0, 0, {}, None
    with open(out) as f:
        for line in f:
            if line.startswith(("summary:", "totals:")):
                instructions = max(instructions, int(line.split()[1]))
                continue
            match = re.match(r"(c?fn)=\((\d+)\)(?: (.*))?", line)
            if match:
                kind, ident, text = match.groups()
                if text:
                    names[ident] = text.strip()
                if kind == "cfn":
                    callee = names.get(ident, "")
                continue
            match = re.match(r"calls=(\d+)", line)
            if match and callee is not None and "timedSubmit" in callee:
                frames += int(match.group(1))
    return instructions, frames


def steady_per_op(binary, name, scratch, runs):
    """The median over `runs` estimates (the allocator's share moves by a few percent between runs)."""
    estimates = []
    for _ in range(runs):
        (i1, f1), (i2, f2) = (callgrind(binary, name, s, os.path.join(scratch, f"cg.{s}")) for s in RUN_SECONDS)
        if f2 <= f1:
            raise RuntimeError(f"{name}: the longer run did not run more frames ({f1} and {f2})")
        estimates.append((i2 - i1) / ((f2 - f1) * OPS_PER_FRAME))
    return statistics.median(estimates)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--binary", required=True, help="janus_bench_rhi")
    parser.add_argument("--filter", default="", help="only the pairs whose '<work>/<backend>' matches this regex")
    parser.add_argument("--runs", type=int, default=1, help="estimates per benchmark; the table shows their median")
    args = parser.parse_args()
    if not args.binary or not os.access(args.binary, os.X_OK):
        sys.exit(f"bench_instructions: {args.binary} is not an executable")
    if args.runs < 1:
        sys.exit("bench_instructions: --runs must be at least 1")
    print(f"Steady-state instructions per operation (callgrind, inside timedSubmit; {OPS_PER_FRAME} ops per frame; "
          f"frames from runs of --benchmark_min_time {RUN_SECONDS[0]} and {RUN_SECONDS[1]}; median of {args.runs})")
    print()
    print(f"| backend | work | raw side | raw instr/op | RHI instr/op | RHI - raw | ratio RHI/raw | target <= {TARGET}x |")
    print("|---|---|---|---:|---:|---:|---:|---|")
    missed = 0
    with tempfile.TemporaryDirectory() as scratch:
        rhi_counts = {}   # each RHI side is counted once, however many raw sides it is compared with
        for work, backend, raw_side in PAIRS:
            if args.filter and not re.search(args.filter, f"{work}/{backend}"):
                continue
            try:
                raw = steady_per_op(args.binary, f"{work}/{backend}/{raw_side}", scratch, args.runs)
                if (work, backend) not in rhi_counts:
                    rhi_counts[work, backend] = steady_per_op(args.binary, f"{work}/{backend}/rhi", scratch, args.runs)
                rhi = rhi_counts[work, backend]
            except RuntimeError as error:
                print(f"| {backend} | {work} | {raw_side} | - | - | - | - | skipped: {str(error).splitlines()[0]} |")
                continue
            ratio = rhi / raw
            missed += ratio > TARGET
            print(f"| {backend} | {work} | {raw_side} | {raw:.0f} | {rhi:.0f} | {rhi - raw:+.0f} | {ratio:.3f}x | "
                  f"{'met' if ratio <= TARGET else 'MISSED'} |", flush=True)
    if missed:
        print(f"\n{missed} comparison(s) above the {TARGET}x target.")


if __name__ == "__main__":
    main()
