#!/usr/bin/env bash
# Build and run an example (the README's main command).
#
#   scripts/run-example.sh [render arguments...]                  # the example renderer
#   scripts/run-example.sh lobe_explorer [lobe_explorer arguments...]
#
# Installs the examples' Debian packages if missing, configures build/example (Release,
# examples on, tests off), builds the chosen target and runs it from the repository
# root. By default the renderer draws a 1500-hair blond block on a ground plane with dual
# scattering (importance sampling combined with light sampling, 32 spp, 480 × 360) and
# writes out/render.exr and out/render.png; the lobe explorer writes
# out/lobe_explorer.exr and .png. --help prints this text, then builds the example and
# prints its own options.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
# shellcheck source=SCRIPTDIR/lib.sh
source "$ROOT/scripts/lib.sh"
JOBS="${JOBS:-$(nproc 2>/dev/null || echo 2)}"
BUILD_DIR="build/example"
TARGET="render"
if [[ $# -gt 0 && ( "$1" == lobe_explorer || "$1" == render ) ]]; then
    TARGET="$1"
    shift
fi
for arg in "$@"; do
    if [[ "$arg" == -h || "$arg" == --help ]]; then
        hs_usage
        echo
        break
    fi
done

bash scripts/install-deps.sh example

echo "== configure $BUILD_DIR"
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release \
    -DHAIRSCATTER_BUILD_EXAMPLES=ON -DHAIRSCATTER_BUILD_TESTS=OFF -DHAIRSCATTER_INSTALL=OFF

echo "== build target $TARGET"
cmake --build "$BUILD_DIR" --target "$TARGET" -j "$JOBS"

exe="$(find "$BUILD_DIR/examples" -type f -name "$TARGET" -perm -u+x -print -quit)"
if [[ -z "$exe" || ! -x "$exe" ]]; then
    echo "run-example: built '$TARGET' but cannot find its executable under $BUILD_DIR" >&2
    exit 1
fi

mkdir -p out
echo "== run $exe $*"
exec "$exe" "$@"
