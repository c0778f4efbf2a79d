set datafile separator ','
set terminal pngcairo size 1400,900 font 'Sans,11'
set output 'docs/results/scaling/scaling.png'
set title 'Frame time against bodies (dashed: real time at 60 Hz)'
set logscale xy
set xlabel 'bodies'
set ylabel 'milliseconds per frame'
set key top left
set arrow from graph 0, first 16.667 to graph 1, first 16.667 nohead dt 2 lc rgb 'gray'
s(c,l,t) = (strcol(1) eq c && $2 == l && $3 == t) ? $4 : 1/0
plot 'docs/results/scaling/scaling.csv' every ::1 using (s('bullet-float',0,1)):6 with linespoints pt 7 title 'bullet-float', \
     'docs/results/scaling/scaling.csv' every ::1 using (s('bullet-double',0,1)):6 with linespoints pt 5 title 'bullet-double', \
     'docs/results/scaling/scaling.csv' every ::1 using (s('lpss-float',4096,1)):6 with linespoints pt 9 title 'lpss-float L=4096 (one world)', \
     'docs/results/scaling/scaling.csv' every ::1 using (s('lpss-float',32,1)):6 with linespoints pt 11 title 'lpss-float L=32, 1 thread', \
     'docs/results/scaling/scaling.csv' every ::1 using (s('lpss-float',32,2)):6 with linespoints pt 13 title 'lpss-float L=32, 2 threads', \
     'docs/results/scaling/scaling.csv' every ::1 using (s('lpss-double',32,1)):6 with linespoints pt 4 title 'lpss-double L=32, 1 thread', \
     'docs/results/scaling/scaling.csv' every ::1 using (s('lpss-double',32,2)):6 with linespoints pt 6 title 'lpss-double L=32, 2 threads'
