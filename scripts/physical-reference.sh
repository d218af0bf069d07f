#!/usr/bin/env bash
# The physical fiber reference (tests/support/physical_fiber.hpp): ray tracing of rough
# dielectric fibers of elliptical section. Rewrites its cache, tests/data/physical_fiber.txt
# (24 cases, 20 million rays each: about 6 minutes on 2 cores), unless --report-only, and
# writes Huang et al. 2022's fiber against it to docs/huang_physical.md.
#
#   scripts/physical-reference.sh [--rays N] [--report-only]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
source scripts/lib.sh
rays=20000000
generate=1
while [[ $# -gt 0 ]]; do
    case "$1" in
        -h|--help) hs_usage; exit 0 ;;
        --rays) rays="$2"; shift ;;
        --report-only) generate=0 ;;
        *) hs_usage_error "unknown option $1" ;;
    esac
    shift
done
# Before anything is written: the output must not make the tree look modified.
rev="$(git describe --always --dirty 2>/dev/null || echo unknown)"
cmake -S . -B build/physical -DCMAKE_BUILD_TYPE=Release -DHAIRSCATTER_BUILD_TESTS=ON >/dev/null
cmake --build build/physical -j "$(nproc)" --target physical_fiber_tool >/dev/null
tool=build/physical/tests/physical_fiber_tool
if [[ "$generate" == 1 ]]; then
    "$tool" generate --rays "$rays" --threads "$(nproc)" --out tests/data/physical_fiber.txt
fi
{
    echo "# Huang et al. 2022's fiber against a physical reference"
    echo
    echo "Written by \`scripts/physical-reference.sh\` ($(date -u +%Y-%m-%d), $rev)"
    echo "from the cached reference \`tests/data/physical_fiber.txt\` ($(sed -n '1s/.*: //p' tests/data/physical_fiber.txt))."
    echo "What the reference models and what it leaves out: [models.md](models.md) (Huang 2022) and"
    echo "\`tests/support/physical_fiber.hpp\`. Errors are relative L1 over the sphere of outgoing"
    echo "directions of f averaged over the reference's bins (24 in sin θ × 48 in φ), for the"
    echo "lossless fiber and for blond (σa = 0.5447, 0.9061, 1.781 per unit radius; the mean over"
    echo "RGB); η 1.55, cuticle tilt 2°; \"noise\" is the reference's own (from two independent halves)."
    echo
    echo "## Default quadrature"
    echo
    "$tool" report --cache tests/data/physical_fiber.txt --quadrature default
    echo
    echo "## huang_scaled_quadrature (twice the paths, 4 internal reflections each)"
    echo
    "$tool" report --cache tests/data/physical_fiber.txt --quadrature fine
    echo
    echo "## Lossless energy per lobe, model / reference"
    echo
    "$tool" lobes --cache tests/data/physical_fiber.txt
} > docs/huang_physical.md
echo "physical-reference: wrote docs/huang_physical.md"
