#!/usr/bin/env bash
# hairscatter stress run (not CI): random and adversarial calls of every model and of the
# dual-scattering BCSDF in float and double (bench/stress.cpp: edge directions, h = ±1,
# parameters at their limits, u at 0, 1 and 1 - ulp, light states at their limits,
# non-finite inputs), then docs/stress.md with the counts.
#
#   scripts/stress.sh                       1e8 calls per model and precision (Chiang,
#                                           tabulated, tabulated fast(), dual), 1e7 for the
#                                           far field and Marschner: about 35 min of one core
#   scripts/stress.sh --calls 2e6           a quick run (slow models: a tenth of it)
#   scripts/stress.sh --slow-calls N        the far field's and Marschner's count
#   scripts/stress.sh --dual-calls N        the dual BCSDF's count (default: --calls)
#   scripts/stress.sh --out FILE            another report file (default docs/stress.md)
#
# Builds build/stress/stress with the system C++ compiler (-O2, NDEBUG); needs only GLM.
# Runs on one thread, under nice (the machine is shared).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
calls=1e8
slow=""
dual=""
out="$ROOT/docs/stress.md"
while [[ $# -gt 0 ]]; do
    case "$1" in
        --calls) calls="$2"; shift ;;
        --slow-calls) slow="$2"; shift ;;
        --dual-calls) dual="$2"; shift ;;
        --out) out="$2"; shift ;;
        -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
        *) echo "stress.sh: unknown argument '$1'" >&2; exit 2 ;;
    esac
    shift
done
mkdir -p build/stress
CXX="${CXX:-g++}"
echo "+ $CXX -std=c++17 -O2 -DNDEBUG bench/stress.cpp -> build/stress/stress"
"$CXX" -std=c++17 -O2 -DNDEBUG -Wall -Wextra -I include bench/stress.cpp -o build/stress/stress
args=(--calls "$calls")
[[ -n "$slow" ]] && args+=(--slow-calls "$slow")
[[ -n "$dual" ]] && args+=(--dual-calls "$dual")
table="$(mktemp)"
commit="$(git rev-parse --short HEAD 2>/dev/null || echo unknown)"  # what was built, before a long run
start=$SECONDS
rc=0
nice -n 10 build/stress/stress "${args[@]}" --out "$table" || rc=$?
elapsed=$((SECONDS - start))
{
    echo "# Stress counts"
    echo
    echo "Written by \`scripts/stress.sh ${args[*]}\` (bench/stress.cpp) on $(date -u +%Y-%m-%d), commit"
    echo "$commit, $($CXX --version | head -n 1), -O2, one core, ${elapsed} s."
    echo
    echo "Each model and precision cycles through its parameter sets (materials): the defaults, both"
    echo "roughnesses at the documented lower limit (β_m = β_n = 1e-3; Marschner β_R = 1e-4 rad,"
    echo "β_n = 1e-3), at 1, one at each end, cuticle tilt ±π/8, σa = 0 and 50–100, η = 1.0001 and 3"
    echo "(Marschner: its defaults, the limits, eccentricity 0.85 with caustic gain 5). Directions are"
    echo "uniform on the sphere or, one call in 2.7, an edge: along the fiber axis, within 1e-6 of it,"
    echo "grazing, unnormalised by 1e-14, ±y, ±z; Chiang's h is uniform or exactly -1, 0, 1; each u"
    echo "component is uniform or exactly 0, 1 or 1 - ulp, and one call in 32 has one at 2 or -1 (every"
    echo "model clamps u into [0, 1]); one call in 64 has a NaN or ±Inf component in wo, wi or u, which"
    echo "must give the zero result, and one in 64 a wo or wi of another finite length (its largest"
    echo "component the largest float, 3, 1e-3 or 1e-30), which every model normalises"
    echo "(docs/robustness.md). Chiang and the dual BCSDF have two more materials with lobe gains far"
    echo "above 1 over a lossless fiber: every gain at the limit 1e6, and TT 100 with R 0 and TRT 10."
    echo
    echo "The dual-scattering BCSDF (over the Chiang fiber, the same materials, improved formulation on"
    echo "even materials and Zinke 2008's on odd ones) is called as a renderer calls it: eval under a"
    echo "light state, pdf, and at(wo, spread).sample with the pdf of the sample. Light states take"
    echo "direct fractions 0, ½, 1 and uniform; counts n and beyond from 0 through 1e-9, 1e7, 1e30 to"
    echo "kUnbounded; one in four a renderer's own T_f and σ̄²_f; one in 16 a NaN, negative or infinite"
    echo "field. Spread hints run from 0 to 1e6 and kUnbounded, one in 64 NaN or ±Inf. All of these must"
    echo "give finite, non-negative values; non-finite directions or u give 0 or no sample."
    echo
    echo "Counted over eval, pdf, eval_pdf, sample and the pdf of each sample's direction: NaN, Inf and"
    echo "negative values of f, pdf and the sample's weight and pdf (NaN and Inf also in its direction);"
    echo "non-finite inputs that did not give 0; and sample/pdf/eval mismatches: a sample whose pdf differs"
    echo "from pdf(wo, wi) of its direction, or whose weight × pdf differs from eval(wo, wi) in a channel,"
    echo "by more than 1e-4 relative (the dual BCSDF: its pdf; its value needs a light state). Samples"
    echo "exactly on the fiber axis (u.y at 0 or 1 can put sinθi at ±1) are counted and compared like any"
    echo "other. A difference that moving wi by up to 4 ulps of 1 explains (along each axis, and between,"
    echo "along the fiber's inclination and azimuth, where the sampler's exact value can sit on a narrow"
    echo "lobe's peak that no rounded direction reaches) is counted as rounding, not as a mismatch."
    echo "The far field and Marschner cost 10–50× more per call and run fewer calls (the slow-calls count:"
    echo "10^8 calls of the far field alone would take about an hour of one core per precision)."
    echo
    cat "$table"
} >"$out"
rm -f "$table"
echo "stress.sh: wrote $out (${elapsed} s)"
exit "$rc"
