#!/usr/bin/env bash
# Dual scattering against path tracing on slabs of explicit parallel fibers: builds
# tests/dual_slab_sweep and writes docs/slab.md (about 3 minutes on 2 cores).
#
#   scripts/slab.sh [paths per row, default 20000]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
source scripts/lib.sh
[[ "${1:-}" == -h || "${1:-}" == --help ]] && { hs_usage; exit 0; }
paths="${1:-20000}"
cmake -S . -B build/slab -DCMAKE_BUILD_TYPE=Release -DHAIRSCATTER_BUILD_TESTS=ON >/dev/null
cmake --build build/slab -j "$(nproc)" --target dual_slab_sweep >/dev/null
mkdir -p docs/results
{
    echo "# Dual scattering against path-traced slabs of explicit fibers"
    echo
    echo "Written by \`scripts/slab.sh $paths\` ($(date -u +%Y-%m-%d), $(git rev-parse --short HEAD 2>/dev/null || echo unknown))."
    echo "Slabs of non-overlapping parallel fibers (packing fraction 0.2, laterally periodic), one"
    echo "directional light from above; mean radiance over $paths camera rays' first hits. See"
    echo "docs/theory.md §5.6 for the set-up."
    echo
    build/slab/tests/dual_slab_sweep "$paths"
} > docs/slab.md
echo "slab: wrote docs/slab.md"
