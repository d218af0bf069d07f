#!/usr/bin/env bash
# ThreadSanitizer over the example renderer's tiles (not in CI: the instrumented build alone
# takes several minutes on 2 cores). Builds examples/render with -fsanitize=thread into
# build/tsan, then renders a tiny hair block with every integrator (single, dual, path) on
# more threads than the machine has cores (--threads), so that tiles really run
# concurrently. Any report fails the run (TSan's exit code 66). First, the negative control
# tests/tsan/race_control.cpp (a deliberate race between TBB tasks) must be reported under
# the same suppressions.
#
#   scripts/tsan.sh                  # gcc (the default), 6 threads
#   CXX=clang++ scripts/tsan.sh      # clang
#   THREADS=8 scripts/tsan.sh
#
# TBB's and Embree's shared libraries are not instrumented; scripts/tsan.supp holds the
# suppressions for what that hides from TSan, each with its reason (docs/robustness.md).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
# shellcheck source=SCRIPTDIR/lib.sh
source "$ROOT/scripts/lib.sh"
hs_no_args "$@"
CXX="${CXX:-g++}"
THREADS="${THREADS:-6}"
BUILD_DIR="build/tsan"
flags="-O1 -g -fsanitize=thread -fno-omit-frame-pointer"
echo "== configure $BUILD_DIR ($CXX, $flags)"
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER="$CXX" \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread" \
    -DHAIRSCATTER_BUILD_EXAMPLES=ON -DHAIRSCATTER_BUILD_TESTS=OFF -DHAIRSCATTER_BUILD_BENCH=OFF \
    -DHAIRSCATTER_INSTALL=OFF -DHAIRSCATTER_DOCS=OFF >/dev/null
echo "== build render"
nice cmake --build "$BUILD_DIR" -j "${JOBS:-2}" --target render
mkdir -p "$BUILD_DIR/out"
# history_size=7: the longest history, so that the earlier access of a report keeps its
# stack (a report without it cannot be matched against the suppressions).
export TSAN_OPTIONS="suppressions=$ROOT/scripts/tsan.supp history_size=7 second_deadlock_stack=1 ${TSAN_OPTIONS:-}"
echo "== negative control: tests/tsan/race_control.cpp must be reported"
"$CXX" -std=c++17 $flags tests/tsan/race_control.cpp -o "$BUILD_DIR/race_control" -ltbb
control_rc=0
"$BUILD_DIR/race_control" >"$BUILD_DIR/race_control.log" 2>&1 || control_rc=$?
if [[ $control_rc -ne 66 ]] || ! grep -q "SUMMARY: ThreadSanitizer: data race .*race_control.cpp" "$BUILD_DIR/race_control.log"; then
    cat "$BUILD_DIR/race_control.log" >&2
    echo "tsan.sh: the deliberate race was not reported (exit $control_rc): the suppressions hide too much" >&2
    exit 1
fi
echo "reported, as it must be"
export TSAN_OPTIONS="$TSAN_OPTIONS halt_on_error=1"
for integrator in single dual path; do
    echo "== render --integrator $integrator --threads $THREADS"
    "$BUILD_DIR/examples/render/render" --integrator "$integrator" --threads "$THREADS" --hairs 300 \
        --width 64 --height 48 --spp 2 --quiet -o "$BUILD_DIR/out/$integrator"
done
# The progress bar's thread draws only on a terminal: script(1) gives the render one.
if command -v script >/dev/null 2>&1; then
    echo "== render --integrator path --threads $THREADS, with the progress bar (on a pseudo-terminal)"
    script -qec "'$BUILD_DIR/examples/render/render' --integrator path --threads $THREADS --hairs 300 \
        --width 96 --height 72 --spp 2 -o '$BUILD_DIR/out/progress'" /dev/null
fi
echo "tsan.sh: the control race was reported; none in the renderer ($CXX, $THREADS threads, 3 integrators)"
