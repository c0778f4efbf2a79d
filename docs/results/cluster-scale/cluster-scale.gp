set datafile separator ','
set terminal pngcairo size 1400,900 font 'Sans,11'
set output 'docs/results/cluster-scale/cluster-scale.png'
set multiplot layout 2,2 title 'A world at rest: lpss-cluster against lpss-sim on the same scene (targets dotted)'
set datafile missing NaN
set logscale x
set xrange [7000:1.5e6]
set yrange [0:*]
set xlabel 'bodies at rest'
set key top right font ',8'
set grid
set ylabel 'first frame / lpss-sim load'
set title 'Start: time to the first frame, over lpss-sim loading the scene (worker counts offset)'
plot 'docs/results/cluster-scale/cluster-scale.csv' using ($1*0.94):($2==1?$5:NaN) with linespoints pt 7 lc 1 title '1 worker', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==2?$5:NaN) with linespoints pt 5 lc 2 title '2 workers', \
     'docs/results/cluster-scale/cluster-scale.csv' using ($1*1.06):($2==4?$5:NaN) with linespoints pt 9 lc 3 title '4 workers', \
     1.5 with lines dt 3 lc rgb 'black' title 'target 1.5'
set ylabel 'ms per frame / (1.5 x lpss-sim + 1 ms)'
set title "Running: frame over its budget, rounds' median and range; p99 open"
set key top left maxrows 4 width 1 samplen 2
set logscale y
set yrange [0.5:12]
set ytics (0.5, 0.75, 1, 1.5, 2, 3, 5, 8, 12)
plot 'docs/results/cluster-scale/cluster-scale.csv' using ($1*0.94):($2==1?$25:NaN):26:27 with yerrorlines pt 7 lc 1 title '1 worker', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==2?$25:NaN):26:27 with yerrorlines pt 5 lc 2 title '2 workers', \
     'docs/results/cluster-scale/cluster-scale.csv' using ($1*1.06):($2==4?$25:NaN):26:27 with yerrorlines pt 9 lc 3 title '4 workers', \
     'docs/results/cluster-scale/cluster-scale.csv' using ($1*0.94):($2==1?$7/$10:NaN) with points pt 6 lc 1 title '1 worker p99', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==2?$7/$10:NaN) with points pt 4 lc 2 title '2 workers p99', \
     'docs/results/cluster-scale/cluster-scale.csv' using ($1*1.06):($2==4?$7/$10:NaN) with points pt 8 lc 3 title '4 workers p99', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==1?$9/$10:NaN) with points pt 12 lc 4 title 'lpss-sim p99', \
     1 with lines dt 3 lc rgb 'black' title 'target'
unset logscale y
set yrange [0:*]
set ytics autofreq
set key default
set key top right font ',8'
set ylabel 'all processes / lpss-sim'
set title 'Memory, all processes over lpss-sim: resident (solid), shared pages once (dashed)'
set key top right font ',8' maxrows 3
plot 'docs/results/cluster-scale/cluster-scale.csv' using ($1*0.94):($2==1?$13:NaN) with linespoints pt 7 lc 1 title '1 worker', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==2?$13:NaN) with linespoints pt 5 lc 2 title '2 workers', \
     'docs/results/cluster-scale/cluster-scale.csv' using ($1*1.06):($2==4?$13:NaN) with linespoints pt 9 lc 3 title '4 workers', \
     'docs/results/cluster-scale/cluster-scale.csv' using ($1*0.94):($2==1?$16:NaN) with linespoints dt 2 pt 6 lc 1 title '1, Pss', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==2?$16:NaN) with linespoints dt 2 pt 4 lc 2 title '2, Pss', \
     'docs/results/cluster-scale/cluster-scale.csv' using ($1*1.06):($2==4?$16:NaN) with linespoints dt 2 pt 8 lc 3 title '4, Pss', \
     1.5 with lines dt 3 lc rgb 'black' title 'target 1.5'
set ylabel 'kB per frame'
set title 'Bytes the busiest worker receives per frame'
set key default
set key bottom right font ',8'
plot 'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==2?$19/1000:NaN) with linespoints pt 5 lc 2 title '2 workers', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==4?$19/1000:NaN) with linespoints pt 9 lc 3 title '4 workers'
unset multiplot
