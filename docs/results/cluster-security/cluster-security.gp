set datafile separator ','
set terminal pngcairo size 1400,900 font 'Sans,11'
set output 'docs/results/cluster-security/cluster-security.png'
set multiplot layout 1,2
set logscale xy
set xrange [700:14000]
set xlabel 'bodies'
set key top left
set title 'Frame time with and without DDS Security (2 workers)'
set ylabel 'milliseconds per frame'
plot 'docs/results/cluster-security/cluster-security.csv' every 4::1 using 1:6 with linespoints pt 7 title 'plain, all moving', \
     'docs/results/cluster-security/cluster-security.csv' every 4::2 using 1:6 with linespoints pt 5 title 'secured, all moving', \
     'docs/results/cluster-security/cluster-security.csv' every 4::3 using 1:6 with linespoints pt 6 title 'plain, 1 in 10 moving', \
     'docs/results/cluster-security/cluster-security.csv' every 4::4 using 1:6 with linespoints pt 4 title 'secured, 1 in 10 moving'
set title 'Worker to reader latency, 99th percentile'
set ylabel 'milliseconds'
plot 'docs/results/cluster-security/cluster-security.csv' every 4::1 using 1:8 with linespoints pt 7 title 'plain, all moving', \
     'docs/results/cluster-security/cluster-security.csv' every 4::2 using 1:8 with linespoints pt 5 title 'secured, all moving', \
     'docs/results/cluster-security/cluster-security.csv' every 4::3 using 1:8 with linespoints pt 6 title 'plain, 1 in 10 moving', \
     'docs/results/cluster-security/cluster-security.csv' every 4::4 using 1:8 with linespoints pt 4 title 'secured, 1 in 10 moving'
unset multiplot
