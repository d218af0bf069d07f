#!/usr/bin/env bash
# Build and run the lobe_explorer example (the README's main command).
#
#   scripts/run-example.sh [lobe_explorer arguments...]
#
# Installs the example's Debian packages if missing, configures build/example
# (Release, examples on, tests off), builds the lobe_explorer target and runs it
# from the repository root; by default it writes out/lobe_explorer.exr and
# out/lobe_explorer.png. Run with --help to see the example's own options.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
JOBS="${JOBS:-$(nproc 2>/dev/null || echo 2)}"
BUILD_DIR="build/example"
TARGET="lobe_explorer"

if [[ ! -f examples/CMakeLists.txt ]]; then
    echo "run-example: examples/CMakeLists.txt is not in this checkout yet; nothing to run." >&2
    exit 1
fi

bash scripts/install-deps.sh example

echo "== configure $BUILD_DIR"
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release \
    -DHAIRSCATTER_BUILD_EXAMPLES=ON -DHAIRSCATTER_BUILD_TESTS=OFF -DHAIRSCATTER_INSTALL=OFF

echo "== build target $TARGET"
if ! cmake --build "$BUILD_DIR" --target "$TARGET" -j "$JOBS"; then
    if ! grep -rqs --include='CMakeLists.txt' "$TARGET" examples; then
        echo "run-example: the examples do not define a '$TARGET' target yet." >&2
    fi
    exit 1
fi

exe="$BUILD_DIR/examples/$TARGET/$TARGET"
if [[ ! -x "$exe" ]]; then
    # Fall back to wherever the example's CMakeLists put the binary.
    exe="$(find "$BUILD_DIR" -type f -name "$TARGET" -perm -u+x -print -quit)"
fi
if [[ -z "$exe" || ! -x "$exe" ]]; then
    echo "run-example: built '$TARGET' but cannot find its executable under $BUILD_DIR" >&2
    exit 1
fi

mkdir -p out
echo "== run $exe $*"
exec "$exe" "$@"
