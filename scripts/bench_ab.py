#!/usr/bin/env python3
"""Two builds of one Google Benchmark program, run in alternation (scripts/bench.sh --ab).

    bench_ab.py A B [--filter REGEX] [--rounds N] [--min-time S]

A and B are the same benchmark program built against two header revisions. Each round runs
both once (one repetition of every matching benchmark), A first in even rounds and B first
in odd ones, so that a burst of load from another process spoils a round of both rather
than every run of one. Prints, per benchmark, the medians and minima of the rounds' CPU
times and the ratios B / A: of the medians, of the minima, and the median of the rounds'
own ratios (each round's A and B ran seconds apart, under the same load).
"""
import argparse
import json
import statistics
import subprocess
import sys
import tempfile


def run(binary, args):
    # The JSON goes to a file of its own: a program may print more than Google Benchmark's
    # report on standard output (vs_pbrt prints its RESULT lines there).
    with tempfile.NamedTemporaryFile(suffix=".json") as f:
        subprocess.run([binary] + args + ["--benchmark_out=" + f.name, "--benchmark_out_format=json"],
                       check=True, capture_output=True, text=True)
        report = json.load(open(f.name))
    times = {}
    for b in report["benchmarks"]:
        if b.get("run_type", "iteration") != "iteration":
            continue
        scale = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}[b.get("time_unit", "ns")]
        times[b["name"]] = b["cpu_time"] * scale
    return times


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--filter", default=".")
    ap.add_argument("--rounds", type=int, default=10)
    ap.add_argument("--min-time", default="0.2")
    opt = ap.parse_args()
    if opt.rounds < 2:
        sys.exit("bench_ab.py: --rounds must be at least 2")
    args = ["--benchmark_filter=" + opt.filter, "--benchmark_min_time=" + str(opt.min_time),
            "--benchmark_repetitions=1"]
    series = {"A": {}, "B": {}}
    for r in range(opt.rounds):
        order = ("A", "B") if r % 2 == 0 else ("B", "A")
        for label in order:
            for name, t in run(opt.a if label == "A" else opt.b, args).items():
                series[label].setdefault(name, []).append(t)
    names = [n for n in series["A"] if n in series["B"]]
    if not names:
        sys.exit("bench_ab.py: no benchmark matched in both programs")
    print(f"{opt.rounds} rounds, each one repetition of every benchmark (--benchmark_min_time={opt.min_time}),")
    print("A and B alternating; CPU time in ns; ratio = B / A (below 1: B is faster)")
    print()
    w = max(len(n) for n in names)
    print(f"  {'benchmark':<{w}}  {'A median':>9} {'B median':>9} {'ratio':>6}   {'A min':>9} {'B min':>9} {'ratio':>6}"
          f"   {'median of round ratios':>22}")
    for n in names:
        a, b = series["A"][n], series["B"][n]
        k = min(len(a), len(b))
        rounds = statistics.median(b[i] / a[i] for i in range(k))
        am, bm = statistics.median(a), statistics.median(b)
        print(f"  {n:<{w}}  {am:9.1f} {bm:9.1f} {bm / am:6.3f}   {min(a):9.1f} {min(b):9.1f} {min(b) / min(a):6.3f}"
              f"   {rounds:22.3f}")


if __name__ == "__main__":
    main()
