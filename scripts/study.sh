#!/usr/bin/env bash
# The origin study's measurements with the example renderer, written to docs/results/:
#   1. convergence: error of dual scattering against spp and against seconds, uniform vs
#      importance sampling of the dual-scattering BCSDF, over the hair pixels, under a white
#      environment and under the preset's area light + dim environment;
#   2. the variance between consecutive spp levels and where it drops below a threshold;
#   3. dual scattering (improved and Zinke 2008 formulations) and single scattering against
#      the path tracer: white / blond / brown / dark × 400 / 1,500 / 6,000 / 12,000 hairs
#      without ground, a scalp, and blocks with the ground plane: error of the mean hair
#      radiance, mean per-pixel error, error images, times;
#   4. time to equal error: seconds for dual scattering and for the path tracer to reach a
#      relative RMSE over the hair pixels against a converged path-traced reference;
#   5. scale: render time and peak memory against strand count;
#   6. a gallery of the origin study's scenes: the four hair blocks and the Cornell box.
# Tables (CSV), plots (PNG, gnuplot) and docs/results/README.md with the commands, the
# machine and the date; the page holds measured tables only. About 30 minutes on 2 cores.
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
        -h | --help) source "$ROOT/scripts/lib.sh"; hs_usage; exit 0 ;;
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
    dvp_counts=(1500)
    dvp_colours=(blond dark)
    dvp_spp=(--dual-spp 4 --path-spp 16)
    scalp_counts=(2000)
    tte=(--reference-spp 64 --dual-max-spp 8 --path-max-spp 16)
    tte_size=(--width 32 --height 24)
    scale_blocks=(1500 3000)
    scale_scalps=()
    scale_size=(--width 64 --height 48 --spp 1)
else
    size=(--width 80 --height 60)
    conv=(--max-spp 128 --reference-spp 1024 --threshold 0.01)
    dvp_counts=(400 1500 6000 12000)
    dvp_colours=(white blond brown dark)
    dvp_spp=(--dual-spp 64 --path-spp 512)
    scalp_counts=(20000)
    tte=(--reference-spp 8192 --dual-max-spp 1024 --path-max-spp 4096)
    tte_size=(--width 48 --height 36)
    scale_blocks=(1500 6000 12000)
    scale_scalps=(25000 100000)
    scale_size=(--width 320 --height 240 --spp 8)
fi

# ---- 1 + 2: convergence ----------------------------------------------------------------
for lighting in env both; do
    run "$STUDY" convergence --lighting "$lighting" "${size[@]}" "${conv[@]}" --reference-sampling importance \
        --out "$out"
done

# ---- 3: dual scattering against path tracing ------------------------------------------
run "$STUDY" dual-vs-path --lighting both --no-ground "${size[@]}" "${dvp_spp[@]}" --hair-counts "${dvp_counts[@]}" \
    --colours "${dvp_colours[@]}" --out "$out"
run "$STUDY" dual-vs-path --scene scalp --lighting both --no-ground "${size[@]}" "${dvp_spp[@]}" \
    --hair-counts "${scalp_counts[@]}" --colours blond brown --out "$out"
run "$STUDY" dual-vs-path --lighting both "${size[@]}" "${dvp_spp[@]}" --hair-counts 1500 --colours blond dark --out "$out"

# ---- 4: time to equal error -----------------------------------------------------------
run "$STUDY" time-to-error --no-ground --colour blond --hairs 1500 --lighting both "${tte_size[@]}" "${tte[@]}" --out "$out"

# ---- 5: scale --------------------------------------------------------------------------
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

# ---- 6: the origin study's scenes ----------------------------------------------------------------
gallery=()
if [[ $tiny == 1 ]]; then
    gallery_size=(--width 64 --height 48 --spp 2)
    gallery_blocks=(1500)
else
    gallery_size=(--width 240 --height 180 --spp 32)
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
for f in "$out"/convergence_env_reference.exr "$out"/convergence_both_reference.exr "$out"/scene_cornell.exr "$out"/time_to_error.csv "$out"/dual_vs_path_scalp_both_noground.csv; do
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
# The seconds to reach a relative RMSE (log-log interpolation between levels; "not reached"
# when the largest level is still above it).
reach() {  # csv integrator target
    awk -F, -v n="$2" -v t="$3" '
        $1 == n { if (prev != "" && $4 <= t && pe > t) { f = (log(pe) - log(t)) / (log(pe) - log($4));
                      printf "%.3g", exp(log(ps) + f * (log($3) - log(ps))); done = 1; exit }
                  if ($4 <= t && prev == "") { printf "%.3g", $3; done = 1; exit }
                  prev = 1; pe = $4; ps = $3 }
        END { if (!done) printf "not reached" }' "$1"
}
{
    echo "# Results of the origin study's measurements"
    echo
    echo "Made by \`scripts/study.sh$([[ $tiny == 1 ]] && echo " --tiny")\` on $(date -u +%Y-%m-%d), commit $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown),"
    echo "${cpu:-unknown CPU}, $(nproc) cores; $elapsed s in all. Renderer: \`examples/render\`; study program:"
    echo "\`examples/study/study.cpp\`; plots: \`examples/study/plots.gp\`. Commands run:"
    echo
    for c in "${commands[@]}"; do echo "    ${c//$ROOT\//}"; done
    echo
    echo "Errors are over the pixels whose primary ray hits hair. Seconds are wall-clock on the"
    echo "machine above. The theory behind the columns is in [../theory.md](../theory.md) §5."
    echo
    echo "## 1. Convergence: uniform against importance sampling"
    echo
    echo "Dual scattering on the 1,500-hair block, ${size[*]}. \`env\`: white environment only;"
    echo "\`both\`: the small area light plus a dim environment, BCSDF sampling alone in both samplers."
    echo
    for lighting in env both; do
        echo "### Lighting: $lighting"
        echo
        echo "![RMSE against spp](convergence_${lighting}_spp.png) ![RMSE against seconds](convergence_${lighting}_time.png)"
        echo
        table "$out/convergence_$lighting.csv"
        echo
    done
    echo "## 2. Variance between consecutive spp levels"
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
    echo "The path tracer (MIS, Russian roulette only, no depth cut) through \`ChiangFiber\` is the"
    echo "reference, rendered as two independent halves: path_noise is half their difference in mean,"
    echo "relative. rel_error_mean = (mean − mean_path)/mean_path of the hair pixels' mean radiance;"
    echo "mean_abs_pixel_rel_error = mean of |x − path|/(path + 0.01). dual_improved is the library's"
    echo "default formulation, dual_zinke Zinke et al. 2008 as written (theory.md §5.3, §5.5)."
    echo
    echo "### Blocks without the ground plane: colour and density"
    echo
    table "$out/dual_vs_path_block_both_noground.csv"
    echo
    echo "### A scalp without the ground plane"
    echo
    table "$out/dual_vs_path_scalp_both_noground.csv"
    echo
    echo "### Blocks with the ground plane (its bounce light reaches only the path tracer)"
    echo
    table "$out/dual_vs_path_block_both.csv"
    echo
    echo "Images (blocks without ground, 1,500 hairs): path, dual (improved), dual (Zinke), and the"
    echo "improved dual's error (black 0 → white ≥ 50 %):"
    echo
    for colour in "${dvp_colours[@]}"; do
        b="dvp_block_both_noground_${colour}_1500"
        [[ -f "$out/${b}_path.png" ]] && echo "![path](${b}_path.png) ![dual](${b}_dual_improved.png) ![zinke](${b}_dual_zinke.png) ![error](${b}_dual_improved_error.png)" && echo
    done
    echo "## 4. Time to equal error"
    echo
    echo "Blond 1,500-hair block without ground, ${tte_size[*]}, MIS for both; relative RMSE ="
    echo "√(mean (x − ref)²) / mean ref over the hair pixels against the path-traced reference of"
    echo "the --reference-spp above (its own relative RMSE in the last column)."
    echo
    echo "| target | dual scattering (s) | path tracing (s) |"
    echo "|---|---|---|"
    for t in 0.10 0.05; do
        echo "| ${t} | $(reach "$out/time_to_error.csv" dual "$t") | $(reach "$out/time_to_error.csv" path "$t") |"
    done
    echo
    echo "![relative RMSE against seconds](time_to_error.png)"
    echo
    table "$out/time_to_error.csv"
    echo
    echo "## 5. Scale: time and memory against strand count"
    echo
    echo "One process per run (${scale_size[*]}); peak_rss_mb is the process's VmHWM, embree_mb what"
    echo "Embree allocated (BVH and buffers), grid_mb the density grid, tables_kb the dual tables."
    echo
    table "$scale_csv"
    echo
    echo "![time against strands](scale_time.png) ![memory against strands](scale_memory.png)"
    echo
    echo "## 6. The origin study's scenes"
    echo
    echo "Dual scattering with MIS, ${gallery_size[*]}, blond hair: the 5 × 5 × 5 blocks of"
    echo "${gallery_blocks[*]} hairs on the ground plane, and the Cornell box."
    echo
    line=""
    for g in "${gallery[@]}"; do line+="![$g]($g.png) "; done
    echo "$line"
} >"$out/README.md"
echo "study.sh: wrote $out ($elapsed s)"
