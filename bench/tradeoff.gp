# The speed/accuracy plot of docs/tradeoff.md: error of f against eval time, log-log,
# one point per setting. Called by scripts/tradeoff.sh:
#   gnuplot -e "csv='docs/tradeoff.csv'; png='docs/tradeoff.png'" bench/tradeoff.gp
set terminal pngcairo size 1100,760 font "sans,10"
set output png
set datafile separator ','
set logscale xy
set format y "10^{%L}"
set xlabel "eval time (calibration units u, float loop; lower is faster)"
set ylabel "relative L1 error of f against the double-precision reference"
set title "hairscatter: speed against accuracy, one point per model setting"
set grid xtics ytics mxtics mytics lc rgb "#dddddd"
set key bottom right box opaque
set yrange [1e-11:3]
set xrange [0.2:4000]
# Column 8 = eval time in u, 9 = relative L1 error, 1 = model, 2 = knob, 3 = precision.
pick(m) = (strcol(1) eq m) ? column(9) : NaN
# Marschner in a darker yellow than gnuplot's default, which is hard to read on white.
set linetype 5 lc rgb "#b8a000"
err(x) = (x < 1e-11) ? 1e-11 : x
name(m) = m
# (Huang's errors are against its own brute-force reference, whose noise is ~6e-3.)
plot for [m in "chiang pbrt-v4-style deon-farfield tabulated marschner huang"] csv skip 1 \
         using 8:(err(pick(m))) with points pt 7 ps 1.4 title m, \
     csv skip 1 using 8:((strcol(3) eq "float") ? err(column(9)) : NaN):(strcol(2)." ".strcol(3)) \
         with labels offset 0.8,0.6 left font "sans,8" notitle, \
     csv skip 1 using 8:((strcol(3) eq "double") ? err(column(9)) : NaN):(strcol(2)." ".strcol(3)) \
         with labels offset 0.8,-0.8 left font "sans,8" notitle
