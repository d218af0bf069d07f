# Plots of scripts/study.sh: gnuplot -e "dir='docs/results'" examples/study/plots.gp
set terminal pngcairo size 640,460 font "sans,10"
set datafile separator ','
set logscale xy
set grid xtics ytics mxtics mytics lc rgb "#dddddd"
set key top right
sel(s) = (strcol(1) eq s) ? 1 : NaN

do for [l in "env both"] {
    set output dir."/convergence_".l."_spp.png"
    set title "dual scattering, lighting ".l.": RMSE over hair pixels"
    set xlabel "samples per pixel"
    set ylabel "RMSE against the reference"
    plot dir."/convergence_".l.".csv" skip 1 using 2:($4*sel("uniform")) with linespoints pt 7 title "uniform", \
         ''                           skip 1 using 2:($4*sel("importance")) with linespoints pt 5 title "importance"
    set output dir."/convergence_".l."_time.png"
    set xlabel "render seconds (2 threads)"
    plot dir."/convergence_".l.".csv" skip 1 using 3:($4*sel("uniform")) with linespoints pt 7 title "uniform", \
         ''                           skip 1 using 3:($4*sel("importance")) with linespoints pt 5 title "importance"
}

set output dir."/convergence_variance.png"
set title "variance between consecutive spp levels (relative to the reference's mean square)"
set xlabel "samples per pixel"
set ylabel "mean (I_{spp} - I_{spp/2})^2 / mean I_{ref}^2"
plot dir."/convergence_env.csv"  skip 1 using 2:($7 > 0 ? $7*sel("uniform") : NaN) with linespoints pt 7 title "env, uniform", \
     ''                          skip 1 using 2:($7 > 0 ? $7*sel("importance") : NaN) with linespoints pt 5 title "env, importance", \
     dir."/convergence_both.csv" skip 1 using 2:($7 > 0 ? $7*sel("uniform") : NaN) with linespoints pt 6 title "area+env, uniform", \
     ''                          skip 1 using 2:($7 > 0 ? $7*sel("importance") : NaN) with linespoints pt 4 title "area+env, importance"

# scale.csv: scene,strands,segments,integrator,render_s,build_s,peak_rss_mb,...
isint(s) = (strcol(4) eq s) ? 1 : NaN
set key top left
set output dir."/scale_time.png"
set title "time against strand count (blocks, then scalps)"
set xlabel "strands"
set ylabel "seconds"
plot dir."/scale.csv" skip 1 using 2:($5*isint("single")) with linespoints pt 7 title "render, single", \
     ''               skip 1 using 2:($5*isint("dual")) with linespoints pt 5 title "render, dual", \
     ''               skip 1 using 2:($5*isint("path")) with linespoints pt 9 title "render, path tracer", \
     ''               skip 1 using 2:($6*isint("dual")) with linespoints pt 6 title "scene build (BVH, grid, tables)"
set output dir."/scale_memory.png"
set title "memory against strand count"
set ylabel "MB"
plot dir."/scale.csv" skip 1 using 2:($7*isint("dual")) with linespoints pt 7 title "peak RSS (dual run)", \
     ''               skip 1 using 2:($8*isint("dual")) with linespoints pt 5 title "Embree (BVH + buffers)", \
     ''               skip 1 using 2:($9*isint("dual")) with linespoints pt 6 title "density grid"

# time_to_error_<tag>.csv: integrator,spp,seconds,rel_rmse,reference_rel_rmse,...,cpu_seconds (9)
set key top right
set xlabel "CPU seconds (render and setup, every thread)"
set ylabel "relative RMSE"
# every time_to_error_<tag>.csv in dir (the study's small and large sizes, --tiny's)
tags = system("cd ".dir." && ls time_to_error_*.csv 2>/dev/null | sed 's/^time_to_error_//; s/[.]csv$//'")
do for [t in tags] {
    f = dir."/time_to_error_".t.".csv"
    if (system("test -s ".f." && echo 1") eq "1") {
        set output dir."/time_to_error_".t.".png"
        set title "time to equal error, ".t.": relative RMSE over hair pixels against the converged reference"
        plot f skip 1 using 9:($4*sel("dual")) with linespoints pt 7 title "dual scattering (two-stream)", \
             '' skip 1 using 9:($4*sel("dual_field")) with linespoints pt 9 title "dual scattering, field counts", \
             '' skip 1 using 9:($4*sel("path")) with linespoints pt 5 title "path tracing", \
             0.1 with lines dt 2 lc rgb "#888888" title "10 %", 0.05 with lines dt 3 lc rgb "#888888" title "5 %"
    }
}
