#!/usr/bin/env bash
# The speed/accuracy study of every model and knob: builds bench/tradeoff,
# times eval/pdf/sample of each setting with Google Benchmark, measures its error against
# an independent double-precision reference and its furnace, and writes
#   docs/tradeoff.md    the table, the machine, compiler, flags, date and command
#   docs/tradeoff.csv   the same numbers, machine-readable
#   docs/tradeoff.png   error against eval time, log-log, one point per setting
# Not run by CI (about a minute or two on the 2-core machine).
#
#   scripts/tradeoff.sh [--quick] [--out DIR] [--no-deps]
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
# shellcheck source=SCRIPTDIR/lib.sh
source "$ROOT/scripts/lib.sh"
out="$ROOT/docs"
reps=5
min_time=0.1
quick_flag=()
install_deps=1
[[ "${HAIRSCATTER_SKIP_DEPS:-0}" == 1 ]] && install_deps=0
while [[ $# -gt 0 ]]; do
    case "$1" in
        --quick) reps=3; min_time=0.02; quick_flag=(--quick) ;;
        --out) out="$2"; shift ;;
        --no-deps) install_deps=0 ;;
        -h | --help) hs_usage; exit 0 ;;
        *) hs_usage_error "unknown option '$1'" ;;
    esac
    shift
done
[[ $install_deps == 1 ]] && bash "$ROOT/scripts/install-deps.sh" bench

BUILD="$ROOT/build/bench"
cmake -S "$ROOT" -B "$BUILD" -DHAIRSCATTER_BUILD_BENCH=ON -DHAIRSCATTER_BUILD_TESTS=OFF \
    -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" --target tradeoff -j "$(nproc 2>/dev/null || echo 2)"

work="$BUILD/tradeoff-out"
mkdir -p "$work" "$out"
cmd=("$BUILD/bench/tradeoff" --out "$work" ${quick_flag[@]+"${quick_flag[@]}"} --benchmark_repetitions="$reps"
     --benchmark_min_time="$min_time" --benchmark_report_aggregates_only=true)
"${cmd[@]}" | tee "$work/console.txt"

cp "$work/tradeoff.csv" "$out/tradeoff.csv"
gnuplot -e "csv='$out/tradeoff.csv'; png='$out/tradeoff.png'" "$ROOT/bench/tradeoff.gp"

{
    echo "# Speed against accuracy: every model and knob"
    echo
    echo "Made by \`scripts/tradeoff.sh${quick_flag:+ --quick}\` (program: \`bench/tradeoff.cpp\`, plot: \`bench/tradeoff.gp\`)"
    echo "on $(date -u +%Y-%m-%d), commit $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown),"
    echo "$(hs_cpu_line), $(c++ --version | head -1)."
    echo "Times are Google Benchmark medians of $reps repetitions (CPU time, one thread); ratios within"
    echo "this table are the meaningful comparison on a shared machine."
    echo
    echo "![error against eval time](tradeoff.png)"
    echo
    echo "The study material: η = 1.55, βm = βn = 0.3, α = 2°, brown hair (eumelanin 0.8);"
    echo "1024 direction pairs (wo uniform, h uniform, half of wi uniform and half drawn by the"
    echo "full Chiang sampler so the lobe peaks count). The error is Σ|f − f_ref| / Σ|f_ref| over"
    echo "the pairs and colour channels, against the reference of the setting's family:"
    echo
    echo "- *near field* (given h): \`tests/support/reference_chiang.hpp\`, pbrt-v4's model"
    echo "  transcribed in double with Boost's Bessel I0;"
    echo "- *far field* (integrated over h): \`tests/support/reference_farfield.hpp\`, adaptive"
    echo "  Gauss–Kronrod over h to 1e-11 with a brute-force wrapped Gaussian;"
    echo "- *Marschner*: its own model in double with the most accurate knob setting."
    echo
    echo "The furnace column is ∫ f dωi of the lossless fiber at θo = 0°, 40°, 80°, 89° (and"
    echo "h = −0.6, 0, 0.9 for near-field models), by a 256 × 512 Gauss–Legendre product rule:"
    echo "dropped lobes lose their energy, and Marschner's model is not normalised."
    echo
    cat "$work/tradeoff_table.md"
} >"$out/tradeoff.md"
echo "tradeoff.sh: wrote $out/tradeoff.md, $out/tradeoff.csv, $out/tradeoff.png"
