#!/usr/bin/env bash
# Build the Debian packages of hairscatter with CPack (docs/building.md).
#
#   scripts/package.sh [--build DIR] [--ci] [--no-python] [--no-deps] [--build-only] [-j N]
#
# Configures DIR (default build/package) for the prefix /usr, Release, without the tests,
# with the Python module installed into Debian's lib/python3/dist-packages; builds the
# module and runs `cpack -G DEB`, which writes into DIR:
#
#   libhairscatter-dev_<version>_all.deb      headers, CMake package, pkg-config file
#   python3-hairscatter_<version>_<arch>.deb  the Python module (for /usr/bin/python3)
#
# then prints each package's control fields, files and size. Install them with
# `dpkg -i DIR/*.deb` (apt-get install ./DIR/*.deb also fetches libglm-dev and python3-numpy).
#
# --ci         what scripts/test.sh's package step runs: the module at -O1 instead of -O3
#              (scripts/python.sh --ci explains the difference in build time).
# --no-python  libhairscatter-dev only (no Python module to build).
# --no-deps    do not install missing Debian packages (scripts/install-deps.sh package).
# --build-only configure and build the module, no packages (scripts/test.sh builds ahead of
#              its package step so; the step's own run then finds the module built).
# -j N         parallel jobs (default: nproc).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
# shellcheck source=SCRIPTDIR/lib.sh
source "$ROOT/scripts/lib.sh"

build="$ROOT/build/package"
ci=0
python=ON
deps=1
build_only=0
jobs="$(nproc 2>/dev/null || echo 2)"
while [[ $# -gt 0 ]]; do
    case "$1" in
        --build) build="${2:?--build needs a directory}"; shift ;;
        --ci) ci=1 ;;
        --no-python) python=OFF ;;
        --no-deps) deps=0 ;;
        --build-only) build_only=1 ;;
        -j) jobs="${2:?-j needs a number}"; shift ;;
        -j*) jobs="${1#-j}" ;;
        -h | --help) hs_usage; exit 0 ;;
        *) hs_usage_error "unknown argument '$1'" ;;
    esac
    shift
done

[[ $deps == 1 ]] && bash "$ROOT/scripts/install-deps.sh" package

# The install prefix of a Debian package is /usr; the module goes where Debian's python3
# looks for packages of the system (not lib/python3.X/site-packages, the default for a
# prefix install). Installing does not rebuild everything (CMAKE_SKIP_INSTALL_ALL_DEPENDENCY):
# only the module is built, not the C++ programs the Python tests compare it with.
flags=(-DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX=/usr -DHAIRSCATTER_INSTALL=ON
       -DHAIRSCATTER_BUILD_TESTS=OFF -DHAIRSCATTER_DOCS=OFF "-DHAIRSCATTER_BUILD_PYTHON=$python"
       -DCMAKE_SKIP_INSTALL_ALL_DEPENDENCY=ON)
if [[ $python == ON ]]; then
    flags+=(-DPython3_EXECUTABLE=/usr/bin/python3 -DHAIRSCATTER_PYTHON_INSTALL_DIR=lib/python3/dist-packages)
    # Always set: a directory configured once with --ci must not keep -O1 for a release build.
    if [[ $ci == 1 ]]; then flags+=("-DCMAKE_CXX_FLAGS_RELEASE=-O1 -DNDEBUG"); else flags+=("-DCMAKE_CXX_FLAGS_RELEASE=-O3 -DNDEBUG"); fi
fi
echo "+ cmake -S . -B $build ${flags[*]}"
cmake -S . -B "$build" "${flags[@]}"
if [[ $python == ON ]]; then
    echo "+ cmake --build $build -j $jobs --target hairscatter_python"
    cmake --build "$build" -j "$jobs" --target hairscatter_python
fi
[[ $build_only == 0 ]] || exit 0

rm -f "$build"/*.deb
echo "+ (cd $build && cpack -G DEB)"
(cd "$build" && cpack -G DEB)

shopt -s nullglob
debs=("$build"/*.deb)
[[ ${#debs[@]} -gt 0 ]] || { echo "package.sh: cpack wrote no .deb into $build" >&2; exit 1; }
for deb in "${debs[@]}"; do
    echo
    echo "== ${deb#"$ROOT"/}: $(( ($(stat -c %s "$deb") + 1023) / 1024 )) KB"
    dpkg-deb --field "$deb" Package Version Architecture Depends Installed-Size
    dpkg-deb --contents "$deb" | awk '$NF !~ /\/$/ { print "  " $NF }'
done
