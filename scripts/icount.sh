#!/usr/bin/env bash
# Instructions per call (valgrind --tool=callgrind: independent of the machine's load) of
# bench/chiang_icount and bench/dual_icount, built against the headers of git revision REV
# and against the working tree's, with g++ at -O2 and at -O3 (-DNDEBUG).
# Each count is the difference between 6000 and 2000 calls, over 4000: one call without the
# setup. Writes bench/results/icount_<date>.txt (--out FILE to change it). Not run by CI.
# CXX=clang++ counts Clang's code instead of GCC's (the compiler is named in the file).
# MARCH sets -march (default native; x86-64-v3 where native has AVX-512, which valgrind
# cannot run). A program valgrind cannot run fails the script instead of counting 0.
#
#   scripts/icount.sh REV [--out FILE]
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
# shellcheck source=SCRIPTDIR/lib.sh
source "$ROOT/scripts/lib.sh"
rev="${1:?usage: scripts/icount.sh REV [--out FILE]}"
shift
out="$ROOT/bench/results/icount_$(date +%Y-%m-%d).txt"
[[ "${1:-}" == --out ]] && out="${2:?--out needs a file}"
cxx="${CXX:-g++}"
command -v "$cxx" >/dev/null || { echo "icount: compiler $cxx not found" >&2; exit 1; }
command -v valgrind >/dev/null || { echo "icount: valgrind not found (apt-get install valgrind)" >&2; exit 1; }
march="${MARCH:-native}"
if [[ -z "${MARCH:-}" ]] && hs_native_has_avx512 "$cxx"; then
    march=x86-64-v3
    echo "icount: this CPU has AVX-512, which valgrind cannot run: counting -march=$march" >&2
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/old"
git archive "$rev" include | tar -x -C "$work/old"
short="$(git rev-parse --short "$rev")"

count() {  # program kind -> instructions per call
    local n=() calls log
    for calls in 2000 6000; do
        log="$(valgrind --tool=callgrind --callgrind-out-file=/dev/null --error-exitcode=3 "$1" "$calls" "$2" 2>&1)" || {
            printf '%s\n' "$log" | tail -n 5 >&2
            echo "icount: $1 failed under valgrind (set MARCH to an older -march?)" >&2
            return 1
        }
        n+=("$(awk '/Collected/ {print $4}' <<<"$log")")
    done
    echo $(( (n[1] - n[0]) / 4000 ))
}

declare -A kinds=([chiang_icount]="0:eval 1:sample 2:at(wo)+pdf"
                  [dual_icount]="0:single_eval 1:dual_eval 2:single_sample 3:dual_sample")
{
    echo "hairscatter instruction counts: scripts/icount.sh $rev"
    echo
    echo "date:      $(date -u '+%Y-%m-%d %H:%M:%S') UTC"
    echo "commit:    $(git rev-parse --short HEAD)$(git diff --quiet HEAD -- include bench ':!bench/results' || echo ' (with uncommitted changes in include/ or bench/)')"
    echo "compiler:  $("$cxx" --version | head -n 1); flags -std=c++17 -march=$march -DNDEBUG, -O2 and -O3"
    echo "method:    valgrind --tool=callgrind, (calls 6000 - calls 2000) / 4000; float"
    echo
    printf '  %-14s %-14s %-5s %8s %8s\n' program call opt "$short" new
    for prog in chiang_icount dual_icount; do
        for opt in -O2 -O3; do
            for side in old new; do
                inc="$ROOT/include"
                [[ $side == old ]] && inc="$work/old/include"
                "$cxx" -std=c++17 "$opt" -march="$march" -DNDEBUG -I"$inc" "bench/$prog.cpp" -o "$work/${prog}_$side"
            done
            for k in ${kinds[$prog]}; do
                a="$(count "$work/${prog}_old" "${k%%:*}")"  # (an assignment: a failure stops the script)
                b="$(count "$work/${prog}_new" "${k%%:*}")"
                printf '  %-14s %-14s %-5s %8d %8d\n' "$prog" "${k#*:}" "$opt" "$a" "$b"
            done
        done
    done
} | tee "$out"
echo "icount: wrote ${out#"$ROOT"/}"
