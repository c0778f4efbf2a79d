set datafile separator ','
set terminal pngcairo size 1400,900 font 'Sans,11'
set output 'docs/results/overhead/overhead.png'
set multiplot layout 1,3 title 'Cost of sectorization and cloning'
set logscale xy
set xrange [600:170000]
set xlabel 'bodies'
set ylabel 'milliseconds per frame'
set key top left
do for [L in '8 32'] {
  set title sprintf('L = %s', L)
  plot 'docs/results/overhead/overhead.csv' every ::1 using ($2 == L+0 ? $3 : 1/0):10 with linespoints pt 7 title 'step', \
       'docs/results/overhead/overhead.csv' every ::1 using ($2 == L+0 ? $3 : 1/0):8 with linespoints pt 5 title 'sectorize', \
       'docs/results/overhead/overhead.csv' every ::1 using ($2 == L+0 ? $3 : 1/0):9 with linespoints pt 9 title 'clone'
}
set title '(sectorize + clone) / (sectorize + clone + step)'
unset logscale y
set yrange [0:*]
set ylabel 'fraction of the frame'
plot 'docs/results/overhead/overhead.csv' every ::1 using ($2 == 8 ? $3 : 1/0):11 with linespoints pt 7 title 'L = 8', \
     'docs/results/overhead/overhead.csv' every ::1 using ($2 == 32 ? $3 : 1/0):11 with linespoints pt 5 title 'L = 32', \
     0.10 with lines dashtype 2 lc 1 title 'target at L = 8', \
     0.05 with lines dashtype 2 lc 2 title 'target at L >= 32'
unset multiplot
