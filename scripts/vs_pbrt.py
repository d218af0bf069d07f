#!/usr/bin/env python3
"""The tables of bench/vs_pbrt.cpp's results (called by scripts/bench.sh --vs-pbrt).

  vs_pbrt.py results OUT.md HEADER.txt RUN_O2.txt RUN_O3.txt
      writes bench/results/vs_pbrt.md: the header lines (machine, compiler, flags, load),
      one table per real type with both optimisation levels, and the raw RESULT lines.
  vs_pbrt.py tables RESULTS.md FILE...
      regenerates the table between the markers <!-- vs_pbrt:begin --> and
      <!-- vs_pbrt:end --> in each FILE (README.md, docs/performance.md) from RESULTS.md's
      RESULT lines, so that no number in those pages is typed by hand.
"""
import re
import sys

CALLS = [("eval", "`eval(wo, wi)`"), ("pdf", "`pdf(wo, wi)`"), ("sample", "`sample(wo, u)`"),
         ("vertex", "path vertex"), ("at.eval", "`at(wo).eval(wi)`")]
BEGIN, END = "<!-- vs_pbrt:begin -->", "<!-- vs_pbrt:end -->"


def parse(lines):
    """RESULT lines -> {(type, level, call): (ours, ref, ratio, ours_min, ref_min, ratio_min)}, units."""
    rows, units = {}, {}
    for line in lines:
        f = line.split()
        if len(f) < 5 or f[0] != "RESULT":
            continue
        if f[3] == "unit":
            units[f[2]] = (float(f[4]), float(f[5]))
        else:
            rows[(f[1], f[2], f[3])] = tuple(float(x) for x in f[4:10])
    return rows, units


def detail_table(rows, units, real):
    out = ["| call | -O2 ours ns | pbrt-v4 alg. ns | ratio | ratio (minima) | -O3 ours ns | pbrt-v4 alg. ns | ratio | ratio (minima) |",
           "|---|---|---|---|---|---|---|---|---|"]
    for call, label in CALLS:
        cells = [label]
        for level in ("-O2", "-O3"):
            r = rows.get((real, level, call))
            cells += ["%.1f" % r[0], "%.1f" % r[1], "%.2f×" % r[2], "%.2f×" % r[5]] if r else ["–"] * 4
        out.append("| " + " | ".join(cells) + " |")
    if real == "float":
        for level in ("-O2", "-O3"):
            u = units.get(level)
            r = rows.get(("float", level, "at.eval"))
            if u and r:
                out.append("")
                out.append("%s: calibration unit u = %.1f ns (median; minimum %.1f ns); `at(wo).eval` = %.2f u "
                           "(minima: %.2f u)." % (level, u[0], u[1], r[0] / u[0], r[3] / u[1]))
    return out


def summary_table(rows):
    out = ["| pbrt-v4's algorithm ÷ ours | float -O2 | float -O3 | double -O2 | double -O3 |",
           "|---|---|---|---|---|"]
    for call, label in CALLS:
        cells = [label]
        for real in ("float", "double"):
            for level in ("-O2", "-O3"):
                r = rows.get((real, level, call))
                cells.append("%.2f×" % r[2] if r else "–")
        out.append("| " + " | ".join(cells) + " |")
    return out


def cmd_results(out_md, header, run_o2, run_o3):
    runs = [open(run_o2).read().splitlines(), open(run_o3).read().splitlines()]
    rows, units = parse(runs[0] + runs[1])
    text = ["# Chiang fiber against pbrt-v4's algorithm, one process", "",
            "Written by `scripts/bench.sh --vs-pbrt` (bench/vs_pbrt.cpp); do not edit. Times are the",
            "medians (and minima) of the repetitions' CPU times in ns per call, β_m = β_n = 0.3, wi",
            "uniform; ratio = the pbrt-v4-style reference's time ÷ ours (bench/reference/pbrt_style.hpp).", ""]
    text += ["```"] + open(header).read().rstrip("\n").splitlines() + ["```", ""]
    for real in ("float", "double"):
        text += ["## %s" % real, ""] + detail_table(rows, units, real) + [""]
    text += ["## Summary (medians)", ""] + summary_table(rows) + [""]
    text += ["## Raw lines", "", "```"]
    text += [l for l in runs[0] + runs[1] if l.startswith("RESULT")] + ["```", ""]
    open(out_md, "w").write("\n".join(text))


def cmd_tables(results_md, files):
    rows, _ = parse(open(results_md).read().splitlines())
    if not rows:
        sys.exit("vs_pbrt.py: no RESULT lines in " + results_md)
    table = summary_table(rows)
    for path in files:
        text = open(path).read()
        pattern = re.compile(re.escape(BEGIN) + ".*?" + re.escape(END), re.S)
        if not pattern.search(text):
            sys.exit("vs_pbrt.py: no %s … %s markers in %s" % (BEGIN, END, path))
        text = pattern.sub(lambda _: "\n".join([BEGIN] + table + [END]), text)
        open(path, "w").write(text)


if __name__ == "__main__":
    if len(sys.argv) >= 6 and sys.argv[1] == "results":
        cmd_results(*sys.argv[2:6])
    elif len(sys.argv) >= 4 and sys.argv[1] == "tables":
        cmd_tables(sys.argv[2], sys.argv[3:])
    else:
        sys.exit(__doc__)
