#!/usr/bin/env python3
"""The Python module's vectorised eval against the plain C++ loop, over 10^6 directions.

    PYTHONPATH=build/python/python python3 bench/python_bench.py [--build build/python] [--n 1000000]
        [--repeats 7] [--rounds 3] [--out bench/results/python.txt]

Both sides evaluate ChiangFiber<T>(material, h[i]).eval(wo[i], wi[i]) for N uniform random
directions and offsets held in arrays (the C++ side is python/python_eval_loop.cpp, built
with the module's flags by scripts/python.sh). Per round the C++ program reports the median
of its repeats, then the module's call is timed as many times (the arrays made beforehand,
the result allocated by each call as a user's call does); the ratio is Python ÷ C++ of the
same round, and the figure is the median over the rounds. Writes the table with the machine,
compiler and flags to --out.
"""

import argparse
import datetime
import os
import pathlib
import platform
import re
import statistics
import subprocess
import sys
import time

import numpy as np

import hairscatter as hs

ROOT = pathlib.Path(__file__).resolve().parents[1]
# python_eval_loop.cpp's material.
MODEL = dict(eta=1.55, beta_m=0.3, beta_n=0.3, alpha=0.035, sigma_a=(0.6, 0.9, 1.6))


def cpu_line():
    """scripts/lib.sh's hs_cpu_line: model name, family, model (and AMD's core generation), cores."""
    r = subprocess.run(["bash", "-c", f"source '{ROOT}/scripts/lib.sh' && hs_cpu_line"], capture_output=True, text=True)
    return r.stdout.strip() or f"{platform.processor() or 'unknown CPU'}, {os.cpu_count()} cores"


def cache_value(build, key):
    text = (build / "CMakeCache.txt").read_text()
    m = re.search(rf"^{key}:[A-Z]+=(.*)$", text, re.M)
    return m.group(1) if m else "?"


def inputs(n, dtype, seed=12345):
    rng = np.random.default_rng(seed)
    def dirs():
        z = rng.uniform(-1, 1, n)
        phi = rng.uniform(0, 2 * np.pi, n)
        r = np.sqrt(1 - z * z)
        return np.ascontiguousarray(np.stack([z, r * np.cos(phi), r * np.sin(phi)], axis=1).astype(dtype))
    return dirs(), dirs(), rng.uniform(-1, 1, n).astype(dtype)


def time_module(dtype, n, repeats):
    model = hs.Chiang(dtype=dtype, **MODEL)
    wo, wi, h = inputs(n, dtype)
    model.eval(wo[:1000], wi[:1000], h[:1000])  # warm up
    seconds = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        model.eval(wo, wi, h)
        seconds.append(time.perf_counter() - t0)
    return statistics.median(seconds)


def time_cpp(program, dtype, n, repeats):
    out = subprocess.run([str(program), str(n), str(repeats), dtype], check=True, capture_output=True, text=True).stdout
    return float(re.search(r"median_s=([0-9.e+-]+)", out).group(1))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--build", default=str(ROOT / "build" / "python"))
    p.add_argument("--n", type=int, default=1_000_000)
    p.add_argument("--repeats", type=int, default=7)
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--out", default=str(ROOT / "bench" / "results" / "python.txt"))
    a = p.parse_args()
    build = pathlib.Path(a.build)
    program = build / "python" / "python_eval_loop"
    if not program.exists():
        sys.exit(f"python_bench: {program} is missing (bash scripts/python.sh builds it)")

    load = os.getloadavg()[0]
    lines = []
    rows = []
    for dtype in ("float32", "float64"):
        ratios, cpp_t, py_t = [], [], []
        for _ in range(a.rounds):
            c = time_cpp(program, dtype, a.n, a.repeats)
            m = time_module(dtype, a.n, a.repeats)
            cpp_t.append(c)
            py_t.append(m)
            ratios.append(m / c)
        rows.append((dtype, statistics.median(cpp_t), statistics.median(py_t), ratios))

    lines.append(f"# hairscatter Python module: vectorised eval vs the C++ loop ({datetime.date.today().isoformat()})")
    lines.append(f"# command: PYTHONPATH={build.relative_to(ROOT) if build.is_relative_to(ROOT) else build}/python "
                 f"python3 bench/python_bench.py --n {a.n} --repeats {a.repeats} --rounds {a.rounds}")
    lines.append(f"# machine: {cpu_line()}; {platform.platform()}; load average at the start "
                 f"{load:.2f} (a shared machine: each ratio compares timings of one round)")
    compiler = cache_value(build, "CMAKE_CXX_COMPILER")
    version = subprocess.run([compiler, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    lines.append(f"# compiler: {compiler} ({version})")
    lines.append(f"# flags (module and C++ loop alike): {cache_value(build, 'CMAKE_BUILD_TYPE')} "
                 f"{cache_value(build, 'CMAKE_CXX_FLAGS')} {cache_value(build, 'CMAKE_CXX_FLAGS_RELEASE')} -fPIC (module)")
    lines.append(f"# python {platform.python_version()}, numpy {np.__version__}, hairscatter {hs.__version__}")
    lines.append(f"# model: Chiang {MODEL}, N = {a.n} uniform (wo, wi, h); per round the median of {a.repeats} calls")
    lines.append("")
    lines.append(f"{'dtype':8} {'C++ loop ms':>12} {'module ms':>10} {'module/C++':>11}  per round")
    for dtype, c, m, ratios in rows:
        lines.append(f"{dtype:8} {1e3 * c:12.1f} {1e3 * m:10.1f} {statistics.median(ratios):10.3f}x  "
                     + " ".join(f"{r:.3f}" for r in ratios))
    text = "\n".join(lines) + "\n"
    pathlib.Path(a.out).write_text(text)
    print(text, end="")


if __name__ == "__main__":
    main()
