set datafile separator ','
set terminal pngcairo size 1400,900 font 'Sans,11'
set output 'docs/results/late-join/late-join.png'
set title 'Clients joining a running cluster, one after another (2 workers, 2,000 bodies drifting apart)'
set xlabel 'join, in order (the world runs on between joins; odd joins without the discovery prompt)'
set ylabel 'seconds (log)'
set y2label 'world frames per second while it joined'
set logscale y
set yrange [0.005:100]
set y2range [0:80]
set y2tics
set ytics nomirror
set xrange [0.5:30.5]
set key top left
plot 'docs/results/late-join/late-join.csv' using 1:(strcol(4) eq 'never' || strcol(2) eq 'no' ? NaN : $4) with points pt 7 ps 1.5 lc rgb 'dark-green' title 'first frame, with the discovery prompt', \
     'docs/results/late-join/late-join.csv' using 1:(strcol(4) eq 'never' || strcol(2) eq 'yes' ? NaN : $4) with points pt 6 ps 1.5 lc rgb 'dark-orange' title 'first frame, without', \
     'docs/results/late-join/late-join.csv' using 1:(strcol(3) eq 'never' || strcol(2) eq 'no' ? NaN : $3) with points pt 5 lc rgb 'dark-green' title 'matched, with the discovery prompt', \
     'docs/results/late-join/late-join.csv' using 1:(strcol(3) eq 'never' || strcol(2) eq 'yes' ? NaN : $3) with points pt 4 lc rgb 'dark-orange' title 'matched, without', \
     'docs/results/late-join/late-join.csv' using 1:(strcol(4) eq 'never' ? 30 : NaN) with points pt 2 ps 2.5 lw 2 lc rgb 'red' title 'no first frame within 30 s (drawn at 30)', \
     'docs/results/late-join/late-join.csv' using 1:(strcol(3) eq 'never' ? 60 : NaN) with points pt 3 ps 2.5 lw 2 lc rgb 'red' title 'never matched (drawn at 60)', \
     'docs/results/late-join/late-join.csv' using 1:6 axes x1y2 with linespoints dt 3 lc rgb 'gray40' title 'world frames/s (right axis)', \
     0.5 with lines dt 2 lc rgb 'blue' title 'target: matched within 0.5 s'
