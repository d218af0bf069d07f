#!/usr/bin/env bash
# Dual scattering against the path tracer on 34 quick rows, for trying a change to the
# two-stream estimator in about a minute rather than the study's hour (scripts/study.sh
# stays the record). The rows: the study's 17 lit blocks, scalps and fur shells (both
# lights, no ground unless named "g"), and 17 that the study's defaults were not chosen on:
# slabs lit from the front under the area light alone (fslab; those ending in v with their
# fibers vertical, along the light's offset from the camera: --slab-vertical), slabs lit
# from behind (bslab), a white scalp, curly scalps and the bust. Each row's mean hair
# radiance (mean of RGB) by the dual integrator, 80 x 60 at 64 spp, against the path
# tracer's at 512 spp on the same image; printed with the error, then the mean and worst
# |error| per group.
#
#   scripts/dual_probe.sh [--build DIR] [--refs FILE] [--make-refs] [--only REGEX] [render flags...]
#
# Render flags go to the dual renders only (for example --dual-transport diffuse). The path
# tracer's means come from FILE (default bench/results/dual_probe_refs.txt, "name mean" per
# line); --make-refs renders them into FILE first (about ten minutes on 2 cores). The
# path tracer's noise at 512 spp is 0.1-1 % of a row's mean.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="$ROOT/build/dev"
REFS="$ROOT/bench/results/dual_probe_refs.txt"
make_refs=0
only=""
flags=()
while [[ $# -gt 0 ]]; do
    case "$1" in
        --build) BUILD="$2"; shift ;;
        --refs) REFS="$2"; shift ;;
        --make-refs) make_refs=1 ;;
        --only) only="$2"; shift ;;
        -h|--help) sed -n '2,18p' "${BASH_SOURCE[0]}"; exit 0 ;;
        *) flags+=("$1") ;;
    esac
    shift
done
RENDER="$BUILD/examples/render/render"
[[ -x "$RENDER" ]] || { echo "dual_probe: no renderer at $RENDER (build the render target, or pass --build DIR)" >&2; exit 2; }

# group|name|scene arguments
rows=(
"study|block_w1500|--scene block --hairs 1500 --no-ground --colour white"
"study|block_w12000|--scene block --hairs 12000 --no-ground --colour white"
"study|block_b400|--scene block --hairs 400 --no-ground --colour blond"
"study|block_b1500|--scene block --hairs 1500 --no-ground --colour blond"
"study|block_b6000|--scene block --hairs 6000 --no-ground --colour blond"
"study|block_b12000|--scene block --hairs 12000 --no-ground --colour blond"
"study|block_br12000|--scene block --hairs 12000 --no-ground --colour brown"
"study|block_b1500g|--scene block --hairs 1500 --colour blond"
"study|scalp_b|--scene scalp --scalp-hairs 20000 --no-ground --colour blond"
"study|scalp_bg|--scene scalp --scalp-hairs 20000 --colour blond"
"study|shell_w50000|--scene fur --no-fur-body --fur-hairs 50000 --no-ground --colour white"
"study|shell_b50000|--scene fur --no-fur-body --fur-hairs 50000 --no-ground --colour blond"
"study|shell_b20000|--scene fur --no-fur-body --fur-hairs 20000 --no-ground --colour blond"
"study|shell_br50000|--scene fur --no-fur-body --fur-hairs 50000 --no-ground --colour brown"
"study|flat_b50000|--scene fur --no-fur-body --fur-hairs 50000 --no-ground --colour blond --fur-tilt 70"
"study|flat_w50000|--scene fur --no-fur-body --fur-hairs 50000 --no-ground --colour white --fur-tilt 70"
"study|fur_b20000|--scene fur --fur-hairs 20000 --colour blond"
"other|fslab_w5|--scene slab --slab-depth 5 --colour white --environment 0"
"other|fslab_w10|--scene slab --slab-depth 10 --colour white --environment 0"
"other|fslab_b5|--scene slab --slab-depth 5 --colour blond --environment 0"
"other|fslab_b10|--scene slab --slab-depth 10 --colour blond --environment 0"
"other|fslab_br10|--scene slab --slab-depth 10 --colour brown --environment 0"
"other|fslab_b10v|--scene slab --slab-vertical --slab-depth 10 --colour blond --environment 0"
"other|fslab_w10v|--scene slab --slab-vertical --slab-depth 10 --colour white --environment 0"
"other|bslab_b5|--scene slab --back-lit --slab-depth 5 --colour blond"
"other|bslab_b10|--scene slab --back-lit --slab-depth 10 --colour blond"
"other|bslab_br5|--scene slab --back-lit --slab-depth 5 --colour brown"
"other|bslab_br10|--scene slab --back-lit --slab-depth 10 --colour brown"
"other|scalp_w_light|--scene scalp --scalp-hairs 20000 --no-ground --colour white --environment 0"
"other|scalp_w_both|--scene scalp --scalp-hairs 20000 --no-ground --colour white"
"other|curl3_b|--scene scalp --scalp-hairs 20000 --no-ground --curl 0.3 --colour blond"
"other|curl3_w|--scene scalp --scalp-hairs 20000 --no-ground --curl 0.3 --colour white"
"other|head_b|--scene head --env constant --light-power 1 --colour blond"
"other|head_w|--scene head --env constant --light-power 1 --colour white"
)

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# The mean of the hair pixels' RGB mean from one render's summary line.
hair_mean() {
    local line
    line="$("$RENDER" "$@" --width 80 --height 60 -q -o "$tmp/img" 2>&1 | grep -o 'mean_hair_rgb=[0-9.e+-]*,[0-9.e+-]*,[0-9.e+-]*' || true)"
    [[ -n "$line" ]] || { echo "dual_probe: no mean_hair_rgb from: $RENDER $*" >&2; exit 1; }
    echo "${line#mean_hair_rgb=}" | awk -F, '{printf "%.6g\n", ($1 + $2 + $3) / 3}'
}

if [[ $make_refs == 1 ]]; then
    {
        echo "# The path tracer's mean hair radiance (mean of RGB) per scripts/dual_probe.sh row:"
        echo "# 80 x 60, 512 spp, $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown), $(date -u +%Y-%m-%d)."
        for r in "${rows[@]}"; do
            IFS='|' read -r group name args <<<"$r"
            # shellcheck disable=SC2086
            echo "$name $(hair_mean $args --spp 512 --integrator path)"
        done
    } >"$tmp/refs"
    mkdir -p "$(dirname "$REFS")"
    mv "$tmp/refs" "$REFS"
    echo "dual_probe: wrote $REFS"
fi
[[ -s "$REFS" ]] || { echo "dual_probe: no reference means in $REFS (run with --make-refs)" >&2; exit 2; }

printf '%-14s %-6s %10s %10s %8s\n' row group dual path error
for r in "${rows[@]}"; do
    IFS='|' read -r group name args <<<"$r"
    [[ -z "$only" || "$name" =~ $only ]] || continue
    ref="$(awk -v n="$name" '$1 == n {print $2}' "$REFS")"
    [[ -n "$ref" ]] || { echo "dual_probe: no reference for $name in $REFS" >&2; exit 2; }
    # shellcheck disable=SC2086
    m="$(hair_mean $args --spp 64 --integrator dual "${flags[@]+"${flags[@]}"}")"
    awk -v n="$name" -v g="$group" -v m="$m" -v r="$ref" \
        'BEGIN {printf "%-14s %-6s %10.5f %10.5f %+7.1f%%\n", n, g, m, r, 100 * (m / r - 1)}'
done | tee "$tmp/out"
awk 'NR > 0 {e = $5; sub(/%/, "", e); e += 0; e = (e < 0 ? -e : e); s[$2] += e; c[$2]++; if (e > w[$2]) w[$2] = e;
             S += e; C++; if (e > W) W = e}
     END {for (g in s) printf "%-6s rows %2d  mean |error| %5.2f %%  worst %5.1f %%\n", g, c[g], s[g] / c[g], w[g];
          if (C) printf "all    rows %2d  mean |error| %5.2f %%  worst %5.1f %%\n", C, S / C, W}' "$tmp/out"
