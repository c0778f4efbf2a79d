set datafile separator ','
set terminal pngcairo size 1400,900 font 'Sans,11'
set output 'docs/results/cluster/cluster.png'
set title 'Frame time: two worker processes against one process'
set logscale xy
set xlabel 'bodies'
set ylabel 'milliseconds per frame'
set key top left
plot 'docs/results/cluster/cluster.csv' every 2::1 using 1:6 with linespoints pt 7 title 'lpss-cluster, 2 workers, all moving', \
     'docs/results/cluster/cluster.csv' every 2::1 using 1:11 with linespoints pt 5 title 'one process (lpss-sim engine), all moving', \
     'docs/results/cluster/cluster.csv' every 2::2 using 1:6 with linespoints pt 6 title 'lpss-cluster, 2 workers, 1 in 10 moving', \
     'docs/results/cluster/cluster.csv' every 2::1 using 1:8 with linespoints pt 9 title 'latency p99 (worker to client), all moving'
