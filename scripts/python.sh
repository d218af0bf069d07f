#!/usr/bin/env bash
# Build the Python module hairscatter and run its tests (docs/python.md).
#
#   scripts/python.sh [--build DIR] [--install PREFIX] [--ci] [--no-tests] [--no-deps] [-j N]
#
# Installs the Debian packages it needs when missing (scripts/install-deps.sh python),
# configures DIR (default build/python) with -DHAIRSCATTER_BUILD_PYTHON=ON, builds the
# module, the C++ reference program of the tests and the C++ loop of the benchmark, and
# runs the pytest suite through ctest. Afterwards:
#
#   PYTHONPATH=build/python/python python3 -c "import hairscatter"
#
# --install PREFIX  also install into PREFIX and import the package from there
#                   (PREFIX/lib/python3.X/site-packages).
# --ci              what scripts/test.sh's python step runs: -O1 instead of -O3 (the module
#                   compiles every model and the Chiang fiber's 15 lobe sets in float and
#                   double: about three CPU-minutes at -O3, two at -O1; the tests compare it
#                   with a C++ program built with the same flags).
# --no-tests        build (and install) without running the tests.
# -j N              parallel jobs (default: nproc). PYTHON=… picks the interpreter (default
#                   /usr/bin/python3, where Debian's python3-numpy lives, when it exists).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
# shellcheck source=SCRIPTDIR/lib.sh
source "$ROOT/scripts/lib.sh"

build="$ROOT/build/python"
prefix=""
ci=0
tests=1
deps=1
jobs="$(nproc 2>/dev/null || echo 2)"
while [[ $# -gt 0 ]]; do
    case "$1" in
        --build) build="${2:?--build needs a directory}"; shift ;;
        --install) prefix="${2:?--install needs a prefix}"; shift ;;
        --ci) ci=1 ;;
        --no-tests) tests=0 ;;
        --no-deps) deps=0 ;;
        -j) jobs="${2:?-j needs a number}"; shift ;;
        -j*) jobs="${1#-j}" ;;
        -h | --help) hs_usage; exit 0 ;;
        *) hs_usage_error "unknown argument '$1'" ;;
    esac
    shift
done

[[ $deps == 1 ]] && bash "$ROOT/scripts/install-deps.sh" python
if [[ -z "${PYTHON:-}" ]]; then
    if [[ -x /usr/bin/python3 ]]; then PYTHON=/usr/bin/python3; else PYTHON="$(command -v python3)"; fi
fi

flags=(-DCMAKE_BUILD_TYPE=Release -DHAIRSCATTER_BUILD_TESTS=OFF -DHAIRSCATTER_BUILD_PYTHON=ON
       -DHAIRSCATTER_WERROR=ON "-DPython3_EXECUTABLE=$PYTHON")
# Always set: a directory configured once with --ci must not keep -O1 for a release build.
if [[ $ci == 1 ]]; then flags+=("-DCMAKE_CXX_FLAGS_RELEASE=-O1 -DNDEBUG"); else flags+=("-DCMAKE_CXX_FLAGS_RELEASE=-O3 -DNDEBUG"); fi
echo "+ cmake -S . -B $build ${flags[*]}"
cmake -S . -B "$build" "${flags[@]}"
echo "+ cmake --build $build -j $jobs"
cmake --build "$build" -j "$jobs"
[[ $tests == 1 ]] && (cd "$build" && ctest --output-on-failure --no-tests=error -R '^python_')

if [[ -n "$prefix" ]]; then
    echo "+ cmake --install $build --prefix $prefix"
    cmake --install "$build" --prefix "$prefix" >/dev/null
    site="$(cmake -L -N "$build" | sed -n 's/^HAIRSCATTER_PYTHON_INSTALL_DIR:STRING=//p')"
    (cd / && PYTHONPATH="$prefix/$site" "$PYTHON" -c \
        "import hairscatter, sys; m = hairscatter.Chiang(); assert abs(m.albedo([0, 1, 0], 0.0)[0] - 1) < 1e-9; print('installed:', hairscatter.__file__)")
fi
echo "python.sh: PYTHONPATH=${build#"$ROOT"/}/python $PYTHON -c 'import hairscatter'"
