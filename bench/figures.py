#!/usr/bin/env python3
"""The figures table of docs/performance.md from fesph_bench JSON files.

    bench/figures.py RUN.json...

Each file is one `build/fesph_bench --benchmark_format=json --benchmark_out=RUN.json` run
(repetitions welcome). Prints, per case, the minimum and median ns per item over every
repetition of every file (the triad's best and median GB/s), then the 2-thread speed-ups
(1-thread minimum over 2-thread minimum; target 1.8), the FE-SPH impact step over the
FE-only one (target <= 2x) and issue 11's rate targets in millions of items per second.
"""
import json
import re
import statistics
import sys
from collections import defaultdict


def load(paths):
    """case name -> list of values (ns per item, or GB/s for BM_Stream)."""
    values = defaultdict(list)
    for path in paths:
        try:
            with open(path) as f:
                runs = json.load(f)["benchmarks"]
        except (OSError, ValueError, KeyError) as e:
            sys.exit(f"figures.py: {path}: not a fesph_bench JSON output ({e})")
        for case in runs:
            if case.get("run_type") != "iteration":
                continue
            name = case["run_name"].replace("/real_time", "")
            if "bytes_per_s" in case:
                values[name].append(case["bytes_per_s"] / 1e9)
            elif "s_per_item" in case:
                values[name].append(case["s_per_item"] * 1e9)
    return values


def is_bandwidth(name):
    return name.startswith("BM_Stream")


def main(paths):
    if not paths:
        sys.exit(__doc__.strip().split("\n\n")[1].strip())
    values = load(paths)
    if not values:
        sys.exit("figures.py: no benchmark results in " + ", ".join(paths))
    # the triad is a bandwidth (more is better), every other case a time per item
    best = {n: (max(v) if is_bandwidth(n) else min(v)) for n, v in values.items()}
    print(f"{'case':64s} {'best':>9s} {'median':>9s}  runs")
    for name, v in values.items():
        unit = "GB/s" if is_bandwidth(name) else "ns"
        print(f"{name:64s} {best[name]:9.1f} {statistics.median(v):9.1f}  {len(v)}  {unit}")

    print("\n2-thread speed-up (minima):")
    for name, t1 in best.items():
        if "threads:1" not in name:
            continue
        two = name.replace("threads:1", "threads:2")
        if two in best and best[two] > 0:
            ratio = best[two] / t1 if is_bandwidth(name) else t1 / best[two]
            print(f"  {name.replace('/threads:1', ''):62s} {ratio:5.2f}")

    print("\nFE-SPH impact step over FE only (minima, medians):")
    for name in best:
        m = re.match(r"BM_ImpactStep/(n:\d+)/mode:2/(threads:\d+)", name)
        if not m:
            continue
        fe = name.replace("mode:2", "mode:1")
        if fe in best:
            print(f"  {m.group(1)} {m.group(2)}: {best[name] / best[fe]:.2f}x, "
                  f"{statistics.median(values[name]) / statistics.median(values[fe]):.2f}x "
                  "(target <= 2x)")
    lines = targets(best)
    if lines:
        print("\nIssue 11's rate targets (minima):")
        print("\n".join(lines))


def targets(best):
    """Issue 11's rate targets from the 2-thread minima (the cases present)."""
    rates = [("element kernel", r"BM_ElementKernel/.*threads:2", 20.0),
             ("SPH step", r"BM_SphForces/.*threads:2", 1.0),
             ("FE-only impact step", r"BM_ImpactStep/n:\d+/mode:1/threads:2", 6.0)]
    lines = []
    for label, pattern, target in rates:
        found = {n: 1e3 / ns for n, ns in best.items() if re.match(pattern, n) and ns > 0}
        if found:
            lo, hi = min(found.values()), max(found.values())
            verdict = "met" if lo >= target else ("missed" if hi < target else "met by some")
            lines.append(f"  {label}: {lo:.2f}-{hi:.2f} M items/s on 2 threads, "
                         f"target >= {target:g}: {verdict}")
    return lines


if __name__ == "__main__":
    main(sys.argv[1:])
