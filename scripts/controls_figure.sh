#!/usr/bin/env bash
# The lobe-controls figure of docs/controls.md: renders the example renderer's hair block
# once per model (chiang, farfield, tabulated, marschner: the rows) and per setting (the
# columns: the plain material; "more highlight, less glint", --gain-r 2 --gain-trt 0.3; a
# tinted transmission, --tint-tt 1,0.55,0.3), all path traced with the same scene, seed and
# light (200 × 150, 16 spp), and tiles the previews with gnuplot into docs/controls.png.
# About two minutes on 2 cores.
#
#   scripts/controls_figure.sh [--build DIR] [--out FILE]
#
# --build: a build directory configured with -DHAIRSCATTER_BUILD_EXAMPLES=ON (default
# build/example, configured here as scripts/run-example.sh does); --out: the PNG to write
# (default docs/controls.png). The renders stay in <build>/controls-figure/. Missing
# packages are installed as for the examples (HAIRSCATTER_SKIP_DEPS=1 skips the check).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
# shellcheck source=SCRIPTDIR/lib.sh
source "$ROOT/scripts/lib.sh"
BUILD="$ROOT/build/example"
out="$ROOT/docs/controls.png"
while [[ $# -gt 0 ]]; do
    case "$1" in
        --build) BUILD="$2"; shift ;;
        --out) out="$2"; shift ;;
        -h | --help) hs_usage; exit 0 ;;
        *) hs_usage_error "unknown option '$1'" ;;
    esac
    shift
done
bash "$ROOT/scripts/install-deps.sh" example
command -v gnuplot >/dev/null || { echo "controls_figure: gnuplot not found (apt-get install gnuplot)" >&2; exit 1; }

if [[ ! -f "$BUILD/CMakeCache.txt" ]]; then
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DHAIRSCATTER_BUILD_EXAMPLES=ON \
        -DHAIRSCATTER_BUILD_TESTS=OFF -DHAIRSCATTER_INSTALL=OFF >/dev/null
fi
cmake --build "$BUILD" --target render -j "$(nproc 2>/dev/null || echo 2)"
exe="$(find "$BUILD/examples" -type f -name render -perm -u+x -print -quit)"
[[ -x "$exe" ]] || { echo "controls_figure: no render executable under $BUILD/examples" >&2; exit 1; }

work="$BUILD/controls-figure"
mkdir -p "$work"
models=(chiang farfield tabulated marschner)
settings=("" "--gain-r 2 --gain-trt 0.3" "--tint-tt 1,0.55,0.3")
scene=(--integrator path --width 200 --height 150 --spp 16 --hairs 1500 --seed 7 --colour blond)
for model in "${models[@]}"; do
    for k in "${!settings[@]}"; do
        # shellcheck disable=SC2086  # a setting is several options
        "$exe" "${scene[@]}" --model "$model" ${settings[$k]} -o "$work/${model}_$k" >"$work/${model}_$k.log"
        echo "controls_figure: $model ${settings[$k]:-(plain)}: $(grep -o 'mean_hair_rgb=[^ ]*' "$work/${model}_$k.log")"
    done
done

gnuplot <<EOF
set terminal pngcairo size 640,540 font "sans,10"
set output "$out"
set multiplot layout 4,3 margins 0.09,0.995,0.005,0.95 spacing 0.006,0.008
unset key; unset border; unset tics; unset colorbox
set size ratio -1
titles = "'plain' 'gain R 2, gain TRT 0.3' 'tint TT (1, 0.55, 0.3)'"
rows = "chiang farfield tabulated marschner"
do for [r=1:4] {
    do for [c=1:3] {
        file = sprintf("$work/%s_%d.png", word(rows, r), c - 1)
        if (r == 1) { set title word(titles, c) offset 0,-0.6 } else { unset title }
        if (c == 1) { set label 1 word(rows, r) at graph -0.04, 0.5 center rotate by 90 } else { unset label 1 }
        plot file binary filetype=png with rgbimage
    }
}
unset multiplot
EOF
echo "controls_figure: wrote $out"
