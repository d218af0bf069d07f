#!/usr/bin/env python3
"""The tables of bench/vs_pbrt.cpp's results (called by scripts/bench.sh --vs-pbrt).

  vs_pbrt.py results OUT.md HEADER.txt RUN.txt...
      writes bench/results/vs_pbrt.md: the header lines (machine, compiler, flags, load),
      per real type a table per instruction set (native, x86-64-v3, x86-64-v2) with both
      optimisation levels, the summaries, the material build costs and the raw RESULT lines.
  vs_pbrt.py tables RESULTS.md FILE...
      regenerates the table between the markers <!-- vs_pbrt:begin --> and
      <!-- vs_pbrt:end --> in each FILE (README.md, docs/performance.md) from RESULTS.md's
      RESULT lines, so that no number in those pages is typed by hand.
"""
import re
import sys

CALLS = [("eval", "`eval(wo, wi)`"), ("pdf", "`pdf(wo, wi)`"), ("sample", "`sample(wo, u)`"),
         ("vertex", "path vertex"), ("at.eval", "`at(wo).eval(wi)`"),
         ("fresh.eval", "stateless `eval`: fiber(h) + eval"), ("fresh.pdf", "stateless `pdf`: fiber(h) + pdf"),
         ("fresh.sample", "stateless `sample`: fiber(h) + sample"),
         ("hit.eval", "per-hit `eval`: per_hit_eval"),
         ("hit.eval.parts", "per-hit material, then fiber + `eval`"), ("hit.vertex", "per-hit path vertex: per_hit_vertex"),
         ("hit.vertex.parts", "per-hit material, then fiber + path vertex"),
         ("b0.05.eval", "`eval`, β 0.05"), ("b1.eval", "`eval`, β 1"),
         ("b0.05.sample", "`sample`, β 0.05"), ("b1.sample", "`sample`, β 1"),
         ("batch.eval", "batched `eval`, per hit"), ("batch.pdf", "batched `pdf`, per hit"),
         ("batch.sample", "batched `sample`, per hit")]
# The builds, in table order: -march=native, x86-64-v3, x86-64-v2 (bench/CMakeLists.txt).
LEVELS = ["-O2", "-O3", "-O2/v3", "-O3/v3", "-O2/v2", "-O3/v2"]
LEVEL_NAMES = {"-O2": "-O2 native", "-O3": "-O3 native", "-O2/v3": "-O2 v3", "-O3/v3": "-O3 v3",
               "-O2/v2": "-O2 v2", "-O3/v2": "-O3 v2"}
BEGIN, END = "<!-- vs_pbrt:begin -->", "<!-- vs_pbrt:end -->"


def parse(lines):
    """RESULT lines -> {(type, level, call): (ours, ref, ratio, ours_min, ref_min, ratio_min)}, units, builds."""
    rows, units, builds = {}, {}, {}
    for line in lines:
        f = line.split()
        if len(f) < 5 or f[0] != "RESULT":
            continue
        if f[3] == "unit":
            units[f[2]] = (float(f[4]), float(f[5]))
        elif f[3] == "build":
            builds[(f[1], f[2])] = tuple(float(x) for x in f[4:8])
        else:
            rows[(f[1], f[2], f[3])] = tuple(float(x) for x in f[4:10])
    return rows, units, builds


def levels_in(rows):
    present = {k[1] for k in rows}
    return [l for l in LEVELS if l in present] + sorted(present - set(LEVELS))


def detail_table(rows, units, real, pair):
    out = ["| call | %s ours ns | pbrt-v4 alg. ns | ratio | ratio (minima) | %s ours ns | pbrt-v4 alg. ns | ratio | ratio (minima) |"
           % (LEVEL_NAMES.get(pair[0], pair[0]), LEVEL_NAMES.get(pair[1], pair[1])),
           "|---|---|---|---|---|---|---|---|---|"]
    for call, label in CALLS:
        cells = [label]
        for level in pair:
            r = rows.get((real, level, call))
            cells += ["%.1f" % r[0], "%.1f" % r[1], "%.2f×" % r[2], "%.2f×" % r[5]] if r else ["–"] * 4
        if any(c != "–" for c in cells[1:]):
            out.append("| " + " | ".join(cells) + " |")
    if real == "float":
        for level in pair:
            u = units.get(level)
            r = rows.get(("float", level, "at.eval"))
            if u and r:
                out.append("")
                out.append("%s: calibration unit u = %.1f ns (median; minimum %.1f ns); `at(wo).eval` = %.2f u "
                           "(minima: %.2f u)." % (level, u[0], u[1], r[0] / u[0], r[3] / u[1]))
    return out


def summary_table(rows, real, levels):
    out = ["| pbrt-v4's algorithm ÷ ours, %s | %s |" % (real, " | ".join(LEVEL_NAMES.get(l, l) for l in levels)),
           "|---|" + "---|" * len(levels)]
    for call, label in CALLS:
        cells = [label]
        for level in levels:
            r = rows.get((real, level, call))
            cells.append("%.2f×" % r[2] if r else "–")
        if any(c != "–" for c in cells[1:]):
            out.append("| " + " | ".join(cells) + " |")
    return out


def build_table(builds, levels):
    out = ["| material build, ns (median) | " + " | ".join(LEVEL_NAMES.get(l, l) for l in levels) + " |",
           "|---|" + "---|" * len(levels)]
    for real in ("float", "double"):
        for k, label in ((0, "`ChiangMaterial::per_hit`"), (1, "`ChiangMaterial(params)` (checked)")):
            cells = ["%s, %s" % (label, real)]
            for level in levels:
                b = builds.get((real, level))
                cells.append("%.1f" % b[k] if b else "–")
            out.append("| " + " | ".join(cells) + " |")
    return out


def cmd_results(out_md, header, *runs_paths):
    runs = [open(p).read().splitlines() for p in runs_paths]
    lines = [l for run in runs for l in run]
    rows, units, builds = parse(lines)
    levels = levels_in(rows)
    text = ["# Chiang fiber against pbrt-v4's algorithm, one process", "",
            "Written by `scripts/bench.sh --vs-pbrt` (bench/vs_pbrt.cpp); do not edit. Times are the",
            "medians (and minima) of the repetitions' CPU times in ns per call, β_m = β_n = 0.3 (but for",
            "the β rows), wi uniform; ratio = the pbrt-v4-style reference's time ÷ ours",
            "(bench/reference/pbrt_style.hpp), both measured in the same process. Builds: native =",
            "-march=native, v3 = -march=x86-64-v3, v2 = -march=x86-64-v2. Stateless rows build the",
            "fiber from h inside the timed call (the reference its HairBxDF); per-hit rows build the",
            "material too, from parameters that differ at every input (ours inside the call:",
            "ChiangFiber::per_hit_eval and per_hit_vertex, the latter also giving the pdf toward wi;",
            "or from the parts: ChiangMaterial::per_hit, then the fiber).",
            "Batched rows: ChiangBatch over 256 hits of one material per call (h per hit), the time",
            "per hit against the reference's prebuilt per-hit calls.", ""]
    text += ["```"] + open(header).read().rstrip("\n").splitlines() + ["```", ""]
    for real in ("float", "double"):
        text += ["## %s" % real, ""]
        for i in range(0, len(levels), 2):
            text += detail_table(rows, units, real, (levels[i:i + 2] + levels[i:i + 1])[:2]) + [""]
    text += ["## Summary (medians)", ""]
    for real in ("float", "double"):
        text += summary_table(rows, real, levels) + [""]
    text += build_table(builds, levels) + [""]
    text += ["## Raw lines", "", "```"]
    text += [l for l in lines if l.startswith("RESULT")] + ["```", ""]
    open(out_md, "w").write("\n".join(text))


def cmd_tables(results_md, files):
    rows, _, builds = parse(open(results_md).read().splitlines())
    if not rows:
        sys.exit("vs_pbrt.py: no RESULT lines in " + results_md)
    levels = levels_in(rows)
    table = summary_table(rows, "float", levels) + [""] + summary_table(rows, "double", levels)
    if builds:
        table += [""] + build_table(builds, levels)
    for path in files:
        text = open(path).read()
        pattern = re.compile(re.escape(BEGIN) + ".*?" + re.escape(END), re.S)
        if not pattern.search(text):
            sys.exit("vs_pbrt.py: no %s … %s markers in %s" % (BEGIN, END, path))
        text = pattern.sub(lambda _: "\n".join([BEGIN] + table + [END]), text)
        open(path, "w").write(text)


if __name__ == "__main__":
    if len(sys.argv) >= 5 and sys.argv[1] == "results":
        cmd_results(*sys.argv[2:])
    elif len(sys.argv) >= 4 and sys.argv[1] == "tables":
        cmd_tables(sys.argv[2], sys.argv[3:])
    else:
        sys.exit(__doc__)
