#!/usr/bin/env python3
"""The summary table of a dual_bench or tabulated_bench run (scripts/bench.sh), from its
Google Benchmark JSON (medians of the CPU time over the repetitions):

  bench_ratios.py dual JSON        each dual call / the single fiber's call of the same run
  bench_ratios.py tabulated JSON   each float call in calibration units (BM_Calib<float>)
"""
import json
import sys


def medians(path):
    data = json.load(open(path))
    rows = {}
    for b in data["benchmarks"]:
        if b.get("aggregate_name") == "median":
            rows[b["run_name"]] = (b["cpu_time"], b.get("label", ""))
    return rows


def dual(rows):
    print("== Summary: dual BCSDF / single fiber (ChiangFiber), medians of this run ==")
    print()
    print("  %-8s %-26s %10s %10s %7s" % ("real", "call", "single ns", "dual ns", "ratio"))
    pairs = [("eval (fiber + eval)", "BM_SingleEval", "BM_DualEval"),
             ("sample (fiber + sample)", "BM_SingleSample", "BM_DualSample"),
             ("bound eval (at(wo) once)", "BM_SingleAtEval", "BM_DualAtEval"),
             # The same over tables in Zinke et al. 2008's formulation (no per-θi light
             # transport): the floor a dual BCSDF over this fiber reaches (float only).
             ("Zinke 2008: eval", "BM_SingleEval", "BM_DualZinkeEval"),
             ("Zinke 2008: sample", "BM_SingleSample", "BM_DualZinkeSample"),
             ("Zinke 2008: bound eval", "BM_SingleAtEval", "BM_DualZinkeAtEval")]
    for real in ("float", "double"):
        for label, single, dual_name in pairs:
            s = rows.get("%s<%s>" % (single, real))
            d = rows.get("%s<%s>" % (dual_name, real))
            if s and d:
                print("  %-8s %-26s %10.1f %10.1f %6.2fx" % (real, label, s[0], d[0], d[0] / s[0]))


def tabulated(rows):
    calib = rows.get("BM_Calib<float>")
    if not calib:
        print("(no calibration result)")
        return
    u = calib[0]
    print("== Summary: float calls in calibration units u = %.1f ns (BM_Calib<float> of this run) ==" % u)
    print()
    print("  %-44s %9s %7s  %s" % ("benchmark", "ns", "u", "label"))
    for name, (ns, label) in sorted(rows.items()):
        if "<float>" in name and any(name.startswith(p) for p in ("BM_Eval", "BM_AtEval", "BM_At<", "BM_Sample",
                                                                     "BM_AtSample", "BM_Pdf<")):
            if "/bm:1" in name:
                print("  %-44s %9.1f %7.2f  %s" % (name, ns, ns / u, label))


def main():
    if len(sys.argv) != 3 or sys.argv[1] not in ("dual", "tabulated"):
        sys.exit(__doc__)
    rows = medians(sys.argv[2])
    (dual if sys.argv[1] == "dual" else tabulated)(rows)


if __name__ == "__main__":
    main()
