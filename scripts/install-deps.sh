#!/usr/bin/env bash
# Install the Debian/Ubuntu packages hairscatter needs, but only those missing.
#
#   scripts/install-deps.sh [tests|example|bench|python|package|all]...   (default: tests)
#
# Nothing is done (and no root is needed) when everything is already installed.
# Set HAIRSCATTER_SKIP_DEPS=1 to skip this step entirely (e.g. on a machine
# whose dependencies come from elsewhere).
set -euo pipefail
# shellcheck source=SCRIPTDIR/lib.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

if [[ "${HAIRSCATTER_SKIP_DEPS:-0}" == 1 ]]; then
    echo "install-deps: HAIRSCATTER_SKIP_DEPS=1, not checking packages"
    exit 0
fi

# Packages per purpose. (libboost-math-dev brings the Boost headers and
# BoostConfig.cmake; make is listed because cmake only recommends it; pkgconf is for the
# consumer step's pkg-config build.)
tests_pkgs=(cmake make g++ clang libglm-dev libgtest-dev libgmock-dev libboost-math-dev pkgconf)
example_pkgs=(cmake make g++ libglm-dev libopenexr-dev libcli11-dev libstb-dev libpng-dev libembree-dev libtbb-dev libgtest-dev
              libboost-math-dev)
bench_pkgs=(cmake make g++ libglm-dev libbenchmark-dev libboost-math-dev gnuplot-nox python3)
# The Python module (scripts/python.sh): pybind11, numpy, pytest, matplotlib for the plots.
python_pkgs=(cmake make g++ libglm-dev python3-dev python3-pybind11 python3-numpy python3-pytest python3-matplotlib)
# The DEB packages (scripts/package.sh): CPack's DEB generator reads the module's library
# dependencies with dpkg-shlibdeps (dpkg-dev) and file; pkgconf for the consumer check.
package_pkgs=(cmake make g++ libglm-dev python3-dev python3-pybind11 python3-numpy dpkg-dev file pkgconf)

[[ $# -eq 0 ]] && set -- tests
wanted=()
for what in "$@"; do
    case "$what" in
        tests | test) wanted+=("${tests_pkgs[@]}") ;;
        example | examples) wanted+=("${example_pkgs[@]}") ;;
        bench | benchmarks) wanted+=("${bench_pkgs[@]}") ;;
        python) wanted+=("${python_pkgs[@]}") ;;
        package) wanted+=("${package_pkgs[@]}") ;;
        all) wanted+=("${tests_pkgs[@]}" "${example_pkgs[@]}" "${bench_pkgs[@]}" "${python_pkgs[@]}" "${package_pkgs[@]}") ;;
        -h | --help) hs_usage; exit 0 ;;
        *) hs_usage_error "unknown set '$what'" ;;
    esac
done

if ! command -v dpkg >/dev/null 2>&1 || ! command -v apt-get >/dev/null 2>&1; then
    echo "install-deps: not a Debian-like system (no dpkg/apt-get); assuming the dependencies are installed:"
    printf '  %s\n' "${wanted[@]}" | sort -u
    exit 0
fi

is_installed() {
    dpkg -s "$1" 2>/dev/null | grep -q '^Status: install ok installed'
}

missing=()
for pkg in $(printf '%s\n' "${wanted[@]}" | sort -u); do
    is_installed "$pkg" || missing+=("$pkg")
done

if [[ ${#missing[@]} -eq 0 ]]; then
    echo "install-deps: all packages present ($*)"
    exit 0
fi

echo "install-deps: installing missing packages: ${missing[*]}"
SUDO=()
if [[ "$(id -u)" -ne 0 ]]; then
    if command -v sudo >/dev/null 2>&1; then
        SUDO=(sudo)
    else
        echo "install-deps: not root and sudo is unavailable; please install: ${missing[*]}" >&2
        exit 1
    fi
fi

export DEBIAN_FRONTEND=noninteractive
retry() {
    local n
    for n in 1 2 3; do
        if "$@"; then return 0; fi
        echo "install-deps: '$*' failed (attempt $n/3)" >&2
        sleep $((n * 5))
    done
    return 1
}

retry "${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q
retry "${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive \
    apt-get install -y -q --no-install-recommends "${missing[@]}"
echo "install-deps: done"
