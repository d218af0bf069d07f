#!/usr/bin/env bash
# hairscatter benchmarks (not run by CI): configure, build, run, and write
# bench/results/chiang_<date>.txt with the machine, compiler, flags, the Google Benchmark
# medians and a table in calibration units (see bench/chiang_bench.cpp).
#
#   scripts/bench.sh                      full run (5 repetitions, medians; ~2-3 minutes)
#   scripts/bench.sh --quick              1 repetition, short runs: a smoke test, no results file
#   scripts/bench.sh --filter REGEX       only the matching benchmarks (plus the calibration loop)
#   scripts/bench.sh --min-time S         seconds per repetition (default 0.2)
#   scripts/bench.sh --out FILE           results file (default bench/results/chiang_<date>.txt)
#   scripts/bench.sh --headers REV        benchmark include/ as committed in REV (e.g. HEAD, to
#                                         compare with uncommitted header changes); the bench
#                                         code and build files are the working tree's. Builds in
#                                         build/bench-REV; default file chiang_<date>_<REV>.txt
#   scripts/bench.sh --no-deps            skip the apt package check (or HAIRSCATTER_SKIP_DEPS=1)
#   scripts/bench.sh --vs-pbrt            ours against pbrt-v4's algorithm in one process
#                                         (bench/vs_pbrt.cpp, built at -O2 and at -O3, each at
#                                         -march=native, x86-64-v3 and x86-64-v2 (x86-64 only),
#                                         float and double; --reps N repetitions, default 15):
#                                         writes bench/results/vs_pbrt.md, then regenerates the
#                                         tables of README.md and docs/performance.md from it
#                                         (~12 min)
#   scripts/bench.sh --tables             only that last step, from the committed vs_pbrt.md
#   scripts/bench.sh --vs-cycles          HuangFiber against Blender Cycles' scheme for the same
#                                         model in one process (bench/vs_cycles.cpp, float and
#                                         double; --reps N repetitions, default 5), then both
#                                         against the physical reference's cache (the accuracy
#                                         mode, 16 seeds of Cycles' normals; ~30 min on 2 busy
#                                         cores): bench/results/vs_cycles_<date>.txt
#   scripts/bench.sh --programs           only the dual and tabulated programs (no Chiang run):
#                                         bench/results/{dual,tabulated}_<date>.txt
#   scripts/bench.sh --ab REV             dual_bench built against REV's include/ (A) and the
#                                         working tree's (B), run in alternation for --rounds N
#                                         rounds (default 10; scripts/bench_ab.py), only the
#                                         benchmarks of --filter (default: the BCSDF calls, not
#                                         the table builds): bench/results/dual_ab_<date>_<REV>.txt.
#                                         --ab-program chiang|tabulated: that program instead
#                                         (default filter: the float calls at β_m = 0.3);
#                                         --ab-program vs_pbrt_o2|vs_pbrt_o3: bench/vs_pbrt.cpp
#                                         at -O2 or -O3, our float calls (the -O3 build is the
#                                         only A/B at -O3); bench/results/<program>_ab_<date>_<REV>.txt.
#                                         Two runs minutes apart on a shared machine can differ
#                                         by more than a change; rounds seconds apart do not.
#
# Build tree: build/bench (Release; the bench targets add -O2 -march=native themselves,
# bench/CMakeLists.txt). Timings are the medians of the repetitions' CPU times: on a
# shared machine the wall time also counts the time other processes hold the core.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
# shellcheck source=SCRIPTDIR/lib.sh
source "$ROOT/scripts/lib.sh"

BUILD="$ROOT/build/bench"
SRC="$ROOT"
headers_rev=""
reps=5
min_time=0.2
filter=""
out=""
quick=0
install_deps=1
mode=chiang
vs_reps=15
ab_rounds=10
ab_prog=dual
[[ "${HAIRSCATTER_SKIP_DEPS:-0}" == 1 ]] && install_deps=0

while [[ $# -gt 0 ]]; do
    case "$1" in
        --quick) quick=1; reps=1; min_time=0.05 ;;
        --filter) filter="$2"; shift ;;
        --min-time) min_time="$2"; shift ;;
        --out) out="$2"; shift ;;
        --headers) headers_rev="$2"; shift ;;
        --no-deps) install_deps=0 ;;
        --vs-pbrt) mode=vs_pbrt ;;
        --tables) mode=tables ;;
        --vs-cycles) mode=vs_cycles ;;
        --programs) mode=programs ;;
        --ab) mode=ab; headers_rev="${2:?--ab needs a revision}"; shift ;;
        --rounds) ab_rounds="$2"; shift ;;
        --ab-program) ab_prog="$2"; shift ;;
        --reps) vs_reps="$2"; vs_reps_cycles="$2"; shift ;;
        -h | --help) hs_usage; exit 0 ;;
        *) hs_usage_error "unknown option '$1'" ;;
    esac
    shift
done

VS_MD="$ROOT/bench/results/vs_pbrt.md"
regenerate_tables() {
    python3 "$ROOT/scripts/vs_pbrt.py" tables "$VS_MD" "$ROOT/README.md" "$ROOT/docs/performance.md"
    echo "bench.sh: regenerated the tables of README.md and docs/performance.md from ${VS_MD#"$ROOT"/}"
}
if [[ $mode == tables ]]; then
    regenerate_tables
    exit 0
fi

# --- dependencies ---------------------------------------------------------------------
[[ $install_deps == 1 ]] && bash "$ROOT/scripts/install-deps.sh" bench

# --- ours against pbrt-v4's algorithm (bench/vs_pbrt.cpp) --------------------------------
if [[ $mode == vs_pbrt ]]; then
    cmake -S "$SRC" -B "$BUILD" -DHAIRSCATTER_BUILD_BENCH=ON -DHAIRSCATTER_BUILD_TESTS=OFF -DHAIRSCATTER_DOCS=OFF \
        -DCMAKE_BUILD_TYPE=Release >/dev/null
    # -march=native, then x86-64-v3 and x86-64-v2 where the compiler targets x86-64.
    vs_targets=(vs_pbrt_o2 vs_pbrt_o3)
    if grep -q 'vs_pbrt_o2_v3' "$BUILD/bench/Makefile" "$BUILD/build.ninja" 2>/dev/null; then
        vs_targets+=(vs_pbrt_o2_v3 vs_pbrt_o3_v3 vs_pbrt_o2_v2 vs_pbrt_o3_v2)
    fi
    cmake --build "$BUILD" --target "${vs_targets[@]}" -j "$(nproc 2>/dev/null || echo 2)"
    cxx="$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$BUILD/CMakeCache.txt")"
    header="$BUILD/vs_pbrt.header.txt"
    load_before="$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo '?')"
    args=(--benchmark_repetitions="$vs_reps" --benchmark_min_time=0.1 --benchmark_enable_random_interleaving=true)
    for t in "${vs_targets[@]}"; do
        echo "bench.sh: $t ${args[*]}"
        "$BUILD/bench/$t" "${args[@]}" 2>&1 | tee "$BUILD/$t.txt"
    done
    {
        echo "date:      $(date -u '+%Y-%m-%d %H:%M:%S UTC')"
        dirty="$(git -C "$ROOT" status --porcelain -- include bench ':!bench/results' 2>/dev/null | head -1 || true)"
        echo "commit:    $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo '?')${dirty:+ (with uncommitted changes in include/ or bench/)}"
        echo "cpu:       $(hs_cpu_line)"
        echo "compiler:  $("$cxx" --version | head -1)"
        for t in "${vs_targets[@]}"; do
            echo "flags $t: $(sed -n 's/.*"flags": "\(.*\)".*/\1/p; s/^flags: //p' "$BUILD/$t.txt" | head -1)"
        done
        echo "run:       ${vs_targets[*]}, one after the other, each ${args[*]}"
        echo "load:      average before ${load_before}, after $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo '?')"
    } >"$header"
    vs_runs=()
    for t in "${vs_targets[@]}"; do vs_runs+=("$BUILD/$t.txt"); done
    python3 "$ROOT/scripts/vs_pbrt.py" results "$VS_MD" "$header" "${vs_runs[@]}"
    echo "bench.sh: wrote ${VS_MD#"$ROOT"/}"
    regenerate_tables
    exit 0
fi

# --- HuangFiber against Cycles' scheme (bench/vs_cycles.cpp) ------------------------------
if [[ $mode == vs_cycles ]]; then
    cmake -S "$SRC" -B "$BUILD" -DHAIRSCATTER_BUILD_BENCH=ON -DHAIRSCATTER_BUILD_TESTS=OFF -DHAIRSCATTER_DOCS=OFF \
        -DCMAKE_BUILD_TYPE=Release >/dev/null
    cmake --build "$BUILD" --target vs_cycles -j "$(nproc 2>/dev/null || echo 2)"
    [[ -x "$BUILD/bench/vs_cycles" ]] || { echo "bench.sh: vs_cycles was not built (it needs Boost.Math)" >&2; exit 1; }
    cxx="$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$BUILD/CMakeCache.txt")"
    out="${out:-$ROOT/bench/results/vs_cycles_$(date -u +%Y-%m-%d).txt}"
    load_before="$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo '?')"
    args=(--benchmark_repetitions="${vs_reps_cycles:-5}" --benchmark_min_time=0.2 --benchmark_enable_random_interleaving=true
          --benchmark_report_aggregates_only=true)
    "$BUILD/bench/vs_cycles" "${args[@]}" 2>&1 | tee "$BUILD/vs_cycles.txt"
    load_mid="$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo '?')"
    "$BUILD/bench/vs_cycles" --accuracy "$ROOT/tests/data/physical_fiber.txt" --seeds 16 --threads "$(nproc 2>/dev/null || echo 2)" \
        | tee "$BUILD/vs_cycles_accuracy.txt"
    {
        echo "date:      $(date -u '+%Y-%m-%d %H:%M:%S UTC')"
        dirty="$(git -C "$ROOT" status --porcelain -- include bench ':!bench/results' 2>/dev/null | head -1 || true)"
        echo "commit:    $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo '?')${dirty:+ (with uncommitted changes in include/ or bench/)}"
        echo "cpu:       $(hs_cpu_line)"
        echo "compiler:  $("$cxx" --version | head -1)"
        echo "run:       vs_cycles ${args[*]}; medians of CPU time"
        echo "load:      average before ${load_before}, after the timing ${load_mid}"
        echo
        cat "$BUILD/vs_cycles.txt"
        echo
        cat "$BUILD/vs_cycles_accuracy.txt"
    } >"$out"
    echo "bench.sh: wrote ${out#"$ROOT"/}"
    exit 0
fi

# --- build ------------------------------------------------------------------------------
if [[ -n "$headers_rev" ]]; then
    # A source tree of its own: the working tree's build files and bench/, REV's include/.
    rev_name="$(git -C "$ROOT" rev-parse --short "$headers_rev")"
    SRC="$ROOT/build/bench-src-$rev_name"
    BUILD="$ROOT/build/bench-$rev_name"
    rm -rf "$SRC"
    mkdir -p "$SRC"
    for f in CMakeLists.txt cmake LICENSE bench; do
        if [[ -e "$ROOT/$f" ]]; then cp -r "$ROOT/$f" "$SRC/"; fi
    done
    rm -rf "$SRC/bench/results"
    git -C "$ROOT" archive "$headers_rev" include | tar -x -C "$SRC"
fi
cmake -S "$SRC" -B "$BUILD" -DHAIRSCATTER_BUILD_BENCH=ON -DHAIRSCATTER_BUILD_TESTS=OFF -DHAIRSCATTER_DOCS=OFF \
    -DCMAKE_BUILD_TYPE=Release >/dev/null
if [[ $mode == ab ]]; then
    case $ab_prog in
        dual | chiang | tabulated) ab_target="${ab_prog}_bench" ;;
        vs_pbrt_o2 | vs_pbrt_o3) ab_target="$ab_prog" ;;
        *) echo "bench.sh: --ab-program is dual, chiang, tabulated, vs_pbrt_o2 or vs_pbrt_o3, not '$ab_prog'" >&2
           exit 2 ;;
    esac
    cmake --build "$BUILD" --target "$ab_target" -j "$(nproc 2>/dev/null || echo 2)"
elif [[ $mode == programs ]]; then
    cmake --build "$BUILD" --target dual_bench dual_icount tabulated_bench -j "$(nproc 2>/dev/null || echo 2)"
else
    cmake --build "$BUILD" --target chiang_bench bench_crosscheck dual_bench dual_icount tabulated_bench \
        -j "$(nproc 2>/dev/null || echo 2)"
fi
cxx="$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$BUILD/CMakeCache.txt")"

# --- the other programs: dual scattering (table build, density march, the dual BCSDF) and
# the tabulated fiber (build, eval/pdf/sample, the cost split of eval) ---------------------
# Instructions per call of bench/dual_icount under callgrind (load-independent): the
# difference between 6000 and 2000 calls, over 4000.
# Where -march=native has AVX-512, which valgrind cannot run, the counts come from a build
# for x86-64-v3 instead (named in the output; lib.sh: hs_native_has_avx512).
dual_icounts() {
    command -v valgrind >/dev/null || { echo "(valgrind not found: no instruction counts)"; return; }
    local names=("single eval" "dual eval" "single sample" "dual sample") counts=() bin="$BUILD/bench/dual_icount"
    local march="-march=native (the bench build)"
    if hs_native_has_avx512 "$cxx"; then
        bin="$BUILD/dual_icount_x86-64-v3"
        march="-march=x86-64-v3 (this CPU has AVX-512, which valgrind cannot run)"
        "$cxx" -std=c++17 -O2 -march=x86-64-v3 -DNDEBUG -I"$SRC/include" "$ROOT/bench/dual_icount.cpp" -o "$bin" ||
            { echo "(could not build dual_icount for x86-64-v3: no instruction counts)"; return; }
    fi
    for kind in 0 1 2 3; do
        local n=() log
        for calls in 2000 6000; do
            log="$(valgrind --tool=callgrind --callgrind-out-file=/dev/null --error-exitcode=3 "$bin" "$calls" "$kind" 2>&1)" ||
                { echo "(valgrind could not run $bin: no instruction counts)"; return; }
            n+=("$(awk '/Collected/ {print $4}' <<<"$log")")
        done
        counts+=($(( (n[1] - n[0]) / 4000 )))
    done
    echo "== Instructions per call (valgrind --tool=callgrind, bench/dual_icount, float, -O2 $march; load-independent) =="
    echo
    for kind in 0 1 2 3; do printf '  %-14s %6d\n' "${names[$kind]}" "${counts[$kind]}"; done
    printf '  dual / single: eval %s, sample %s\n' "$(python3 -c "print('%.2fx' % (${counts[1]} / ${counts[0]}))")" \
        "$(python3 -c "print('%.2fx' % (${counts[3]} / ${counts[2]}))")"
}

run_programs() {
    for prog in dual tabulated; do
        [[ -z "$filter" && -x "$BUILD/bench/${prog}_bench" ]] || continue
        prog_out="$ROOT/bench/results/${prog}_$(date +%Y-%m-%d)${headers_rev:+_$rev_name}.txt"
        prog_json="$BUILD/${prog}_bench.json"
        prog_args=(--benchmark_repetitions="$reps" --benchmark_min_time="$min_time"
                   --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true
                   --benchmark_out="$prog_json" --benchmark_out_format=json)
        echo "bench.sh: ${prog}_bench ${prog_args[*]}"
        prog_load_before="$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo '?')"
        prog_busy="$(ps -eo pcpu=,comm= --sort=-pcpu 2>/dev/null | awk '$1 > 5 {printf "%s(%s%%) ", $2, $1}' || true)"
        prog_console="$("$BUILD/bench/${prog}_bench" "${prog_args[@]}" 2>&1 | grep -v -E '_(mean|stddev) ')"
        {
            echo "hairscatter benchmark: bench/${prog}_bench.cpp (scripts/bench.sh)"
            echo
            echo "date:      $(date -u '+%Y-%m-%d %H:%M:%S UTC')"
            dirty="$(git -C "$ROOT" status --porcelain -- include bench ':!bench/results' 2>/dev/null | head -1 || true)"
            echo "commit:    $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo '?')${dirty:+ (with uncommitted changes in include/ or bench/)}"
            echo "cpu:       $(hs_cpu_line)"
            echo "compiler:  $("$cxx" --version | head -1); flags -O2 -march=native -DNDEBUG (bench/CMakeLists.txt)"
            echo "run:       ${prog}_bench ${prog_args[*]:0:4} (medians of the CPU time)"
            echo "load:      average before ${prog_load_before}, after $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo '?')"
            [[ -n "$prog_busy" ]] && echo "           other busy processes at the start: ${prog_busy}"
            echo
            python3 "$ROOT/scripts/bench_ratios.py" "$prog" "$prog_json"
            echo
            [[ $prog == dual ]] && { dual_icounts; echo; }
            echo "$prog_console"
        } >"$prog_out"
        echo "bench.sh: wrote ${prog_out#"$ROOT"/}"
    done
}
if [[ $mode == programs ]]; then
    run_programs
    exit 0
fi
if [[ $mode == ab ]]; then
    # B: the working tree's program (A, REV's, was built above).
    cmake -S "$ROOT" -B "$ROOT/build/bench" -DHAIRSCATTER_BUILD_BENCH=ON -DHAIRSCATTER_BUILD_TESTS=OFF \
        -DHAIRSCATTER_DOCS=OFF -DCMAKE_BUILD_TYPE=Release >/dev/null
    cmake --build "$ROOT/build/bench" --target "$ab_target" -j "$(nproc 2>/dev/null || echo 2)"
    ab_out="${out:-$ROOT/bench/results/${ab_prog}_ab_$(date +%Y-%m-%d)_$rev_name.txt}"
    case $ab_prog in
        dual) ab_default='BM_(Single|Dual)(At)?(Eval|Sample)' ;;
        chiang) ab_default='BM_(Eval|Pdf|Sample|AtEval|AtSample|Hit)<float>/bm:1(/wi:0)?$' ;;
        tabulated) ab_default='BM_(At)?(Eval|Pdf|Sample)<float>/res:1/bm:1(/wi:0)?$' ;;
        vs_pbrt_o2 | vs_pbrt_o3) ab_default='BM_Ours(Eval|Pdf|Sample|Vertex|AtEval)<float>' ;;
    esac
    ab_flags="-O2 -march=native -DNDEBUG (bench/CMakeLists.txt)"
    [[ $ab_prog == vs_pbrt_o3 ]] && ab_flags="-O3 -march=native -DNDEBUG (bench/CMakeLists.txt)"
    ab_filter="${filter:-$ab_default}"
    echo "bench.sh: $ab_target, $rev_name against the working tree, $ab_rounds rounds (filter $ab_filter)"
    ab_load_before="$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo '?')"
    ab_table="$(python3 "$ROOT/scripts/bench_ab.py" "$BUILD/bench/$ab_target" "$ROOT/build/bench/bench/$ab_target" \
        --filter "$ab_filter" --rounds "$ab_rounds" --min-time "$min_time")"
    {
        echo "hairscatter benchmark: bench/${ab_target%_o[23]}.cpp ($ab_target), two header revisions in alternation (scripts/bench.sh --ab)"
        echo
        echo "date:      $(date -u '+%Y-%m-%d %H:%M:%S UTC')"
        dirty="$(git -C "$ROOT" status --porcelain -- include bench ':!bench/results' 2>/dev/null | head -1 || true)"
        echo "A:         include/ of commit $rev_name (--ab $headers_rev)"
        echo "B:         the working tree, commit $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo '?')${dirty:+ (with uncommitted changes in include/ or bench/)}"
        echo "cpu:       $(hs_cpu_line)"
        echo "compiler:  $("$cxx" --version | head -1); flags $ab_flags"
        echo "load:      average before ${ab_load_before}, after $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo '?')"
        echo
        echo "$ab_table"
    } >"$ab_out"
    cat "$ab_out"
    echo "bench.sh: wrote ${ab_out#"$ROOT"/}"
    exit 0
fi

BENCH="$BUILD/bench/chiang_bench"
CROSS="$BUILD/bench/bench_crosscheck"
JSON="$BUILD/chiang_bench.json"
CONSOLE="$BUILD/chiang_bench.console.txt"
CROSSOUT="$BUILD/bench_crosscheck.txt"

# --- run --------------------------------------------------------------------------------
echo "bench.sh: cross-check"
"$CROSS" | tee "$CROSSOUT"

load_before="$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo '?')"
busy_before="$(ps -eo pcpu=,comm= --sort=-pcpu 2>/dev/null | awk '$1 > 5 {printf "%s(%s%%) ", $2, $1}' || true)"
# Repetitions interleaved in random order, so that a burst of load from another process
# spoils one repetition of many benchmarks instead of every repetition of one.
args=(--benchmark_repetitions="$reps" --benchmark_min_time="$min_time"
      --benchmark_enable_random_interleaving=true
      --benchmark_out="$JSON" --benchmark_out_format=json)
[[ $reps -gt 1 ]] && args+=(--benchmark_report_aggregates_only=true)
[[ -n "$filter" ]] && args+=(--benchmark_filter="BM_Calib|$filter")
echo "bench.sh: $BENCH ${args[*]}"
start=$(date +%s)
"$BENCH" "${args[@]}" 2>&1 | tee "$CONSOLE"
elapsed=$(( $(date +%s) - start ))
load_after="$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo '?')"

if [[ $quick == 1 && -z "$out" ]]; then
    echo "bench.sh: --quick: no results file written"
    exit 0
fi

# --- the results file -------------------------------------------------------------------
mkdir -p "$ROOT/bench/results"
if [[ -z "$out" ]]; then
    out="$ROOT/bench/results/chiang_$(date +%Y-%m-%d)${headers_rev:+_$rev_name}.txt"
fi

compile_cmd="$(python3 - "$BUILD/compile_commands.json" <<'EOF'
import json, sys
for e in json.load(open(sys.argv[1])):
    if e["file"].endswith("bench/chiang_bench.cpp"):
        print(e.get("command") or " ".join(e.get("arguments", [])))
        break
EOF
)"

{
    echo "hairscatter benchmark: Chiang model (bench/chiang_bench.cpp, scripts/bench.sh)"
    echo
    echo "date:      $(date -u '+%Y-%m-%d %H:%M:%S UTC')"
    if [[ -n "$headers_rev" ]]; then
        echo "headers:   include/ of commit $rev_name (--headers $headers_rev); bench/ from the working tree"
    else
        dirty="$(git -C "$ROOT" status --porcelain -- include 2>/dev/null | head -1 || true)"
        echo "commit:    $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo '?')${dirty:+ (with uncommitted changes in include/)}"
    fi
    echo "           sha1 of include/**/*.hpp $(cd "$SRC" && find include -name '*.hpp' | LC_ALL=C sort | xargs cat | sha1sum | cut -c1-12)"
    echo "uname -a:  $(uname -a)"
    echo "cpu:       $(hs_cpu_line) ($(lscpu | sed -n 's/^CPU(s):[[:space:]]*//p' | head -1) CPUs)"
    echo "compiler:  $("$cxx" --version | head -1)"
    march="$("$cxx" -march=native -Q --help=target 2>/dev/null | awk '$1 == "-march=" {print $2}' | head -1 || true)"
    echo "flags:     -O2 -march=native (= ${march:-?} here) -DNDEBUG on the bench targets; they come after"
    echo "           the Release flags, so -O2 wins over -O3. The compile command:"
    echo "           ${compile_cmd}"
    echo "run:       chiang_bench ${args[*]}"
    echo "           ${elapsed} s; load average before ${load_before}, after ${load_after}"
    [[ -n "$busy_before" ]] && echo "           other busy processes at the start: ${busy_before}"
    echo
    echo "== Summary (from the medians of the CPU times) =="
    echo
    python3 - "$JSON" <<'EOF'
import json, re, sys

data = json.load(open(sys.argv[1]))
rows = {}
cv = []
for b in data["benchmarks"]:
    agg = b.get("aggregate_name")
    name = b.get("run_name", b["name"])
    if agg == "cv":
        cv.append((b["cpu_time"], name))
    if agg not in (None, "median"):
        continue
    if agg is None and any(x.get("aggregate_name") for x in data["benchmarks"]):
        continue
    rows[name] = b["cpu_time"]  # ns

def get(fn, T, bm=None, wi=None):
    n = "%s<%s>" % (fn, T)
    if bm is not None:
        n += "/bm:%d" % bm
    if wi is not None:
        n += "/wi:%d" % wi
    return rows.get(n)

calf = get("BM_Calib", "float")
cald = get("BM_Calib", "double")
if not calf:
    print("(no calibration result: cannot form the table)")
    sys.exit(0)
print("calibration loop body: float %.1f ns, double %.1f ns. u = ns / %.1f ns (the float calibration loop) in"
      % (calf, cald or float("nan"), calf))
print("both tables. pbrt-v4 (stated for this machine kind, float, -O2 -march=native): f 6.5 u, Sample_f 14 u,")
print("PDF 6.6 u; the goal is ours <= pbrt/4, i.e. eval <= 1.63 u and sample <= 3.50 u. 'x pbrt' = stated pbrt u /")
print("our u (goal >= 4); 'ref/ours' = bench_ref (reference/pbrt_style.hpp, same binary) / ours.")
print("eval_pdf's reference is f + PDF (pbrt has no combined call); ctor = the per-hit constructor")
print("(ChiangFiber from a ChiangMaterial; bench_ref::HairBxDF like pbrt's), material = ChiangMaterial.")
print("at(wo) = binding a fiber to wo (the wo terms, once per hit); at.eval / at.sample = each call on a bound")
print("fiber (compared with pbrt's per-call f / Sample_f, which redo the wo terms); hit = one path vertex as a")
print("renderer shades it: fiber + at(wo) + eval(light wi) + sample(u), against pbrt's f + Sample_f (6.5 + 14 u)")
print("and the reference's HairBxDF + f + Sample_f.")
betas = ["0.05", "0.30", "1.00"]
calls = [("eval", "BM_Eval", "BM_RefF", True, 6.5), ("pdf", "BM_Pdf", "BM_RefPdf", True, 6.6),
         ("eval_pdf", "BM_EvalPdf", None, True, None), ("sample", "BM_Sample", "BM_RefSample", False, 14.0),
         ("ctor", "BM_FiberCtor", "BM_RefCtor", False, None), ("material", "BM_MaterialCtor", None, False, None),
         ("at(wo)", "BM_At", None, False, None), ("at.eval", "BM_AtEval", "BM_RefF", True, 6.5),
         ("at.sample", "BM_AtSample", "BM_RefSample", False, 14.0), ("hit", "BM_Hit", "BM_RefHit", False, 20.5)]
for T in ("float", "double"):
    print()
    print("%s:" % T)
    print("  %-9s %-5s %-8s %9s %7s %9s %7s %9s %8s" % ("call", "b_m", "wi", "ours ns", "ours u", "ref ns", "ref u",
                                                      "ref/ours", "x pbrt"))
    for call, fn, rfn, has_wi, pbrt_u in calls:
        for wi in ((0, 1) if has_wi else (None,)):
            for bm in range(3):
                ours = get(fn, T, bm, wi)
                if ours is None:
                    continue
                if call == "eval_pdf":
                    a, b = get("BM_RefF", T, bm, wi), get("BM_RefPdf", T, bm, wi)
                    ref = a + b if a is not None and b is not None else None
                else:
                    ref = get(rfn, T, bm, wi) if rfn else None
                wis = "-" if wi is None else ("uniform", "sampled")[wi]
                line = "  %-9s %-5s %-8s %9.1f %7.2f" % (call, betas[bm], wis, ours, ours / calf)
                line += (" %9.1f %7.2f %9.2f" % (ref, ref / calf, ref / ours)) if ref else " %9s %7s %9s" % ("", "", "")
                if pbrt_u and T == "float":
                    line += " %8.2f" % (pbrt_u / (ours / calf))
                print(line.rstrip())

def slow(fn, T, wi, bm):
    a, b = get(fn, T, 1, wi), get(fn, T, bm, wi)
    return b / a if a and b else float("nan")
print()
print("slow paths: time at beta_m = 1.0 and at 0.05, each / time at beta_m = 0.3 (pbrt-v4 f: 2.3x at 1.0):")
print("  %-22s %8s %8s" % ("", "1.0", "0.05"))
for label, fn, wi in (("ours eval", "BM_Eval", 0), ("ours eval (wi sampled)", "BM_Eval", 1),
                      ("ours sample", "BM_Sample", None), ("ref f", "BM_RefF", 0),
                      ("ref f (wi sampled)", "BM_RefF", 1), ("ref Sample_f", "BM_RefSample", None)):
    for T in ("float", "double"):
        print("  %-22s %7.2fx %7.2fx  %s" % (label, slow(fn, T, wi, 2), slow(fn, T, wi, 0), T))
if cv:
    cv.sort(reverse=True)
    print()
    print("noise: coefficient of variation of the CPU time over the repetitions: median %.1f %%, max %.1f %% (%s)"
          % (100 * sorted(c for c, _ in cv)[len(cv) // 2], 100 * cv[0][0], cv[0][1]))
EOF
    echo
    echo "== bench_crosscheck (double; and float accuracy against the accurate double reference) =="
    echo
    cat "$CROSSOUT"
    echo
    echo "== Google Benchmark console output (medians and coefficients of variation) =="
    echo
    echo "(\"Library was built as DEBUG\" refers to Debian's libbenchmark package, not to this code.)"
    echo
    grep -v -E '_(mean|stddev) ' "$CONSOLE"
} >"$out"

echo "bench.sh: wrote ${out#"$ROOT"/}"

run_programs
