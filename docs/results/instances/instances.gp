set datafile separator ','
set terminal pngcairo size 1400,900 font 'Sans,11'
set output 'docs/results/instances/instances.png'
set multiplot layout 1,3 title '128 boxes over N sectors'
set logscale x 2
set xlabel 'sectors'
set key top left
set xrange [0.7:180]
set title 'time per frame relative to one sector'
set ylabel 'ratio to one sector'
set arrow from graph 0, first 1.15 to graph 1, first 1.15 nohead dashtype 2
plot 'docs/results/instances/instances.csv' every ::1 using (strcol(1) eq 'lpss-float' ? $2 : 1/0):4:7:8 with yerrorlines pt 7 title 'lpss-float', \
     'docs/results/instances/instances.csv' every ::1 using (strcol(1) eq 'naive-bullet' ? $2 : 1/0):4:7:8 with yerrorlines pt 5 title 'naive-bullet', \
     1/0 with lines dashtype 2 lc rgb 'black' title 'target for lpss (1.15)'
unset arrow
set xrange [1.5:180]
set title 'memory per extra sector'
set logscale y
set ylabel 'bytes'
plot 'docs/results/instances/instances.csv' every ::2 using (strcol(1) eq 'lpss-float' && $2 > 1 ? $2 : 1/0):5 with linespoints pt 7 title 'lpss-float', \
     'docs/results/instances/instances.csv' every ::2 using (strcol(1) eq 'naive-bullet' && $2 > 1 ? $2 : 1/0):5 with linespoints pt 5 title 'naive-bullet'
set title 'creation time per extra sector'
set ylabel 'microseconds'
plot 'docs/results/instances/instances.csv' every ::2 using (strcol(1) eq 'lpss-float' && $2 > 1 ? $2 : 1/0):6 with linespoints pt 7 title 'lpss-float', \
     'docs/results/instances/instances.csv' every ::2 using (strcol(1) eq 'naive-bullet' && $2 > 1 ? $2 : 1/0):6 with linespoints pt 5 title 'naive-bullet'
unset multiplot
