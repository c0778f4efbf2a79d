set datafile separator ','
set terminal pngcairo size 1400,900 font 'Sans,11'
set output 'docs/results/overhead/overhead.png'
set multiplot layout 1,3 title 'Cost of sectorization and cloning (solid: frames 61-120, dashed: frames 6-35)'
set logscale xy
set format y '%g'
set xrange [600:170000]
set xlabel 'bodies'
set ylabel 'milliseconds per frame'
set key top left
do for [L in '8 32'] {
  set title sprintf('L = %s', L)
  plot 'docs/results/overhead/overhead.csv' every ::1 using ($2 == L+0 && strcol(4) eq '61-120' ? $3 : 1/0):11 with linespoints lc 1 pt 7 title 'step', \
       'docs/results/overhead/overhead.csv' every ::1 using ($2 == L+0 && strcol(4) eq '61-120' ? $3 : 1/0):9 with linespoints lc 2 pt 5 title 'sectorize', \
       'docs/results/overhead/overhead.csv' every ::1 using ($2 == L+0 && strcol(4) eq '61-120' ? $3 : 1/0):10 with linespoints lc 3 pt 9 title 'clone', \
       'docs/results/overhead/overhead.csv' every ::1 using ($2 == L+0 && strcol(4) eq '6-35' ? $3 : 1/0):11 with linespoints lc 1 pt 6 dt 2 notitle, \
       'docs/results/overhead/overhead.csv' every ::1 using ($2 == L+0 && strcol(4) eq '6-35' ? $3 : 1/0):9 with linespoints lc 2 pt 4 dt 2 notitle, \
       'docs/results/overhead/overhead.csv' every ::1 using ($2 == L+0 && strcol(4) eq '6-35' ? $3 : 1/0):10 with linespoints lc 3 pt 8 dt 2 notitle
}
set title '(sectorize + clone) / (sectorize + clone + step)'
unset logscale y
set yrange [0:0.35]
set key top left
set ylabel 'fraction of the frame'
plot 'docs/results/overhead/overhead.csv' every ::1 using ($2 == 8 && strcol(4) eq '61-120' ? $3 : 1/0):12 with linespoints lc 1 pt 7 title 'L = 8', \
     'docs/results/overhead/overhead.csv' every ::1 using ($2 == 32 && strcol(4) eq '61-120' ? $3 : 1/0):12 with linespoints lc 2 pt 5 title 'L = 32', \
     'docs/results/overhead/overhead.csv' every ::1 using ($2 == 8 && strcol(4) eq '6-35' ? $3 : 1/0):12 with linespoints lc 1 pt 6 dt 2 title 'L = 8, frames 6-35', \
     'docs/results/overhead/overhead.csv' every ::1 using ($2 == 32 && strcol(4) eq '6-35' ? $3 : 1/0):12 with linespoints lc 2 pt 4 dt 2 title 'L = 32, frames 6-35', \
     0.10 with lines dashtype 3 lc 1 title 'target at L = 8', \
     0.05 with lines dashtype 3 lc 2 title 'target at L >= 32'
unset multiplot
