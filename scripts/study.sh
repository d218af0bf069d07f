#!/usr/bin/env bash
# The origin study's measurements with the example renderer, written to docs/results/:
#   1. convergence: error of dual scattering against spp and against seconds, uniform vs
#      importance sampling of the dual-scattering BCSDF, over the hair pixels, under a white
#      environment and under the preset's area light + dim environment;
#   2. the variance between consecutive spp levels and where it drops below a threshold;
#   3. dual scattering (two-stream, improved and Zinke 2008) and single scattering against
#      the path tracer: white / blond / brown / dark × 400 / 1,500 / 6,000 / 12,000 hairs
#      without ground, blocks on the ground plane, a scalp with and without it, fur on a
#      body and a shell of fur, slabs lit from behind and from the front: error of the
#      mean hair radiance, mean per-pixel error, error images, times per sample;
#   4. the white furnace (lossless hair, uniform environment) on every kind of scene;
#   5. time to equal error: seconds for dual scattering and for the path tracer to reach a
#      relative RMSE over the hair pixels against a converged path-traced reference, on the
#      blond 1,500-hair block and on blond fur;
#   6. scale: render time and peak memory against strand count;
#   7. a gallery of the origin study's scenes: the four hair blocks, the Cornell box, fur;
#   8. arrivals by direction: the light arriving at hair points along each direction, by the
#      dual integrator and by the path tracer, binned by the fibers along it.
# Tables (CSV), plots (PNG, gnuplot) and docs/results/README.md with the commands, the
# machine and the date; the page holds measured tables only. The full run owns
# docs/results: it empties the folder first. About 40 minutes on 2 cores.
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
# Every file under the results folder is this run's: nothing stale survives a rerun.
find "$out" -maxdepth 1 -type f \( -name '*.csv' -o -name '*.png' -o -name '*.exr' -o -name '*.txt' -o -name 'README.md' \) -delete

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
    dvp_all_colours=(blond dark)
    scalp_counts=(2000)
    fur_counts=(2000)
    fur_shell_counts=(2000)
    fur_variants=(fur-short)
    slab_depths=(5)
    furnace_scenes=(block:1500 fur-shell:2000 slab:5)
    furnace_spp=(--dual-spp 4 --path-spp 8)
    tte=(--reference-spp 64 --dual-max-spp 8 --path-max-spp 16)
    tte_fur=(--hairs 2000)
    tte_size=(--width 32 --height 24)
    tte_large=(--reference-spp 32 --dual-max-spp 4 --path-max-spp 8)
    tte_large_size=(--width 40 --height 30)
    scale_blocks=(1500 3000)
    scale_scalps=()
    scale_size=(--width 64 --height 48 --spp 1)
else
    size=(--width 80 --height 60)
    conv=(--max-spp 128 --reference-spp 1024 --threshold 0.01)
    dvp_counts=(400 1500 6000 12000)
    dvp_colours=(white blond brown dark)
    dvp_spp=(--dual-spp 64 --path-spp 512)
    dvp_all_colours=(white blond brown dark)
    scalp_counts=(20000)
    fur_counts=(20000)
    # A shell as dense as a real pelt (50,000 short radial strands, the geometry of public fur
    # models) beside the study's 20,000: the deep regime where straight stacks overestimate.
    fur_shell_counts=(20000 50000)
    # The dense shell's variants, geometry no default was measured on (study.cpp's block_scene):
    # a short pelt, long fur, fur combed flat, fibers twice as thick.
    fur_variants=(fur-short fur-long fur-flat fur-coarse)
    slab_depths=(5 10)
    furnace_scenes=(block:400 block:1500 block:6000 block:12000 scalp:20000 fur:20000 fur-shell:20000 fur-shell:50000
        fur-short:50000 fur-long:50000 slab:1 slab:5 slab:10 slab:40)
    furnace_spp=(--dual-spp 32 --path-spp 64)
    tte=(--reference-spp 8192 --dual-max-spp 1024 --path-max-spp 4096)
    tte_fur=(--hairs 20000)
    tte_size=(--width 48 --height 36)
    # The same at a size where the dual setup (tables, grid, count field, glow volume: a fixed
    # cost per frame) weighs as it does in a real render, field counts only (the default).
    tte_large=(--reference-spp 8192 --dual-max-spp 1024 --path-max-spp 4096)
    tte_large_size=(--width 160 --height 120)
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
run "$STUDY" dual-vs-path --scene scalp --lighting both "${size[@]}" "${dvp_spp[@]}" \
    --hair-counts "${scalp_counts[@]}" --colours blond dark --out "$out"
run "$STUDY" dual-vs-path --lighting both "${size[@]}" "${dvp_spp[@]}" --hair-counts 1500 \
    --colours "${dvp_all_colours[@]}" --out "$out"
run "$STUDY" dual-vs-path --scene fur --lighting both "${size[@]}" "${dvp_spp[@]}" --hair-counts "${fur_counts[@]}" \
    --colours "${dvp_all_colours[@]}" --out "$out"
run "$STUDY" dual-vs-path --scene fur-shell --lighting both --no-ground "${size[@]}" "${dvp_spp[@]}" \
    --hair-counts "${fur_shell_counts[@]}" --colours "${dvp_all_colours[@]}" --out "$out"
# The dense shell on the ground plane (what the renderer gives a loaded .hair file by default).
run "$STUDY" dual-vs-path --scene fur-shell --lighting both "${size[@]}" "${dvp_spp[@]}" \
    --hair-counts "${fur_shell_counts[@]: -1}" --colours "${dvp_all_colours[@]}" --out "$out"
for variant in "${fur_variants[@]}"; do
    run "$STUDY" dual-vs-path --scene "$variant" --lighting both --no-ground "${size[@]}" "${dvp_spp[@]}" \
        --hair-counts "${fur_shell_counts[@]: -1}" --colours white blond --out "$out"
done
run "$STUDY" dual-vs-path --scene slab --lighting both "${size[@]}" "${dvp_spp[@]}" --hair-counts "${slab_depths[@]}" \
    --colours blond brown --out "$out"
# The same slabs lit from the front (the light above the camera), white to brown: the
# estimator's reflection where its transmission is measured above.
run "$STUDY" dual-vs-path --scene slab-front --lighting both "${size[@]}" "${dvp_spp[@]}" \
    --hair-counts "${slab_depths[@]}" --colours white blond brown --out "$out"

# ---- 4: the white furnace ----------------------------------------------------------------
run "$STUDY" furnace --scenes "${furnace_scenes[@]}" "${size[@]}" "${furnace_spp[@]}" --out "$out"

# ---- 5: time to equal error -----------------------------------------------------------
run "$STUDY" time-to-error --no-ground --colour blond --hairs 1500 --lighting both "${tte_size[@]}" "${tte[@]}" --out "$out"
run "$STUDY" time-to-error --scene fur-shell --no-ground --colour blond "${tte_fur[@]}" --lighting both "${tte_size[@]}" \
    "${tte[@]}" --out "$out"
large_suffix="_${tte_large_size[1]}x${tte_large_size[3]}"
run "$STUDY" time-to-error --no-ground --colour blond --hairs 1500 --lighting both "${tte_large_size[@]}" "${tte_large[@]}" \
    --formulations two-stream-field --tag-suffix "$large_suffix" --out "$out"
run "$STUDY" time-to-error --scene fur-shell --no-ground --colour blond "${tte_fur[@]}" --lighting both \
    "${tte_large_size[@]}" "${tte_large[@]}" --formulations two-stream-field --tag-suffix "$large_suffix" --out "$out"

# ---- 6: scale --------------------------------------------------------------------------
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

# ---- 7: the origin study's scenes ----------------------------------------------------------------
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
run "$RENDER" --scene fur "${gallery_size[@]}" --quiet -o "$out/scene_fur" >/dev/null
gallery+=("scene_fur")

# ---- 8: arrivals by direction -----------------------------------------------------------
# The light arriving at the camera's hair points along the fiber's sampled directions, by the
# two-stream estimator (at the camera's hit, and after one traced vertex) and by the path
# tracer, binned by the fibers along the direction and where it points.
if [[ $tiny == 1 ]]; then
    arrivals=(--points 300 --dual-samples 2 --path-samples 4 --width 48 --height 36)
else
    arrivals=(--points 20000 --dual-samples 8 --path-samples 32 --width 80 --height 60)
fi
arrival_runs=()
arrival_run() {  # name, study arguments...
    local name="$1"; shift
    run "$STUDY" arrivals "$@" "${arrivals[@]}" >"$out/arrivals_$name.txt"
    arrival_runs+=("$name")
}
for colour in blond brown; do
    for f in two-stream-field two-stream-field-v1; do
        arrival_run "block_area_${colour}_1500_${f//-/_}" --scene block --hairs 1500 --lighting area --no-ground \
            --colour "$colour" --formulation "$f"
    done
done
shell="${fur_shell_counts[-1]}"
arrival_run "fur_shell_both_white_${shell}_two_stream_field" --scene fur-shell --hairs "$shell" --lighting both \
    --no-ground --colour white --formulation two-stream-field

# ---- checks (always; they are what --tiny is for) -------------------------------------
fail=0
for f in "$out"/convergence_env_reference.exr "$out"/convergence_both_reference.exr "$out"/scene_cornell.exr \
    "$out"/time_to_error_block_blond_1500.csv "$out"/dual_vs_path_scalp_both_noground.csv "$out"/furnace.csv \
    "$out"/dual_vs_path_fur-shell_both_noground.csv "$out"/dual_vs_path_slab_both.csv; do
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
# The white furnace: the two-stream integrator (exact and field counts) within 2 % of 1 on
# every scene, at any size.
awk -F, 'NR > 1 && ($3 == "dual_two_stream" || $3 == "dual_two_stream_field") { d = $6 - 1; if (d < 0) d = -d; if (d > 0.02) { printf "study: furnace %s %s: %s\n", $1, $2, $6 > "/dev/stderr"; bad = 1 } }
         END { exit bad }' "$out/furnace.csv" || fail=1
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
# With a noise column (5 per pixel, 7 after 4×4 blocks), the error against the truth instead:
# √(e² − e_ref²), the reference's own noise removed (the image and the reference are
# independent, so their squared errors add).
# A time column (default 3, the wall-clock seconds; 9 the CPU seconds) reads that clock.
reach() {  # csv integrator target [error column: 4 per pixel (default), 6 after 4×4 blocks] [noise column] [time column]
    awk -F, -v n="$2" -v t="$3" -v c="${4:-4}" -v r="${5:-0}" -v k="${6:-3}" '
        $1 == n { seen = 1; e = $c; if (r > 0) { v = e * e - $r * $r; e = v > 0 ? sqrt(v) : 1e-9 }
                  if (prev != "" && e <= t && pe > t) { f = (log(pe) - log(t)) / (log(pe) - log(e));
                      printf "%.3g", exp(log(ps) + f * (log($k) - log(ps))); done = 1; exit }
                  if (e <= t && prev == "") { printf "%.3g", $k; done = 1; exit }
                  prev = 1; pe = e; ps = $k }
        END { if (!done) printf (seen ? "not reached" : "–") }' "$1"
}
# How many times sooner the path tracer's time is than another integrator's (a ratio of two reach
# outputs; "–" when either is missing).
sooner() { awk -v p="$1" -v d="$2" 'BEGIN { if (p + 0 > 0 && d + 0 > 0) printf "%.1f×", p / d; else printf "–" }'; }
floor_of() {  # csv integrator column [noise column]: the error at the largest spp
    awk -F, -v n="$2" -v c="$3" -v r="${4:-0}" '$1 == n { seen = 1; e = $c; if (r > 0) { v = e * e - $r * $r; e = v > 0 ? sqrt(v) : 0 } }
        END { if (seen) printf "%.3f", e; else printf "–" }' "$1"
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
    echo "mean_abs_pixel_rel_error = mean of |x − path|/(path + 0.01). dual_two_stream is the"
    echo "two-stream estimator with exact fiber counts (surfaces traced); dual_two_stream_field the"
    echo "same estimator with counts looked up in the directional count field (the renderer's default);"
    echo "both with the stacks inclined to their fibers (the default; a -planar suffix keeps the 1D stack);"
    echo "dual_improved and dual_zinke are the dual-scattering BCSDF in the improved formulation and"
    echo "as Zinke et al. 2008 wrote it, which see other surfaces only as shadow casters (theory.md §5)."
    echo "Scenes: blocks of straight strands, a scalp, fur on a diffuse body (fur), the same strands as"
    echo "a hollow shell (fur-shell) and the shell's variants, on which no default was measured: a pelt"
    echo "a quarter as long (fur-short), twice as long (fur-long), combed flat (fur-flat: 70° from the"
    echo "normal instead of 30°) and of fibers twice as thick (fur-coarse); slab: a slab lit from behind;"
    echo "slab-front: the same slab lit from the front, the light above the camera."
    echo
    echo "### Every row at a glance"
    echo
    echo "Relative error of the mean hair radiance against the path tracer, and the cost of a sample"
    echo "on the hair pixels (µs per sample, from per-pixel clocks, every integrator on the same"
    echo "scene; the background's cost is left out)."
    echo
    echo "| scene | colour | hairs | two-stream | two-stream, field counts | improved | Zinke 2008 | single | path noise | µs/sample single | two-stream | field counts | path | two-stream ÷ single | field ÷ single | field ÷ path |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    for f in "$out"/dual_vs_path_*.csv; do
        tag="$(basename "$f" .csv)"; tag="${tag#dual_vs_path_}"
        awk -F, -v tag="$tag" '
            NR == 1 { next }
            { key = $1 SUBSEP $2; if (!(key in seen)) { seen[key] = 1; order[++n] = key }
              err[key, $3] = $8; ms[key, $3] = $11; noise[key] = $10 }
            function pct(x) { return x == "" ? "" : sprintf("%+.1f %%", 100 * x) }
            function num(x) { return x == "" ? "" : sprintf("%.2f", x) }
            END { for (i = 1; i <= n; i++) { k = order[i]; split(k, p, SUBSEP)
                    s = ms[k, "single"]; d = ms[k, "dual_two_stream"]; g = ms[k, "dual_two_stream_field"]; q = ms[k, "path"]
                    printf "| %s | %s | %s | %s | %s | %s | %s | %s | %.1f %% | %s | %s | %s | %s | %s | %s | %s |\n", tag, p[1], p[2],
                        pct(err[k, "dual_two_stream"]), pct(err[k, "dual_two_stream_field"]), pct(err[k, "dual_improved"]),
                        pct(err[k, "dual_zinke"]), pct(err[k, "single"]), 100 * noise[k], num(s), num(d), num(g), num(q),
                        (s > 0 && d != "") ? sprintf("%.2f×", d / s) : "", (s > 0 && g != "") ? sprintf("%.2f×", g / s) : "",
                        (q > 0 && g != "") ? sprintf("%.2f×", g / q) : "" } }' "$f"
    done
    echo
    for f in "$out"/dual_vs_path_*.csv; do
        tag="$(basename "$f" .csv)"
        echo "### ${tag#dual_vs_path_}"
        echo
        table "$f"
        echo
    done
    echo "Images (blocks without ground, 1,500 hairs): path, dual (two-stream), dual (improved), and the"
    echo "two-stream dual's error (black 0 → white ≥ 50 %):"
    echo
    for colour in "${dvp_colours[@]}"; do
        b="dvp_block_both_noground_${colour}_1500"
        [[ -f "$out/${b}_path.png" ]] && echo "![path](${b}_path.png) ![dual](${b}_dual_two_stream.png) ![improved](${b}_dual_improved.png) ![error](${b}_dual_two_stream_error.png)" && echo
    done
    echo "## 4. The white furnace"
    echo
    echo "Lossless hair (σa = 0) and white surfaces (a body or a head of albedo 1) under a uniform"
    echo "environment of radiance 1, no ground: the exact answer is 1 at every hair pixel. Mean over"
    echo "the hair pixels, ${size[*]}; slab:N is a slab N fibers deep."
    echo
    echo "| scene | hairs | two-stream | two-stream (grid counts) | two-stream (field counts) | improved | Zinke 2008 | path |"
    echo "|---|---|---|---|---|---|---|---|"
    awk -F, 'NR == 1 { next }
        { key = $1 SUBSEP $2; if (!(key in seen)) { seen[key] = 1; order[++n] = key } m[key, $3] = $6 }
        END { for (i = 1; i <= n; i++) { k = order[i]; split(k, p, SUBSEP)
                printf "| %s | %s | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f |\n", p[1], p[2], m[k, "dual_two_stream"],
                       m[k, "dual_two_stream_grid"], m[k, "dual_two_stream_field"], m[k, "dual_improved"], m[k, "dual_zinke"],
                       m[k, "path"] } }' "$out/furnace.csv"
    echo
    echo "## 5. Time to equal error"
    echo
    echo "Blond hair without ground, ${tte_size[*]} (and ${tte_large_size[*]}, the tables whose names end"
    echo "in ${large_suffix}, field counts only), MIS for both, dual = the two-stream integrator;"
    echo "relative RMSE = √(mean (x − ref)²) / mean ref over the hair pixels against the path-traced"
    echo "reference of the --reference-spp above (its own relative RMSE in the reference columns);"
    echo "after 4×4 blocks: each 4 × 4 block's hair pixels averaged first, which removes most noise"
    echo "and keeps the bias. The reference is noisy too; the rows \"against the truth\" remove its"
    echo "noise from each error, √(e² − e_ref²) (image and reference are independent, so their squared"
    echo "errors add), which estimates the error against a converged reference. Seconds are the"
    echo "render's plus, for dual scattering, its setup (setup_seconds: the tables, the density grid"
    echo "and the count field, which the path tracer does not need); the render's own seconds hold the"
    echo "glow volume's build. The setup is a fixed cost per frame, so it weighs more the fewer pixels"
    echo "an image has: at ${tte_size[*]} it is most of dual scattering's time to 10 %, at"
    echo "${tte_large_size[*]} a small part. CPU seconds (cpu_seconds, setup_cpu_seconds) are the process's"
    echo "CPU time for the same work, every thread's: unlike the wall clock they do not grow when other"
    echo "jobs share the machine, so they are the figures to compare between runs."
    echo
    for t in "$out"/time_to_error_*.csv; do
        tag="$(basename "$t" .csv)"; tag="${tag#time_to_error_}"
        echo "### $tag"
        echo
        echo "| relative RMSE | dual scattering (s) | dual, field counts (s) | path tracing (s) |"
        echo "|---|---|---|---|"
        for e in 0.20 0.10 0.05; do
            echo "| ${e} per pixel | $(reach "$t" dual "$e") | $(reach "$t" dual_field "$e") | $(reach "$t" path "$e") |"
        done
        for e in 0.20 0.10 0.08 0.05; do
            echo "| ${e} after 4×4 blocks | $(reach "$t" dual "$e" 6) | $(reach "$t" dual_field "$e" 6) | $(reach "$t" path "$e" 6) |"
        done
        echo "| floor per pixel (largest spp) | $(floor_of "$t" dual 4) | $(floor_of "$t" dual_field 4) | $(floor_of "$t" path 4) |"
        echo "| floor after 4×4 blocks | $(floor_of "$t" dual 6) | $(floor_of "$t" dual_field 6) | $(floor_of "$t" path 6) |"
        echo "| *against the truth (the reference's noise removed):* | | | |"
        for e in 0.20 0.10; do
            echo "| ${e} per pixel | $(reach "$t" dual "$e" 4 5) | $(reach "$t" dual_field "$e" 4 5) | $(reach "$t" path "$e" 4 5) |"
        done
        for e in 0.10 0.08; do
            echo "| ${e} after 4×4 blocks | $(reach "$t" dual "$e" 6 7) | $(reach "$t" dual_field "$e" 6 7) | $(reach "$t" path "$e" 6 7) |"
        done
        echo "| floor per pixel (largest spp) | $(floor_of "$t" dual 4 5) | $(floor_of "$t" dual_field 4 5) | $(floor_of "$t" path 4 5) |"
        echo "| floor after 4×4 blocks | $(floor_of "$t" dual 6 7) | $(floor_of "$t" dual_field 6 7) | $(floor_of "$t" path 6 7) |"
        echo "| *CPU seconds, against the truth:* | | | |"
        for e in 0.20 0.10; do
            echo "| ${e} per pixel | $(reach "$t" dual "$e" 4 5 9) | $(reach "$t" dual_field "$e" 4 5 9) | $(reach "$t" path "$e" 4 5 9) |"
        done
        local_p="$(reach "$t" path 0.10 4 5 9)"
        echo "| path ÷ dual at 0.10 per pixel (CPU, truth) | $(sooner "$local_p" "$(reach "$t" dual 0.10 4 5 9)") | $(sooner "$local_p" "$(reach "$t" dual_field 0.10 4 5 9)") | |"
        echo
        [[ -f "$out/time_to_error_$tag.png" ]] && echo "![relative RMSE against seconds](time_to_error_$tag.png)" && echo
        table "$t"
        echo
    done
    echo "## 6. Scale: time and memory against strand count"
    echo
    echo "One process per run (${scale_size[*]}); peak_rss_mb is the process's VmHWM, embree_mb what"
    echo "Embree allocated (BVH and buffers), grid_mb the density grid, tables_kb the dual tables."
    echo
    table "$scale_csv"
    echo
    echo "![time against strands](scale_time.png) ![memory against strands](scale_memory.png)"
    echo
    echo "## 7. The origin study's scenes"
    echo
    echo "Dual scattering (two-stream), ${gallery_size[*]}, blond hair: the 5 × 5 × 5 blocks of"
    echo "${gallery_blocks[*]} hairs on the ground plane, the Cornell box, and fur on a body."
    echo
    line=""
    for g in "${gallery[@]}"; do line+="![$g]($g.png) "; done
    echo "$line"
    echo
    echo "## 8. Arrivals by direction"
    echo
    echo "\`study arrivals\` (render::arrival_profile): at hair points the camera sees, one direction a"
    echo "from the fiber's sampler each; the light arriving along a by the dual integrator"
    echo "(--dual-samples estimates) and by the path tracer (--path-samples paths), binned by the"
    echo "fibers along a (exact counts) and by where a points: away from or toward the camera, and"
    echo "toward the area light (cos > 0.3), across, or off it. w·dual and w·path: the bin's part of"
    echo "the pixel's light (each sample weighted by the fiber's f cos / pdf); excess: (w·dual −"
    echo "w·path) over the total. Means within a few per cent can hide bins that are far off."
    echo "Count bins are half-open: 2-4 holds directions crossing 2 or 3 fibers."
    echo "Formulations with -v1 trace one vertex before the estimator (--dual-vertices 1 --dual-glow 0)."
    echo
    for name in "${arrival_runs[@]}"; do
        echo "### $name"
        echo
        echo '```'
        cat "$out/arrivals_$name.txt"
        echo '```'
        echo
    done
} >"$out/README.md"
echo "study.sh: wrote $out ($elapsed s)"
