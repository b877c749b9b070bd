#!/usr/bin/env python3
"""Instructions per draw / dispatch of janus_bench_rhi's raw and RHI sides, counted by callgrind.

Usage (through scripts/bench.sh): scripts/bench.sh instructions [--build-dir DIR] [--filter REGEX] [--runs N]
                                  [--ops-per-frame N] [--split-with M]

CPU time on a shared machine moves by +-20 % between runs; the instructions the benchmark thread
executes to record and submit a frame do not. For each benchmark this runs janus_bench_rhi under
`valgrind --tool=callgrind`, collecting only inside `timedSubmit` (the timed part of a frame),
twice with different run lengths, and divides the difference in instructions by the difference
in operations: the first frames (descriptor set creation, pipeline compilation, the heap's warm-up)
cancel out and what is left is the steady-state cost per operation. Instructions are not time
(cache misses are not counted), so this complements the timed table of `scripts/bench.sh`.

The null-driver rows (both sides with the per-draw driver calls answered by stubs) count each
side's own code: their RHI - raw is what the RHI's code adds per draw. `--split-with M` counts
every benchmark again in frames of M operations and splits each side's instructions into a part
per frame and a part per operation (instructions per frame = per frame + ops x per op).
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile

# (work, backend, raw side, RHI side). The raw_command_memory rows compare with raw Vulkan recording
# into the RHI's command-pool memory: what the RHI's own code adds, the allocator's effect taken out.
PAIRS = [("draw", "vulkan", "raw", "rhi"), ("dispatch", "vulkan", "raw", "rhi"),
         ("draw", "vulkan", "raw_command_memory", "rhi"), ("dispatch", "vulkan", "raw_command_memory", "rhi"),
         ("draw", "vulkan", "raw_null_driver", "rhi_null_driver"),
         ("dispatch", "vulkan", "raw_null_driver", "rhi_null_driver"), ("draw", "gl", "raw", "rhi"),
         ("dispatch", "gl", "raw", "rhi"), ("draw", "gl", "raw_null_driver", "rhi_null_driver"),
         ("draw", "gles", "raw", "rhi"), ("draw", "gles", "raw_null_driver", "rhi_null_driver"),
         ("draw_dynamic", "vulkan", "raw", "rhi"), ("draw_dynamic", "vulkan", "raw_null_driver", "rhi_null_driver"),
         ("draw_dynamic", "gl", "raw", "rhi"), ("draw_dynamic", "gles", "raw", "rhi")]
DEFAULT_OPS_PER_FRAME = 1000   # kDefaultOpsPerFrame in bench/bench_common.h
RUN_SECONDS = (1, 4)   # --benchmark_min_time of the two runs (under valgrind: about 3 and 10 frames)
TARGET = 1.1


def callgrind(binary, name, seconds, ops, out):
    """Runs one benchmark under callgrind; returns (instructions, frames) collected in timedSubmit."""
    command = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", "--toggle-collect=*timedSubmit*",
               binary, f"--benchmark_filter=^{re.escape(name)}/", f"--benchmark_min_time={seconds}",
               f"--janus_ops_per_frame={ops}"]
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


def steady_per_frame(binary, name, scratch, runs, ops):
    """Instructions per frame of `ops` operations: the median over `runs` estimates (the allocator's
    share moves by a few percent between runs)."""
    estimates = []
    for _ in range(runs):
        (i1, f1), (i2, f2) = (callgrind(binary, name, s, ops, os.path.join(scratch, f"cg.{s}")) for s in RUN_SECONDS)
        if f2 <= f1:
            raise RuntimeError(f"{name}: the longer run did not run more frames ({f1} and {f2})")
        estimates.append((i2 - i1) / (f2 - f1))
    return statistics.median(estimates)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--binary", required=True, help="janus_bench_rhi")
    parser.add_argument("--filter", default="", help="only the pairs whose '<work>/<backend>' matches this regex")
    parser.add_argument("--runs", type=int, default=1, help="estimates per benchmark; the table shows their median")
    parser.add_argument("--ops-per-frame", type=int, default=DEFAULT_OPS_PER_FRAME,
                        help="draws or dispatches per frame (janus_bench_rhi --janus_ops_per_frame)")
    parser.add_argument("--split-with", type=int, default=0, metavar="M",
                        help="also count in frames of M operations and split each side into per frame and per op")
    args = parser.parse_args()
    if not args.binary or not os.access(args.binary, os.X_OK):
        sys.exit(f"bench_instructions: {args.binary} is not an executable")
    if args.runs < 1:
        sys.exit("bench_instructions: --runs must be at least 1")
    ops = args.ops_per_frame
    for name, value in (("--ops-per-frame", ops), ("--split-with", args.split_with or ops)):
        if not 1 <= value <= 65536:   # janus_bench_rhi's range (kMaxOpsPerFrame)
            sys.exit(f"bench_instructions: {name} takes a number of operations from 1 to 65536, got {value}")
    if args.split_with == ops:
        sys.exit(f"bench_instructions: --split-with needs a frame size other than --ops-per-frame ({ops})")
    print(f"Steady-state instructions per operation (callgrind, inside timedSubmit; {ops} ops per frame; "
          f"frames from runs of --benchmark_min_time {RUN_SECONDS[0]} and {RUN_SECONDS[1]}; median of {args.runs})")
    print()
    print(f"| backend | work | raw side | raw instr/op | RHI instr/op | RHI - raw | ratio RHI/raw | target <= {TARGET}x |")
    print("|---|---|---|---:|---:|---:|---:|---|")
    missed = 0
    splits = []
    with tempfile.TemporaryDirectory() as scratch:
        counts = {}   # each side is counted once, however many pairs it is in

        def per_frame(name, size):
            if (name, size) not in counts:
                counts[name, size] = steady_per_frame(args.binary, name, scratch, args.runs, size)
            return counts[name, size]

        for work, backend, raw_side, rhi_side in PAIRS:
            if args.filter and not re.search(args.filter, f"{work}/{backend}"):
                continue
            names = (f"{work}/{backend}/{raw_side}", f"{work}/{backend}/{rhi_side}")
            try:
                raw, rhi = (per_frame(name, ops) / ops for name in names)
            except RuntimeError as error:
                print(f"| {backend} | {work} | {raw_side} | - | - | - | - | skipped: {str(error).splitlines()[0]} |")
                continue
            ratio = rhi / raw
            # The null-driver rows measure the sides' own code, not the target's comparison.
            target = "(own code)" if raw_side.endswith("null_driver") else "met" if ratio <= TARGET else "MISSED"
            missed += target == "MISSED"
            print(f"| {backend} | {work} | {raw_side} | {raw:.1f} | {rhi:.1f} | {rhi - raw:+.1f} | {ratio:.3f}x | "
                  f"{target} |", flush=True)
            if args.split_with:
                other = args.split_with
                split = []
                for name in names:
                    at_ops, at_other = per_frame(name, ops), per_frame(name, other)
                    per_op = (at_ops - at_other) / (ops - other)
                    split += [at_ops - ops * per_op, per_op]
                splits.append(f"| {backend} | {work} | {raw_side} | {split[0]:.0f} | {split[1]:.1f} | {split[2]:.0f} | "
                              f"{split[3]:.1f} | {split[3] - split[1]:+.1f} |")
    if missed:
        print(f"\n{missed} comparison(s) above the {TARGET}x target.")
    if splits:
        print(f"\nPer frame and per operation, from frames of {ops} and of {args.split_with} operations "
              f"(instructions per frame = per frame + ops x per op):")
        print()
        print("| backend | work | raw side | raw per frame | raw per op | RHI per frame | RHI per op | RHI - raw per op |")
        print("|---|---|---|---:|---:|---:|---:|---:|")
        print("\n".join(splits))


if __name__ == "__main__":
    main()
