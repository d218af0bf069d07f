# docs/fur_roughness.png from docs/fur_roughness.dat, which is written by
#   fur_roughness_tool --rays 4000000 --theta 30 --alphas 0.17,0.3 --dat docs/fur_roughness.dat
# (tests/tools/fur_roughness_tool.cpp). gnuplot docs/fur_roughness.gp, from the repository root.
# The fur model without a medulla (Chiang's lobes, β_m = β_n = 0.3) against the physical
# fibre with GGX α 0.17 (the α whose R lobe is as wide) and 0.3, lossless, θo = 30°: each
# path class's f integrated over φ (left, per unit sin θi) and over sin θi (right, per radian).
set terminal pngcairo size 1200,480 font ",11"
set output "docs/fur_roughness.png"
set multiplot layout 1,2
set key top left font ",9"
set grid
set logscale y
set yrange [1e-3:*]
f = "docs/fur_roughness.dat"
set title "over φ: f per unit sin θi (θo = 30°)"
set xlabel "sin θi"
plot f index 0 using 1:2 with lines lw 2 lc rgb "#1f77b4" title "R model β 0.3", \
     f index 2 using 1:2 with lines lw 2 dt 2 lc rgb "#1f77b4" title "R GGX 0.17", \
     f index 4 using 1:2 with lines lw 1 dt 3 lc rgb "#1f77b4" title "R GGX 0.3", \
     f index 0 using 1:3 with lines lw 2 lc rgb "#d62728" title "TT model", \
     f index 2 using 1:3 with lines lw 2 dt 2 lc rgb "#d62728" title "TT GGX 0.17", \
     f index 4 using 1:3 with lines lw 1 dt 3 lc rgb "#d62728" title "TT GGX 0.3", \
     f index 0 using 1:($4+$5) with lines lw 2 lc rgb "#2ca02c" title "TRT+ model", \
     f index 2 using 1:($4+$5) with lines lw 2 dt 2 lc rgb "#2ca02c" title "TRT+ GGX 0.17", \
     f index 4 using 1:($4+$5) with lines lw 1 dt 3 lc rgb "#2ca02c" title "TRT+ GGX 0.3"
set title "over sin θi: f per radian of φ"
set xlabel "φ = atan2(z, y) (wo at π/2, forward at −π/2)"
set xrange [-pi:pi]
plot f index 1 using 1:2 with lines lw 2 lc rgb "#1f77b4" title "R model β 0.3", \
     f index 3 using 1:2 with lines lw 2 dt 2 lc rgb "#1f77b4" title "R GGX 0.17", \
     f index 5 using 1:2 with lines lw 1 dt 3 lc rgb "#1f77b4" title "R GGX 0.3", \
     f index 1 using 1:3 with lines lw 2 lc rgb "#d62728" title "TT model", \
     f index 3 using 1:3 with lines lw 2 dt 2 lc rgb "#d62728" title "TT GGX 0.17", \
     f index 5 using 1:3 with lines lw 1 dt 3 lc rgb "#d62728" title "TT GGX 0.3", \
     f index 1 using 1:($4+$5) with lines lw 2 lc rgb "#2ca02c" title "TRT+ model", \
     f index 3 using 1:($4+$5) with lines lw 2 dt 2 lc rgb "#2ca02c" title "TRT+ GGX 0.17", \
     f index 5 using 1:($4+$5) with lines lw 1 dt 3 lc rgb "#2ca02c" title "TRT+ GGX 0.3"
unset multiplot
