#!/usr/bin/env bash
# The seed thesis's study with the example renderer (issue 5), written to docs/results/:
#   1. convergence (seed §4.3): error of dual scattering against spp and against seconds,
#      uniform vs importance sampling of the dual-scattering BCSDF, over the hair pixels,
#      under a white environment and under the preset's area light + dim environment;
#   2. the variance between consecutive spp levels and where it drops below a threshold
#      (seed §4.4);
#   3. dual scattering (and single scattering) against the brute-force path tracer on hair
#      blocks, blond and dark: error of the mean hair radiance, error images, times;
#   4. scale: render time and peak memory against strand count, hair blocks of 1,500 to
#      12,000 strands and scalps of 25,000 to 100,000, single and dual scattering and the
#      path tracer (one process per run, so peak memory is per run);
#   5. a gallery of the seed's scenes: the four hair blocks and the Cornell box.
# Tables (CSV), plots (PNG, gnuplot) and docs/results/README.md with the commands, the
# machine and the date. About 15 minutes on the 2-core machine.
#
#   scripts/study.sh [--tiny] [--out DIR] [--build DIR] [--no-deps]
#
# --tiny is CI's end-to-end check: small images and few spp into build/study-tiny (not
# docs/); it fails unless every image exists and is finite and the error falls with spp
# for both samplers.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
tiny=0
out=""
BUILD=""
install_deps=1
[[ "${HAIRSCATTER_SKIP_DEPS:-0}" == 1 ]] && install_deps=0
while [[ $# -gt 0 ]]; do
    case "$1" in
        --tiny) tiny=1 ;;
        --out) out="$2"; shift ;;
        --build) BUILD="$2"; shift ;;   # an existing build tree with examples on (test.sh's)
        --no-deps) install_deps=0 ;;
        -h | --help) sed -n '2,20p' "$0"; exit 0 ;;
        *) echo "study.sh: unknown option '$1'" >&2; exit 2 ;;
    esac
    shift
done
if [[ -z "$out" ]]; then
    if [[ $tiny == 1 ]]; then out="$ROOT/build/study-tiny"; else out="$ROOT/docs/results"; fi
fi
mkdir -p "$out"
out="$(cd "$out" && pwd)"

if [[ $install_deps == 1 ]]; then
    bash "$ROOT/scripts/install-deps.sh" example
    bash "$ROOT/scripts/install-deps.sh" bench   # gnuplot
fi
if [[ -z "$BUILD" ]]; then
    BUILD="$ROOT/build/study"
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DHAIRSCATTER_BUILD_TESTS=OFF \
        -DHAIRSCATTER_BUILD_EXAMPLES=ON >/dev/null
fi
cmake --build "$BUILD" --target study render -j "$(nproc 2>/dev/null || echo 2)"
STUDY="$BUILD/examples/study/study"
RENDER="$BUILD/examples/render/render"
start=$SECONDS
commands=()
run() {
    commands+=("$*")
    echo "+ $*" >&2
    "$@"
}

# ---- parameters ------------------------------------------------------------------------
if [[ $tiny == 1 ]]; then
    size=(--width 48 --height 36)
    conv=(--max-spp 16 --reference-spp 64 --threshold 0.01)
    dvp=(--dual-spp 4 --path-spp 16 --hair-counts 1500)
    dvp_sweep=(--dual-spp 4 --path-spp 16 --hair-counts 1500 --colours blond dark)
    scale_blocks=(1500 3000)
    scale_scalps=()
    scale_size=(--width 64 --height 48 --spp 1)
else
    size=(--width 160 --height 120)
    conv=(--max-spp 512 --reference-spp 4096 --threshold 0.01)
    dvp=(--dual-spp 256 --path-spp 512 --hair-counts 1500 6000)
    dvp_sweep=(--dual-spp 256 --path-spp 512 --hair-counts 400 1500 6000 --colours white blond brown dark)
    scale_blocks=(1500 3000 6000 12000)
    scale_scalps=(25000 50000 100000)
    scale_size=(--width 320 --height 240 --spp 8)
fi

# ---- 1 + 2: convergence ----------------------------------------------------------------
for lighting in env both; do
    run "$STUDY" convergence --lighting "$lighting" "${size[@]}" "${conv[@]}" --reference-sampling importance \
        --out "$out"
done

# ---- 3: dual scattering against path tracing ------------------------------------------
run "$STUDY" dual-vs-path --lighting both --no-ground "${size[@]}" "${dvp_sweep[@]}" --out "$out"
run "$STUDY" dual-vs-path --lighting both "${size[@]}" "${dvp[@]}" --colours blond dark --out "$out"

# ---- 4: scale --------------------------------------------------------------------------
scale_csv="$out/scale.csv"
echo "scene,strands,segments,integrator,render_s,build_s,peak_rss_mb,embree_mb,grid_mb,tables_kb" >"$scale_csv"
field() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" <<<" $2"; }
scale_run() {  # scene-args...
    local integrator line
    for integrator in single dual path; do
        line="$(run "$RENDER" "$@" --integrator "$integrator" "${scale_size[@]}" --quiet -o "$BUILD/scale-tmp")"
        echo "$line" >&2
        echo "$(field scene "$line"),$(field strands "$line"),$(field segments "$line"),$integrator,$(field time_s "$line"),$(field build_s "$line"),$(field peak_rss_mb "$line"),$(field embree_mb "$line"),$(field grid_mb "$line"),$(field tables_kb "$line")" >>"$scale_csv"
    done
}
for n in "${scale_blocks[@]}"; do scale_run --scene block --hairs "$n"; done
for n in "${scale_scalps[@]+"${scale_scalps[@]}"}"; do scale_run --scene scalp --scalp-hairs "$n"; done

# ---- 5: the seed's scenes ----------------------------------------------------------------
gallery=()
if [[ $tiny == 1 ]]; then
    gallery_size=(--width 64 --height 48 --spp 2)
    gallery_blocks=(1500)
else
    gallery_size=(--width 320 --height 240 --spp 64)
    gallery_blocks=(1500 3000 6000 12000)
fi
for n in "${gallery_blocks[@]}"; do
    run "$RENDER" --scene block --hairs "$n" "${gallery_size[@]}" --quiet -o "$out/scene_block_$n" >/dev/null
    gallery+=("scene_block_$n")
done
run "$RENDER" --scene cornell "${gallery_size[@]}" --quiet -o "$out/scene_cornell" >/dev/null
gallery+=("scene_cornell")

# ---- checks (always; they are what --tiny is for) -------------------------------------
fail=0
for f in "$out"/convergence_env_reference.exr "$out"/convergence_both_reference.exr "$out"/scene_cornell.exr; do
    [[ -s "$f" ]] || { echo "study: missing $f" >&2; fail=1; }
done
for lighting in env both; do
    for sampler in uniform importance; do
        # RMSE at the largest spp level must be below the RMSE at 1 spp.
        awk -F, -v s="$sampler" -v l="$lighting" '
            $1 == s { if (first == "") first = $4; last = $4 }
            END { if (!(last < first)) { printf "study: %s/%s: RMSE does not fall with spp (%s -> %s)\n", l, s, first, last > "/dev/stderr"; exit 1 } }' \
            "$out/convergence_$lighting.csv" || fail=1
    done
done
[[ $(wc -l <"$scale_csv") -gt 1 ]] || { echo "study: no scale results" >&2; fail=1; }
[[ $fail == 0 ]] || exit 1
elapsed=$((SECONDS - start))

# ---- plots -----------------------------------------------------------------------------
if command -v gnuplot >/dev/null 2>&1; then
    gnuplot -e "dir='$out'" "$ROOT/examples/study/plots.gp"
else
    echo "study.sh: gnuplot not found, no plots" >&2
fi

# ---- README of the results ----------------------------------------------------------------
cpu="$(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -1)"
table() {  # csv → markdown table
    awk -F, 'NR == 1 { h = "|"; s = "|"; for (i = 1; i <= NF; i++) { h = h " " $i " |"; s = s "---|" } print h; print s; next }
             { r = "|"; for (i = 1; i <= NF; i++) r = r " " $i " |"; print r }' "$1"
}
{
    echo "# Results of the seed thesis's study"
    echo
    echo "Made by \`scripts/study.sh$([[ $tiny == 1 ]] && echo " --tiny")\` on $(date -u +%Y-%m-%d), commit $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown),"
    echo "${cpu:-unknown CPU}, $(nproc) cores; $elapsed s in all. Renderer: \`examples/render\`; study program:"
    echo "\`examples/study/study.cpp\`; plots: \`examples/study/plots.gp\`. Commands run:"
    echo
    for c in "${commands[@]}"; do echo "    ${c//$ROOT\//}"; done
    echo
    echo "## 1. Convergence: uniform against importance sampling (seed §4.3)"
    echo
    echo "Dual scattering on the 1,500-hair block, ${size[*]}; errors over the pixels whose primary"
    echo "ray hits hair. The reference is importance-sampled at the --reference-spp above (the seed's"
    echo "ground truth is uniform sampling at 1024 spp; both estimate the same integral, and the"
    echo "reference's own variance is 8× below the largest level's). Seconds are wall-clock"
    echo "on 2 threads. \`env\`: white environment only; \`both\`: the small area light plus a dim"
    echo "environment, with BCSDF sampling alone (no light sampling) in both samplers."
    echo
    for lighting in env both; do
        echo "### Lighting: $lighting"
        echo
        echo "![RMSE against spp](convergence_${lighting}_spp.png) ![RMSE against seconds](convergence_${lighting}_time.png)"
        echo
        table "$out/convergence_$lighting.csv"
        echo
    done
    echo "Under the white environment importance sampling wins, as the seed expected. Under the small"
    echo "area light with BCSDF sampling alone it loses: all of its second moment sits in the rare"
    echo "samples that hit the light, the light lies in the backward half where blond hair's dual"
    echo "BCSDF is 0.38× its mean over the sphere, and the sampling density toward it is below half of"
    echo "uniform's for 88 % of the hair pixels (even a pdf exactly ∝ F would only match uniform"
    echo "there). The renderer's default therefore combines BCSDF sampling with light sampling by MIS."
    echo
    echo "## 2. Variance between consecutive spp levels (seed §4.4)"
    echo
    echo "consecutive_var = mean over the hair pixels of (I_spp − I_spp/2)²; consecutive_var_rel divides by"
    echo "the reference's mean square. The first spp level below the threshold:"
    echo
    for lighting in env both; do
        echo "Lighting $lighting:"
        echo
        table "$out/convergence_${lighting}_threshold.csv"
        echo
    done
    echo "![consecutive variance](convergence_variance.png)"
    echo
    echo "## 3. Dual scattering against path tracing"
    echo
    echo "The path tracer (\`--integrator path\`, MIS, Russian roulette) through \`ChiangFiber\` is the"
    echo "multiple-scattering ground truth. rel_error_mean is (mean − mean_path)/mean_path of the channel"
    echo "sum over the hair pixels; mean_abs_pixel_rel_error the mean of |x − path|/(path + 0.01)."
    echo "Without the ground plane the only difference is the hair's own multiple scattering; with it"
    echo "the path tracer also has the light the ground bounces onto the hair, which dual and single"
    echo "scattering (direct light only) do not."
    echo
    echo "### No ground plane: hair colour (white = lossless, blond, brown, dark) and density"
    echo
    table "$out/dual_vs_path_both_noground.csv"
    echo
    echo "### With the ground plane"
    echo
    table "$out/dual_vs_path_both.csv"
    echo
    echo "Reading the no-ground table: dual scattering is close for dark hair (little multiple"
    echo "scattering to approximate) and for sparse hair, and its error changes sign with absorption:"
    echo "too bright for lossless hair, too dark for blond and brown, and more so as the block gets"
    echo "denser. This is the approximation, not a bug (checked: the sampling modes agree with each"
    echo "other, the path tracer's importance and MIS estimates agree, a lossless fiber's dual"
    echo "BCSDF satisfies the energy identities of \`tests/dual_bcsdf_test.cpp\`). Zinke's backscatter"
    echo "A_b is a one-dimensional forward/backward series that falls 45× from lossless to blond"
    echo "hair's blue channel while the path tracer's multiple scattering falls ~13×: the broad"
    echo "transmission lobe and the white surface reflection turn light around through several"
    echo "'forward' events that the 1D series does not count, and with light and camera on the same"
    echo "side a shadowed point receives only the backscatter term. No choice of d_f, d_b fixes both"
    echo "ends (d_f = d_b = 1 gets blond's mean right with the wrong colour)."
    echo "Images (no ground plane, 1,500 hairs): path, dual, single, dual's error (black 0 → white ≥ 50 %):"
    echo
    for colour in blond dark; do
        echo "![path](dvp_both_noground_${colour}_1500_path.png) ![dual](dvp_both_noground_${colour}_1500_dual.png) ![single](dvp_both_noground_${colour}_1500_single.png) ![dual error](dvp_both_noground_${colour}_1500_dual_error.png)"
        echo
    done
    echo "## 4. Scale: time and memory against strand count"
    echo
    echo "One process per run (${scale_size[*]}); peak_rss_mb is the process's VmHWM, embree_mb what"
    echo "Embree allocated (BVH and buffers), grid_mb the density grid, tables_kb the dual tables."
    echo
    table "$scale_csv"
    echo
    echo "![time against strands](scale_time.png) ![memory against strands](scale_memory.png)"
    echo
    echo "## 5. The seed's scenes"
    echo
    echo "Dual scattering with MIS, ${gallery_size[*]}, blond hair: the 5 × 5 × 5 blocks of"
    echo "${gallery_blocks[*]} hairs on the ground plane, and the Cornell box (red left wall,"
    echo "green right wall, grey back and front walls, the hair block and a red diffuse sphere)."
    echo
    line=""
    for g in "${gallery[@]}"; do line+="![$g]($g.png) "; done
    echo "$line"
} >"$out/README.md"
echo "study.sh: wrote $out ($elapsed s)"
