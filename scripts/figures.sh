#!/usr/bin/env bash
# Collects the figures the tests print (furnace worst cases, chi-square p-values, accuracy
# against references, table errors, variance ratios) into docs/test_figures.txt, so that
# the numbers quoted in the README and docs/ come from a committed run.
#
#   bash scripts/figures.sh        (builds the tests in build/figures, Release)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
# shellcheck source=SCRIPTDIR/lib.sh
source "$ROOT/scripts/lib.sh"
hs_no_args "$@"
bash scripts/install-deps.sh tests
cmake -S . -B build/figures -DCMAKE_BUILD_TYPE=Release -DHAIRSCATTER_BUILD_TESTS=ON >/dev/null
cmake --build build/figures -j "$(nproc 2>/dev/null || echo 2)"
out="$ROOT/docs/test_figures.txt"
mkdir -p docs
{
    echo "Figures printed by the hairscatter tests (scripts/figures.sh)"
    echo "date:     $(date -u '+%Y-%m-%d %H:%M:%S UTC')"
    echo "commit:   $(git rev-parse --short HEAD)$(git status --porcelain -- include tests | head -1 | sed 's/.*/ (with uncommitted changes)/')"
    echo "compiler: $(c++ --version | head -1), Release"
    for t in build/figures/tests/*_test; do
        echo
        echo "== $(basename "$t")"
        "$t" 2>&1 | grep -E '^\[ [a-z0-9]+ *\] ' || true
    done
} >"$out"
echo "figures.sh: wrote ${out#"$ROOT"/}"
