set datafile separator ','
set terminal pngcairo size 1400,900 font 'Sans,11'
set output 'docs/results/cluster/cluster.png'
set title 'Frame time: two worker processes against one process'
set logscale xy
set xlabel 'bodies'
set ylabel 'milliseconds per frame'
set key top left
plot 'docs/results/cluster/cluster.csv' every ::1 using 1:5 with linespoints pt 7 title 'lpss-cluster, 2 workers', \
     'docs/results/cluster/cluster.csv' every ::1 using 1:10 with linespoints pt 5 title 'one process (lpss-sim engine)', \
     'docs/results/cluster/cluster.csv' every ::1 using 1:7 with linespoints pt 9 title 'latency p99 (worker to client)'
