#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang (-fsanitize=fuzzer,address,undefined) and
# runs each from its committed corpus fuzz/corpus/<target> (copied: new inputs go to the
# build tree, the committed corpus is not changed). Two modes:
#   - exploring (the default): each target for FUZZ_SECONDS (default 60) from the seed
#     FUZZ_SEED (default: a fresh one, printed), so that every run searches new ground;
#   - --repeatable (what scripts/test.sh and CI run): a fixed number of inputs per target
#     from seed 1 (FUZZ_SEED to change it), 30–60 s each on a 2-core machine, without
#     address randomisation (setarch -R, where the machine allows it). Two runs on one
#     machine then try the same inputs; another machine can still part from them where its
#     C library computes a maths function differently (docs/robustness.md).
# A crash leaves its input in <build>/crashes/<target>/ and fails the run: fix it and add the
# input to fuzz/corpus/<target>/ as a regression. Skipped, with a message, when clang or its
# libFuzzer is missing.
#
#   fuzz/run.sh [--build DIR] [-j N] [--seconds S | --repeatable] [target ...]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="$ROOT/build/fuzz"
SECONDS_EACH="${FUZZ_SECONDS:-60}"
repeatable=0
targets=()
while [[ $# -gt 0 ]]; do
    case "$1" in
        --build) BUILD="$2"; shift ;;
        --seconds) SECONDS_EACH="$2"; shift ;;
        --repeatable) repeatable=1 ;;
        -j) shift ;;  # accepted for test.sh; the targets build one by one
        -j*) ;;
        *) targets+=("$1") ;;
    esac
    shift
done
[[ ${#targets[@]} -gt 0 ]] || targets=(hair_file_fuzz dual_tables_fuzz model_fuzz bcsdf_fuzz)

CXX="${FUZZ_CXX:-clang++}"
if ! command -v "$CXX" >/dev/null 2>&1; then
    echo "fuzz: $CXX not found: fuzzing skipped (apt-get install clang)"
    exit 0
fi
mkdir -p "$BUILD"
probe="$BUILD/probe.cpp"
printf '#include <cstddef>\n#include <cstdint>\nextern "C" int LLVMFuzzerTestOneInput(const std::uint8_t*, std::size_t) { return 0; }\n' >"$probe"
if ! "$CXX" -fsanitize=fuzzer "$probe" -o "$BUILD/probe" >/dev/null 2>&1; then
    echo "fuzz: $CXX cannot link libFuzzer (-fsanitize=fuzzer): fuzzing skipped"
    exit 0
fi

[[ -d /usr/include/glm ]] || { echo "fuzz: GLM headers not found" >&2; exit 1; }
FLAGS=(-std=c++17 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all
       -fno-omit-frame-pointer -I"$ROOT/include" -I"$ROOT/examples/render")
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:${UBSAN_OPTIONS:-}"

# --repeatable: inputs per target, 30–60 s each here (exec/s 16–30,000 by target; bcsdf_fuzz
# builds a Huang material for most new inputs, its reflectance tables ~60 ms each under the
# sanitizers: 4,000 inputs took 244 s on a 2-core CI machine, past the fastmath, consumer and
# cuda steps it runs beside).
declare -A RUNS=([hair_file_fuzz]=600000 [dual_tables_fuzz]=60000 [model_fuzz]=120000 [bcsdf_fuzz]=1000)
if [[ $repeatable == 1 ]]; then
    seed="${FUZZ_SEED:-1}"
else
    seed="${FUZZ_SEED:-$(( (RANDOM << 15 | RANDOM) + 1 ))}"
fi

# Repeatable also means: no address randomisation (libFuzzer keeps inputs by the values they
# make the code compare, pointers among them, so with it two runs from one seed part after
# a few dozen inputs) and no periodic re-reading of the corpus directory.
launch=()
if [[ $repeatable == 1 ]]; then
    if setarch "$(uname -m)" -R true 2>/dev/null; then
        launch=(setarch "$(uname -m)" -R)
    else
        echo "fuzz: cannot turn address randomisation off here (setarch -R): runs from one seed may differ"
    fi
fi

failed=0
for t in "${targets[@]}"; do
    src=("$ROOT/fuzz/$t.cpp")
    [[ "$t" == hair_file_fuzz ]] && src+=("$ROOT/examples/render/hair_file.cpp")
    echo "+ $CXX ${src[*]##*/} -> $BUILD/$t"
    "$CXX" "${FLAGS[@]}" "${src[@]}" -o "$BUILD/$t"
    work="$BUILD/corpus/$t"
    crashes="$BUILD/crashes/$t"
    rm -rf "$work" "$crashes"
    mkdir -p "$work" "$crashes"
    cp "$ROOT/fuzz/corpus/$t"/* "$work"/ 2>/dev/null || true
    if [[ $repeatable == 1 ]]; then
        [[ -n "${RUNS[$t]:-}" ]] || { echo "fuzz: no input count for $t in RUNS (--repeatable)" >&2; exit 2; }
        budget=(-runs="${RUNS[$t]}" -reload=0) what="${RUNS[$t]} inputs"
    else
        budget=(-max_total_time="$SECONDS_EACH") what="${SECONDS_EACH}s"
    fi
    echo "+ $t for $what from seed $seed (corpus: $(ls "$work" | wc -l) inputs)"
    if ! "${launch[@]}" "$BUILD/$t" -seed="$seed" "${budget[@]}" -timeout=60 -rss_limit_mb=2048 -max_len=4096 \
        -print_final_stats=1 -artifact_prefix="$crashes/" "$work" >"$BUILD/$t.log" 2>&1; then
        echo "fuzz: $t FAILED; input(s) in $crashes, log $BUILD/$t.log" >&2
        tail -n 40 "$BUILD/$t.log" >&2
        failed=1
    else
        grep -E "^stat::number_of_executed_units|^Done" "$BUILD/$t.log" | tr '\n' ' '
        echo
    fi
done
exit "$failed"
