#!/usr/bin/env python3
"""Where `varsfm map`'s CPU time goes, by mapper phase, from a perf profile with call graphs.

    perf record -F 99 --call-graph dwarf,32768 -o perf.data varsfm map ...
    perf script -i perf.data | bench/perf_phases.py [--inside FUNCTION] [--top 30]

Each sample is put in the phase of the outermost mapper function on its stack (next-image
choice, registration, triangulation, local BA, global BA, ...); samples of the BA solver's
worker threads carry no mapper frame and are counted as "BA worker threads". With --inside, the
functions (inclusive) and leaves (self) of the samples under FUNCTION instead. Percentages are of
all samples; at -F 99 a sample is ~10 ms of CPU.
"""
import argparse
import collections
import re
import sys

PHASES = ["NextImageCandidates", "LocalBundleAdjustment", "GlobalBundleAdjustment",
          "RegisterImage", "TriangulateImage", "InitializeModel", "RmsReprojectionError"]
FRAME = re.compile(r"\s+[0-9a-f]+\s+(.*?)\s+\(")


def stacks(lines):
    """The call stacks of `perf script`'s samples, leaf first, offsets stripped."""
    stack = []
    for line in lines:
        line = line.rstrip("\n")
        if not line.strip() or line[0] not in " \t":
            if stack:
                yield stack
            stack = []
            continue
        m = FRAME.match(line)
        if m:
            stack.append(re.sub(r"\+0x[0-9a-f]+$", "", m.group(1)))
    if stack:
        yield stack


def phase_of(stack):
    for frame in reversed(stack):
        for p in PHASES:
            if p in frame:
                return p
    if any("tbb::" in f for f in stack) and not any(" main" in f or f == "main" for f in stack):
        return "BA worker threads"
    return "other"


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("--inside", help="break down the samples under this function")
    p.add_argument("--top", type=int, default=30)
    args = p.parse_args()
    total = 0
    phases = collections.Counter()
    inclusive, leaves = collections.Counter(), collections.Counter()
    for st in stacks(sys.stdin):
        total += 1
        if not args.inside:
            phases[phase_of(st)] += 1
            continue
        hits = [i for i, f in enumerate(st) if args.inside in f]
        if not hits:
            continue
        phases[args.inside] += 1
        for f in set(st[:hits[-1]]):
            inclusive[f[:110]] += 1
        leaves[st[0][:110]] += 1
    if not total:
        sys.exit("no samples on stdin (perf script output expected)")
    print(f"{total} samples")
    for name, n in phases.most_common():
        print(f"{100 * n / total:6.2f} %  {name}")
    if args.inside:
        print("-- inclusive")
        for name, n in inclusive.most_common(args.top):
            print(f"{100 * n / total:6.2f} %  {name}")
        print("-- self")
        for name, n in leaves.most_common(args.top):
            print(f"{100 * n / total:6.2f} %  {name}")


if __name__ == "__main__":
    main()
