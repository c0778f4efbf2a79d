set datafile separator ','
set terminal pngcairo size 1400,900 font 'Sans,11'
set output 'docs/results/cluster-scale/cluster-scale.png'
set multiplot layout 2,2 title 'A world at rest: lpss-cluster against lpss-sim'
set logscale x
set xlabel 'bodies at rest'
set key top left font ',8'
set grid
set logscale y
set ylabel 'seconds'
set title 'Start: first frame'
plot 'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==1?$3:1/0) with linespoints pt 7 title '1 worker', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==2?$3:1/0) with linespoints pt 5 title '2 workers', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==4?$3:1/0) with linespoints pt 9 title '4 workers', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==1?$4:1/0) with linespoints pt 4 dt 2 title 'lpss-sim load', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==1?1.5*$4:1/0) with lines dt 3 lc rgb 'gray' title '1.5 x lpss-sim load'
set ylabel 'ms per frame'
set title 'Running: mean (solid) and p99 (open)'
plot 'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==1?$6:1/0) with linespoints pt 7 lc 1 title '1 worker', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==2?$6:1/0) with linespoints pt 5 lc 2 title '2 workers', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==4?$6:1/0) with linespoints pt 9 lc 3 title '4 workers', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==1?$7:1/0) with points pt 6 lc 1 title '1 worker p99', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==2?$7:1/0) with points pt 4 lc 2 title '2 workers p99', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==4?$7:1/0) with points pt 8 lc 3 title '4 workers p99', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==1?$9:1/0) with points pt 12 lc 4 title 'lpss-sim p99', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==1?$8:1/0) with linespoints pt 13 lc 4 dt 2 title 'lpss-sim', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==1?$10:1/0) with lines dt 3 lc rgb 'gray' title 'budget 1.5 x lpss-sim + 1 ms'
set ylabel 'MiB'
set title 'Memory: all processes together'
plot 'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==1?$11:1/0) with linespoints pt 7 title '1 worker', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==2?$11:1/0) with linespoints pt 5 title '2 workers', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==4?$11:1/0) with linespoints pt 9 title '4 workers', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==1?$12:1/0) with linespoints pt 4 dt 2 title 'lpss-sim', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==1?1.5*$12:1/0) with lines dt 3 lc rgb 'gray' title '1.5 x lpss-sim'
set ylabel 'kB per frame'
set title 'Bytes a worker receives (busiest)'
plot 'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==2?$16/1000:1/0) with linespoints pt 5 title '2 workers', \
     'docs/results/cluster-scale/cluster-scale.csv' using 1:($2==4?$16/1000:1/0) with linespoints pt 9 title '4 workers'
unset multiplot
