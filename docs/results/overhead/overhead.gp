set datafile separator ','
set terminal pngcairo size 1400,900 font 'Sans,11'
set output 'docs/results/overhead/overhead.png'
set multiplot layout 1,2 title 'Cost of sectorization and cloning'
set logscale xy
set xlabel 'bodies'
set ylabel 'milliseconds per frame'
set key top left
do for [L in '8 32'] {
  set title sprintf('L = %s', L)
  plot 'docs/results/overhead/overhead.csv' every ::1 using ($2 == L+0 ? $3 : 1/0):10 with linespoints pt 7 title 'step', \
       'docs/results/overhead/overhead.csv' every ::1 using ($2 == L+0 ? $3 : 1/0):8 with linespoints pt 5 title 'sectorize', \
       'docs/results/overhead/overhead.csv' every ::1 using ($2 == L+0 ? $3 : 1/0):9 with linespoints pt 9 title 'clone'
}
unset multiplot
