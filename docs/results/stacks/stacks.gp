set datafile separator ','
set terminal pngcairo size 1400,900 font 'Sans,11'
set output 'docs/results/stacks/stacks.png'
set multiplot layout 7,4 title 'Side view of the 10-box stacks after 10 s (columns: distance from the origin)'
set datafile separator whitespace
set size ratio -1
unset key
set xrange [-6:6]
set yrange [-1:11]
set xtics 5 font ',7'
set ytics 5 font ',7'
set title 'bullet-float at 0' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 0 with lines lw 1.5
set title 'bullet-float at 1.67772e+07' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 1 with lines lw 1.5
set title 'bullet-float at 1.09951e+12' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 2 with lines lw 1.5
set title 'bullet-float at 1e+15' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 3 with lines lw 1.5
set title 'bullet-double at 0' font ',8'
plot 'docs/results/stacks/stacks_view_double.dat' index 0 with lines lw 1.5
set title 'bullet-double at 1.67772e+07' font ',8'
plot 'docs/results/stacks/stacks_view_double.dat' index 1 with lines lw 1.5
set title 'bullet-double at 1.09951e+12' font ',8'
plot 'docs/results/stacks/stacks_view_double.dat' index 2 with lines lw 1.5
set title 'bullet-double at 1e+15' font ',8'
plot 'docs/results/stacks/stacks_view_double.dat' index 3 with lines lw 1.5
set title 'lpss-float L=64 at 0' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 4 with lines lw 1.5
set title 'lpss-float L=64 at 1.67772e+07' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 5 with lines lw 1.5
set title 'lpss-float L=64 at 1.09951e+12' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 6 with lines lw 1.5
set title 'lpss-float L=64 at 1e+15' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 7 with lines lw 1.5
set title 'lpss-float L=128 at 0' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 8 with lines lw 1.5
set title 'lpss-float L=128 at 1.67772e+07' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 9 with lines lw 1.5
set title 'lpss-float L=128 at 1.09951e+12' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 10 with lines lw 1.5
set title 'lpss-float L=128 at 1e+15' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 11 with lines lw 1.5
set title 'lpss-float L=1024 at 0' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 12 with lines lw 1.5
set title 'lpss-float L=1024 at 1.67772e+07' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 13 with lines lw 1.5
set title 'lpss-float L=1024 at 1.09951e+12' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 14 with lines lw 1.5
set title 'lpss-float L=1024 at 1e+15' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 15 with lines lw 1.5
set title 'lpss-float L=4096 at 0' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 16 with lines lw 1.5
set title 'lpss-float L=4096 at 1.67772e+07' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 17 with lines lw 1.5
set title 'lpss-float L=4096 at 1.09951e+12' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 18 with lines lw 1.5
set title 'lpss-float L=4096 at 1e+15' font ',8'
plot 'docs/results/stacks/stacks_view_float.dat' index 19 with lines lw 1.5
set title 'lpss-double L=1024 at 0' font ',8'
plot 'docs/results/stacks/stacks_view_double.dat' index 4 with lines lw 1.5
set title 'lpss-double L=1024 at 1.67772e+07' font ',8'
plot 'docs/results/stacks/stacks_view_double.dat' index 5 with lines lw 1.5
set title 'lpss-double L=1024 at 1.09951e+12' font ',8'
plot 'docs/results/stacks/stacks_view_double.dat' index 6 with lines lw 1.5
set title 'lpss-double L=1024 at 1e+15' font ',8'
plot 'docs/results/stacks/stacks_view_double.dat' index 7 with lines lw 1.5
unset multiplot
