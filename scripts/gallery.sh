#!/usr/bin/env bash
# Regenerate the gallery: docs/gallery/*.png and docs/gallery.md.
#
#   scripts/gallery.sh            # every picture (minutes on 2 cores: docs/gallery.md says)
#   scripts/gallery.sh --quick    # a quarter of the samples, to try a change
#   RENDER=build/x/examples/render/render scripts/gallery.sh   # an already built renderer
#
# Builds the example renderer like scripts/run-example.sh (build/example, Release), renders
# the showcase bust (--scene head) under the procedural studio environment, close up and
# from behind, with each fiber model, from black to white hair, with single, dual and path-traced scattering and
# with one Chiang lobe at a time, and the fur ball; copies the PNG previews to
# docs/gallery/ (the EXRs stay in out/gallery/) and writes docs/gallery.md with each
# picture's command line and render time. Fails if the PNGs together exceed 3 MB.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
# shellcheck source=SCRIPTDIR/lib.sh
source "$ROOT/scripts/lib.sh"

scale=1
case "${1:-}" in
    "") ;;
    --quick) scale=4 ;;
    -h | --help) hs_usage; exit 0 ;;
    *) hs_usage_error "unknown argument '$1'" ;;
esac

exe="${RENDER:-}"
if [[ -z "$exe" ]]; then
    JOBS="${JOBS:-$(nproc 2>/dev/null || echo 2)}"
    BUILD_DIR="build/example"
    cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release \
        -DHAIRSCATTER_BUILD_EXAMPLES=ON -DHAIRSCATTER_BUILD_TESTS=OFF -DHAIRSCATTER_INSTALL=OFF >/dev/null
    cmake --build "$BUILD_DIR" --target render -j "$JOBS" >/dev/null
    exe="$BUILD_DIR/examples/render/render"
fi
[[ -x "$exe" ]] || hs_usage_error "no renderer at '$exe'"

OUT="out/gallery"
PICS="docs/gallery"
PAGE="docs/gallery.md"
mkdir -p "$OUT" "$PICS"
rm -f "$PICS"/*.png

# Every picture: the showcase (unless its arguments name a --scene) under the studio, at
# 400 x 225 unless its arguments say otherwise.
COMMON=(--env studio --light-power 0 --tone filmic --quiet)
SMALL=(--width 400 --height 225)

load_start="$(cut -d' ' -f1 /proc/loadavg)"
rows=""     # the current section's table rows
body=""     # the page below its header
section() { flush; body+=$'\n'"## $1"$'\n\n'"$2"$'\n\n'; }
flush() {
    if [[ -n "$rows" ]]; then
        body+="| picture | command | render time |"$'\n'"| --- | --- | --- |"$'\n'"$rows"
        rows=""
    fi
}

# picture NAME CAPTION SPP ARGS...: render, copy the PNG, add a table row.
picture() {
    local name="$1" caption="$2" spp="$3"
    shift 3
    spp=$(( spp / scale > 0 ? spp / scale : 1 ))
    local args=("${COMMON[@]}" --spp "$spp" "$@")
    [[ " $* " == *" --scene "* ]] || args=(--scene head "${args[@]}")
    echo "gallery: $name: render ${args[*]}" >&2
    local summary
    summary="$("$exe" "${args[@]}" -o "$OUT/$name" 2>/dev/null)"
    cp "$OUT/$name.png" "$PICS/$name.png"
    local render_s build_s
    render_s="$(sed -n 's/.* time_s=\([0-9.]*\) .*/\1/p' <<<"$summary")"
    build_s="$(sed -n 's/.* build_s=\([0-9.]*\) .*/\1/p' <<<"$summary")"
    printf 'gallery: %s: %s s (scene %s s)\n' "$name" "$render_s" "$build_s" >&2
    rows+="| ![$caption](gallery/$name.png)<br>$caption | \`render ${args[*]}\` | $render_s s (+ $build_s s BVH and shading setup) |"$'\n'
    total_render=$(awk -v a="$total_render" -v b="$render_s" -v c="$build_s" 'BEGIN { print a + b + c }')
}
total_render=0

section "The showcase" "The bust with 30,000 strands of blond hair, dual scattering (the two-stream estimator) under the studio environment, the README's picture."
picture head "blond, dual scattering" 64 --integrator dual --width 960 --height 540

section "Camera" "\`--crop\` renders a window of the frame (here of the showcase's, the same pixels); \`--eye\` and \`--look-at\` move the camera: the back of the head, where the crown's strands leave it."
picture closeup "close-up of the parting" 64 --integrator dual --width 1920 --height 1080 --crop 760,90,1160,315
picture back "from behind" 32 "${SMALL[@]}" --integrator dual --eye -2,4.5,-7.2 --look-at 0,3.25,0

section "Fiber models" "Each model path-traced (\`--integrator path\`: every scattering order), the default blond fiber. huang with \`--aspect 0.7\` is the elliptical fiber."
for model in chiang farfield tabulated marschner; do
    picture "model_$model" "$model" 32 "${SMALL[@]}" --integrator path --model "$model"
done
picture model_huang_elliptical "huang, aspect 0.7" 16 "${SMALL[@]}" --integrator path --model huang --aspect 0.7

section "Melanin, black to white" "\`--melanin\` (Cycles' parameterisation: 0 white, 1 black), dual scattering; the last picture adds \`--redness\`."
for m in 0 0.2 0.4 0.6 0.8 1; do
    picture "melanin_$m" "melanin $m" 32 "${SMALL[@]}" --integrator dual --melanin "$m"
done
picture melanin_0.4_red "melanin 0.4, redness 0.8" 32 "${SMALL[@]}" --integrator dual --melanin 0.4 --redness 0.8

section "Single, dual and path-traced scattering" "The same blond hair: single scattering (hair shadows are opaque), dual scattering, the path tracer (the reference)."
for integrator in single dual path; do
    picture "integrator_$integrator" "$integrator" 32 "${SMALL[@]}" --integrator "$integrator"
done

section "Lobes one at a time" "Chiang's fiber with one lobe kept (\`--lobes\`), path-traced: R is the white surface reflection, TT the forward transmission, TRT the coloured secondary highlight, residual the higher orders."
for lobe in R TT TRT residual; do
    picture "lobe_$lobe" "$lobe" 32 "${SMALL[@]}" --integrator path --lobes "$lobe"
done

section "Fur" "The fur ball of the dual-scattering study under the studio, dual scattering."
picture fur "fur ball" 32 "${SMALL[@]}" --scene fur --integrator dual
flush

bytes=$(cat "$PICS"/*.png | wc -c)
count=$(find "$PICS" -name '*.png' | wc -l)
{
    echo "# Gallery"
    echo
    echo "Regenerated by \`scripts/gallery.sh\` (the commands below, with \`-o\`); times are the"
    echo "renderer's own (\`time_s\` and \`build_s\` of its summary line) on $(nproc) cores of"
    echo "$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)."
    echo "$count pictures, $(awk -v b="$bytes" 'BEGIN { printf "%.2f", b / 1048576 }') MB of PNG,"
    echo "$(awk -v t="$total_render" 'BEGIN { printf "%.0f", t }') s of rendering and scene building in all; the"
    echo "1-minute load average was $load_start at the start and $(cut -d' ' -f1 /proc/loadavg) at the end."
    echo "$body"
} >"$PAGE"
echo "gallery: wrote $PAGE and $count pictures ($bytes bytes)" >&2
if ((bytes > 3 * 1024 * 1024)); then
    echo "gallery: the pictures exceed 3 MB ($bytes bytes): render them smaller" >&2
    exit 1
fi
