set datafile separator ','
set terminal pngcairo size 1400,900 font 'Sans,11'
set output 'docs/results/pareto/pareto.png'
reset
set terminal pngcairo size 2300,1500 font 'Sans,10'
set output 'docs/results/pareto/pareto.png'
set datafile separator whitespace
set termoption noenhanced
set logscale xy
set format y '1e%L'
set format x '%g'
set grid xtics ytics mxtics mytics lc rgb '#e8e8e8'
unset key
set lmargin 8
set rmargin 2
set tmargin 2
set bmargin 4.5
set multiplot
set label 999 "Error against cost. Error: distance of every body from plain double Bullet's run of the scene at the origin (the reference for all)" at screen 0.5, screen 0.985 center font ',14'
set origin 0,0.6666666666666666
set size 0.25,0.29333333333333333
set title 'two_spheres at 1000.7'
set xrange [0.000666667:15]
set yrange [3.33333e-18:1e+07]
set ytics auto
set ytics add ('0' 1e-17)
set arrow 1 from graph 0, first 3.16228e-17 to graph 1, first 3.16228e-17 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 9.1e-14..5.3e-12 @ 1.9us; cluster 1.4e-7 @ 1..2.1ms; float 0.0014; double 5.3e-12" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P00 << EOD
0.0013 5.28466e-12 1 0
0.001392 2.14939e-13 7 0
0.00118 0.00142415 0 0
0.001858 9.05942e-14 2 0
0.001302 2.14939e-13 3 0
0.001302 2.14939e-13 4 0
0.001321 2.14939e-13 5 0
0.001673 5.28466e-12 6 0
1.005 1.43051e-07 8 0
1.408 1.43051e-07 9 0
2.074 1.43051e-07 10 0
EOD
plot $P00 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P00 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P00 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P00 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P00 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P00 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P00 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P00 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P00 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P00 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P00 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0.25,0.6666666666666666
set size 0.25,0.29333333333333333
set title 'two_spheres at 1000003.1'
set xrange [0.000666667:15]
set yrange [3.33333e-18:1e+07]
set ytics auto
set ytics add ('0' 1e-17)
set arrow 1 from graph 0, first 3.16228e-17 to graph 1, first 3.16228e-17 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 9.8e-11 @ 1.4us; cluster 3.1e-7 @ 0.85..1.8ms; float 10; double 1.2e-9" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P01 << EOD
0.001317 1.24174e-09 1 0
0.001603 9.77156e-11 7 0
0.001185 10.4792 0 0
0.001336 9.3145e-11 2 0
0.001295 9.3145e-11 3 0
0.001344 9.28271e-11 4 0
0.001324 9.77156e-11 5 0
0.001373 8.79385e-11 6 0
0.8476 3.09898e-07 8 0
1.632 3.09898e-07 9 0
1.761 3.09898e-07 10 0
EOD
plot $P01 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P01 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P01 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P01 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P01 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P01 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P01 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P01 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P01 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P01 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P01 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0.5,0.6666666666666666
set size 0.25,0.29333333333333333
set title 'two_spheres at 1000000011.9'
set xrange [0.000666667:15]
set yrange [3.33333e-18:1e+07]
set ytics auto
set ytics add ('0' 1e-17)
set arrow 1 from graph 0, first 3.16228e-17 to graph 1, first 3.16228e-17 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 9.5e-8 @ 1.4us; cluster 3.2e-7 @ 2ms; float 24 missed; double 5.6e-6" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P02 << EOD
0.001308 5.5631e-06 1 0
0.001613 9.53628e-08 7 0
0.001423 23.8 0 1
0.001325 9.53674e-08 2 0
0.001307 9.53674e-08 3 0
0.001296 9.53674e-08 4 0
0.001342 9.53628e-08 5 0
0.001388 9.53726e-08 6 0
1.464 3.17891e-07 8 0
1.402 3.17891e-07 9 0
2.044 3.17891e-07 10 0
EOD
plot $P02 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P02 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P02 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P02 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P02 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P02 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P02 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P02 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P02 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P02 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P02 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5, $P02 using 1:($4 == 1 ? $2 : 1/0) with points lc rgb 'black' pt 2 ps 3.2 lw 2
unset arrow 1
unset label 999
set origin 0.75,0.6666666666666666
set size 0.25,0.29333333333333333
set title 'two_spheres at 10000000000037.3'
set xrange [0.000666667:15]
set yrange [3.33333e-18:1e+07]
set ytics auto
set ytics add ('0' 1e-17)
set arrow 1 from graph 0, first 3.16228e-17 to graph 1, first 3.16228e-17 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 9.8e-15..3.1e-13 @ 1.4us; cluster 1.7e-7 @ 0.96..1.8ms; float 3.4e5 missed; double 0.021" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P03 << EOD
0.001298 0.0208333 1 0
0.001399 3.10862e-13 7 0
0.001922 344139 0 1
0.001442 9.76996e-15 2 0
0.001297 3.0731e-13 3 0
0.001344 3.10862e-13 4 0
0.001331 3.10862e-13 5 0
0.001374 3.10862e-13 6 0
0.9578 1.6888e-07 8 0
1.475 1.6888e-07 9 0
1.828 1.6888e-07 10 0
EOD
plot $P03 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P03 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P03 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P03 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P03 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P03 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P03 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P03 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P03 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P03 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P03 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5, $P03 using 1:($4 == 1 ? $2 : 1/0) with points lc rgb 'black' pt 2 ps 3.2 lw 2
unset arrow 1
unset label 999
set origin 0,0.3733333333333333
set size 0.25,0.29333333333333333
set title 'box_stack_10 at 1000.7'
set xrange [0.000666667:15]
set yrange [3.33333e-06:1e+06]
set ytics auto
set ytics add ('0' 1e-05)
set arrow 1 from graph 0, first 3.16228e-05 to graph 1, first 3.16228e-05 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 0.0071..5.7 @ 4.8..18us; cluster 5.7 @ 1.2..1.9ms; float 0.035; double 0.0061" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P10 << EOD
0.005009 0.00609844 1 0
0.005098 0.00978086 7 0
0.004695 0.0349109 0 0
0.01758 5.65103 2 0
0.004808 0.00775183 3 0
0.004757 0.0100809 4 0
0.004989 0.00848661 5 0
0.004938 0.00708358 6 0
1.167 5.65103 8 0
1.604 5.65103 9 0
1.945 5.65103 10 0
EOD
plot $P10 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P10 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P10 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P10 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P10 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P10 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P10 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P10 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P10 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P10 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P10 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0.25,0.3733333333333333
set size 0.25,0.29333333333333333
set title 'box_stack_10 at 1000003.1'
set xrange [0.000666667:15]
set yrange [3.33333e-06:1e+06]
set ytics auto
set ytics add ('0' 1e-05)
set arrow 1 from graph 0, first 3.16228e-05 to graph 1, first 3.16228e-05 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 0.0081..5.7 @ 4.8..17us; cluster 5.7 @ 0.88..1.8ms; float 0.027; double 0.0067" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P11 << EOD
0.005949 0.00672035 1 0
0.005121 0.0075081 7 0
0.004711 0.0271752 0 0
0.01667 5.67307 2 0
0.004837 0.0148523 3 0
0.004757 0.0093081 4 0
0.005079 0.00812301 5 0
0.004998 0.00819968 6 0
0.8799 5.67307 8 0
1.332 5.67307 9 0
1.849 5.67307 10 0
EOD
plot $P11 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P11 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P11 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P11 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P11 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P11 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P11 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P11 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P11 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P11 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P11 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0.5,0.3733333333333333
set size 0.25,0.29333333333333333
set title 'box_stack_10 at 1000000011.9'
set xrange [0.000666667:15]
set yrange [3.33333e-06:1e+06]
set ytics auto
set ytics add ('0' 1e-05)
set arrow 1 from graph 0, first 3.16228e-05 to graph 1, first 3.16228e-05 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 0.0096..5.6 @ 4.8..17us; cluster 5.6 @ 0.82..1.7ms; float 11; double 0.0098" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P12 << EOD
0.005062 0.00975512 1 0
0.005289 0.00659778 7 0
0.003121 10.8457 0 0
0.01725 5.59871 2 0
0.004866 0.0179889 3 0
0.004815 0.0113885 4 0
0.005106 0.00962304 5 0
0.005079 0.0165777 6 0
0.8167 5.59871 8 0
1.402 5.59871 9 0
1.695 5.59871 10 0
EOD
plot $P12 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P12 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P12 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P12 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P12 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P12 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P12 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P12 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P12 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P12 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P12 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0.75,0.3733333333333333
set size 0.25,0.29333333333333333
set title 'box_stack_10 at 10000000000037.3'
set xrange [0.000666667:15]
set yrange [3.33333e-06:1e+06]
set ytics auto
set ytics add ('0' 1e-05)
set arrow 1 from graph 0, first 3.16228e-05 to graph 1, first 3.16228e-05 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 0.0087..6.1 @ 4.8..17us; cluster 6.1 @ 0.87..2.3ms; float 1.6e5; double 0.029" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P13 << EOD
0.00503 0.0294707 1 0
0.005199 0.00803906 7 0
0.003095 156427 0 0
0.01657 6.1481 2 0
0.004799 0.00902191 3 0
0.004817 0.0108902 4 0
0.005156 0.00869629 5 0
0.005033 0.00907991 6 0
0.8727 6.1481 8 0
1.402 6.1481 9 0
2.34 6.1481 10 0
EOD
plot $P13 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P13 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P13 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P13 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P13 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P13 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P13 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P13 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P13 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P13 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P13 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0,0.07999999999999996
set size 0.25,0.29333333333333333
set title 'mixed_pile_2000 at 1000.7'
set xrange [0.666667:150]
set yrange [3.33333e-06:1e+06]
set ytics auto
set ytics add ('0' 1e-05)
set arrow 1 from graph 0, first 3.16228e-05 to graph 1, first 3.16228e-05 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 0.0023 @ 3ms; cluster 0.0023 @ 10ms; float 0.0021; double 0.0019" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P20 << EOD
2.888 0.00190496 1 0
2.526 0.00190478 7 0
2.254 0.00209672 0 0
3.043 0.00228297 2 0
2.29 0.00229982 3 0
2.194 0.00207919 4 0
2.195 0.0020097 5 0
2.062 0.00201175 6 0
8.138 0.00228305 8 0
8.742 0.00228305 9 0
10.32 0.00228305 10 0
EOD
plot $P20 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P20 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P20 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P20 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P20 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P20 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P20 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P20 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P20 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P20 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P20 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0.25,0.07999999999999996
set size 0.25,0.29333333333333333
set title 'mixed_pile_2000 at 1000003.1'
set xrange [0.666667:150]
set yrange [3.33333e-06:1e+06]
set ytics auto
set ytics add ('0' 1e-05)
set arrow 1 from graph 0, first 3.16228e-05 to graph 1, first 3.16228e-05 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 0.0024 @ 2.8ms; cluster 0.0024 @ 9.9ms; float 0.024; double 0.0019" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P21 << EOD
2.304 0.00190496 1 0
2.36 0.00190478 7 0
2.072 0.0239432 0 0
2.838 0.00236105 2 0
2.314 0.00202192 3 0
2.286 0.00202407 4 0
2.108 0.00207312 5 0
1.933 0.00207312 6 0
9.027 0.00236113 8 0
9.163 0.00236113 9 0
9.918 0.00236113 10 0
EOD
plot $P21 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P21 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P21 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P21 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P21 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P21 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P21 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P21 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P21 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P21 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P21 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0.5,0.07999999999999996
set size 0.25,0.29333333333333333
set title 'mixed_pile_2000 at 1000000011.9'
set xrange [0.666667:150]
set yrange [3.33333e-06:1e+06]
set ytics auto
set ytics add ('0' 1e-05)
set arrow 1 from graph 0, first 3.16228e-05 to graph 1, first 3.16228e-05 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 0.0024 @ 2.7ms; cluster 0.0024 @ 10ms; float 12; double 0.0019" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P22 << EOD
2.312 0.00190496 1 0
2.411 0.00190376 7 0
47.64 12.4764 0 0
2.666 0.00243992 2 0
2.184 0.00212481 3 0
2.285 0.00208899 4 0
2.183 0.00196421 5 0
1.957 0.00196421 6 0
9.542 0.00243999 8 0
9.293 0.00243999 9 0
10.2 0.00243999 10 0
EOD
plot $P22 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P22 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P22 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P22 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P22 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P22 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P22 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P22 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P22 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P22 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P22 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0.75,0.07999999999999996
set size 0.25,0.29333333333333333
set title 'mixed_pile_2000 at 10000000000037.3'
set xrange [0.666667:150]
set yrange [3.33333e-06:1e+06]
set ytics auto
set ytics add ('0' 1e-05)
set arrow 1 from graph 0, first 3.16228e-05 to graph 1, first 3.16228e-05 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 0.0019..0.003 @ 2.7ms; cluster 0.003 @ 12ms; float 1.7e5; double 0.0039" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P23 << EOD
2.282 0.00386502 1 0
2.404 0.00190355 7 0
46.76 171983 0 0
2.7 0.0029647 2 0
2.407 0.00216972 3 0
2.038 0.00186848 4 0
2.103 0.00196309 5 0
2 0.00201472 6 0
8.829 0.00296477 8 0
12.33 0.00296477 9 0
12.48 0.00296477 10 0
EOD
plot $P23 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P23 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P23 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P23 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P23 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P23 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P23 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P23 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P23 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P23 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P23 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0,0
set size 1,0.08
unset title
unset logscale
unset border
unset tics
unset grid
unset xlabel
unset ylabel
set xrange [0:1]
set yrange [0:1]
set lmargin 0
set rmargin 0
set tmargin 0
set bmargin 0
set key at graph 0.03, graph 0.95 left top Left reverse horizontal maxrows 3 width 3 spacing 1.5 font ',11'
plot NaN with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5 title 'plain float Bullet', NaN with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5 title 'plain double Bullet', NaN with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5 title 'lpss float L=16', NaN with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5 title 'lpss float L=64', NaN with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5 title 'lpss float L=128', NaN with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5 title 'lpss float L=1024', NaN with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5 title 'lpss float L=4096', NaN with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5 title 'lpss double L=1024', NaN with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5 title 'lpss-cluster L=16, 1 worker', NaN with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5 title 'lpss-cluster L=16, 2 workers', NaN with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5 title 'lpss-cluster L=16, 3 workers', NaN with points lc rgb 'black' pt 2 ps 3.2 lw 2 title 'x: the spheres did not collide', NaN with lines dt 3 lc rgb '#999999' title '0: error exactly 0 (below the line)'
unset multiplot
reset
set terminal pngcairo size 2300,1500 font 'Sans,10'
set output 'docs/results/pareto/pareto_own_origin.png'
set datafile separator whitespace
set termoption noenhanced
set logscale xy
set format y '1e%L'
set format x '%g'
set grid xtics ytics mxtics mytics lc rgb '#e8e8e8'
unset key
set lmargin 8
set rmargin 2
set tmargin 2
set bmargin 4.5
set multiplot
set label 999 "Error against cost. Error: distance of every body from the same configuration's own run of the scene at the origin (what distance alone does)" at screen 0.5, screen 0.985 center font ',14'
set origin 0,0.6666666666666666
set size 0.25,0.29333333333333333
set title 'two_spheres at 1000.7'
set xrange [0.000666667:15]
set yrange [3.33333e-18:1e+07]
set ytics auto
set ytics add ('0' 1e-17)
set arrow 1 from graph 0, first 3.16228e-17 to graph 1, first 3.16228e-17 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 9.1e-14..5.3e-12 @ 1.9us; cluster 2.4e-7 @ 1..2.1ms; float 0.0014; double 5.3e-12" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P00 << EOD
0.0013 5.28466e-12 1 0
0.001392 2.14939e-13 7 0
0.00118 0.00141907 0 0
0.001858 9.05942e-14 2 0
0.001302 2.14939e-13 3 0
0.001302 2.14939e-13 4 0
0.001321 2.14939e-13 5 0
0.001673 5.28466e-12 6 0
1.005 2.38419e-07 8 0
1.408 2.38419e-07 9 0
2.074 2.38419e-07 10 0
EOD
plot $P00 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P00 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P00 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P00 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P00 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P00 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P00 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P00 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P00 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P00 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P00 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0.25,0.6666666666666666
set size 0.25,0.29333333333333333
set title 'two_spheres at 1000003.1'
set xrange [0.000666667:15]
set yrange [3.33333e-18:1e+07]
set ytics auto
set ytics add ('0' 1e-17)
set arrow 1 from graph 0, first 3.16228e-17 to graph 1, first 3.16228e-17 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 9.8e-11 @ 1.4us; cluster 3.1e-7 @ 0.85..1.8ms; float 10; double 1.2e-9" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P01 << EOD
0.001317 1.24174e-09 1 0
0.001603 9.77156e-11 7 0
0.001185 10.4792 0 0
0.001336 9.3145e-11 2 0
0.001295 9.3145e-11 3 0
0.001344 9.28271e-11 4 0
0.001324 9.77156e-11 5 0
0.001373 8.79385e-11 6 0
0.8476 3.09898e-07 8 0
1.632 3.09898e-07 9 0
1.761 3.09898e-07 10 0
EOD
plot $P01 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P01 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P01 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P01 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P01 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P01 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P01 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P01 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P01 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P01 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P01 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0.5,0.6666666666666666
set size 0.25,0.29333333333333333
set title 'two_spheres at 1000000011.9'
set xrange [0.000666667:15]
set yrange [3.33333e-18:1e+07]
set ytics auto
set ytics add ('0' 1e-17)
set arrow 1 from graph 0, first 3.16228e-17 to graph 1, first 3.16228e-17 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 9.5e-8 @ 1.4us; cluster 2.4e-7 @ 2ms; float 24 missed; double 5.6e-6" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P02 << EOD
0.001308 5.5631e-06 1 0
0.001613 9.53628e-08 7 0
0.001423 23.8 0 1
0.001325 9.53674e-08 2 0
0.001307 9.53674e-08 3 0
0.001296 9.53674e-08 4 0
0.001342 9.53628e-08 5 0
0.001388 9.53726e-08 6 0
1.464 2.38419e-07 8 0
1.402 2.38419e-07 9 0
2.044 2.38419e-07 10 0
EOD
plot $P02 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P02 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P02 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P02 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P02 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P02 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P02 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P02 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P02 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P02 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P02 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5, $P02 using 1:($4 == 1 ? $2 : 1/0) with points lc rgb 'black' pt 2 ps 3.2 lw 2
unset arrow 1
unset label 999
set origin 0.75,0.6666666666666666
set size 0.25,0.29333333333333333
set title 'two_spheres at 10000000000037.3'
set xrange [0.000666667:15]
set yrange [3.33333e-18:1e+07]
set ytics auto
set ytics add ('0' 1e-17)
set arrow 1 from graph 0, first 3.16228e-17 to graph 1, first 3.16228e-17 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 9.8e-15..3.1e-13 @ 1.4us; cluster 1.5e-7 @ 0.96..1.8ms; float 3.4e5 missed; double 0.021" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P03 << EOD
0.001298 0.0208333 1 0
0.001399 3.10862e-13 7 0
0.001922 344139 0 1
0.001442 9.76996e-15 2 0
0.001297 3.0731e-13 3 0
0.001344 3.10862e-13 4 0
0.001331 3.10862e-13 5 0
0.001374 3.10862e-13 6 0
0.9578 1.49012e-07 8 0
1.475 1.49012e-07 9 0
1.828 1.49012e-07 10 0
EOD
plot $P03 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P03 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P03 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P03 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P03 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P03 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P03 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P03 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P03 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P03 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P03 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5, $P03 using 1:($4 == 1 ? $2 : 1/0) with points lc rgb 'black' pt 2 ps 3.2 lw 2
unset arrow 1
unset label 999
set origin 0,0.3733333333333333
set size 0.25,0.29333333333333333
set title 'box_stack_10 at 1000.7'
set xrange [0.000666667:15]
set yrange [3.33333e-06:1e+06]
set ytics auto
set ytics add ('0' 1e-05)
set arrow 1 from graph 0, first 3.16228e-05 to graph 1, first 3.16228e-05 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 0.0081..0.72 @ 4.8..18us; cluster 0.72 @ 1.2..1.9ms; float 0.029; double 0.0061" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P10 << EOD
0.005009 0.00609844 1 0
0.005098 0.00978086 7 0
0.004695 0.0286818 0 0
0.01758 0.722809 2 0
0.004808 0.00805913 3 0
0.004757 0.0101774 4 0
0.004989 0.00812129 5 0
0.004938 0.00923936 6 0
1.167 0.722809 8 0
1.604 0.722809 9 0
1.945 0.722809 10 0
EOD
plot $P10 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P10 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P10 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P10 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P10 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P10 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P10 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P10 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P10 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P10 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P10 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0.25,0.3733333333333333
set size 0.25,0.29333333333333333
set title 'box_stack_10 at 1000003.1'
set xrange [0.000666667:15]
set yrange [3.33333e-06:1e+06]
set ytics auto
set ytics add ('0' 1e-05)
set arrow 1 from graph 0, first 3.16228e-05 to graph 1, first 3.16228e-05 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 0.0097..0.82 @ 4.8..17us; cluster 0.82 @ 0.88..1.8ms; float 0.021; double 0.0067" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P11 << EOD
0.005949 0.00672035 1 0
0.005121 0.0075081 7 0
0.004711 0.0212879 0 0
0.01667 0.818118 2 0
0.004837 0.0116925 3 0
0.004757 0.0112097 4 0
0.005079 0.00990322 5 0
0.004998 0.00966389 6 0
0.8799 0.818118 8 0
1.332 0.818118 9 0
1.849 0.818118 10 0
EOD
plot $P11 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P11 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P11 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P11 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P11 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P11 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P11 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P11 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P11 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P11 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P11 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0.5,0.3733333333333333
set size 0.25,0.29333333333333333
set title 'box_stack_10 at 1000000011.9'
set xrange [0.000666667:15]
set yrange [3.33333e-06:1e+06]
set ytics auto
set ytics add ('0' 1e-05)
set arrow 1 from graph 0, first 3.16228e-05 to graph 1, first 3.16228e-05 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 0.0087..1.5 @ 4.8..17us; cluster 1.5 @ 0.82..1.7ms; float 11; double 0.0098" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P12 << EOD
0.005062 0.00975512 1 0
0.005289 0.00659778 7 0
0.003121 10.8406 0 0
0.01725 1.54509 2 0
0.004866 0.0146719 3 0
0.004815 0.00867091 4 0
0.005106 0.00874301 5 0
0.005079 0.0105635 6 0
0.8167 1.54509 8 0
1.402 1.54509 9 0
1.695 1.54509 10 0
EOD
plot $P12 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P12 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P12 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P12 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P12 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P12 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P12 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P12 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P12 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P12 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P12 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0.75,0.3733333333333333
set size 0.25,0.29333333333333333
set title 'box_stack_10 at 10000000000037.3'
set xrange [0.000666667:15]
set yrange [3.33333e-06:1e+06]
set ytics auto
set ytics add ('0' 1e-05)
set arrow 1 from graph 0, first 3.16228e-05 to graph 1, first 3.16228e-05 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 0.0074..2 @ 4.8..17us; cluster 2 @ 0.87..2.3ms; float 1.6e5; double 0.029" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P13 << EOD
0.00503 0.0294707 1 0
0.005199 0.00803906 7 0
0.003095 156427 0 0
0.01657 1.97242 2 0
0.004799 0.00924306 3 0
0.004817 0.012774 4 0
0.005156 0.00747887 5 0
0.005033 0.00736298 6 0
0.8727 1.97242 8 0
1.402 1.97242 9 0
2.34 1.97242 10 0
EOD
plot $P13 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P13 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P13 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P13 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P13 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P13 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P13 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P13 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P13 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P13 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P13 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0,0.07999999999999996
set size 0.25,0.29333333333333333
set title 'mixed_pile_2000 at 1000.7'
set xrange [0.666667:150]
set yrange [3.33333e-07:1e+06]
set ytics auto
set ytics add ('0' 1e-06)
set arrow 1 from graph 0, first 3.16228e-06 to graph 1, first 3.16228e-06 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 0.0005..0.003 @ 3ms; cluster 0.003 @ 10ms; float 0.00018; double 0.0019" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P20 << EOD
2.888 0.00190496 1 0
2.526 0.00190478 7 0
2.254 0.000183557 0 0
3.043 0.00300364 2 0
2.29 0.00237806 3 0
2.194 0.00230715 4 0
2.195 0.000501729 5 0
2.062 0.000502926 6 0
8.138 0.00300374 8 0
8.742 0.00300374 9 0
10.32 0.00300374 10 0
EOD
plot $P20 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P20 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P20 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P20 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P20 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P20 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P20 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P20 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P20 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P20 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P20 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0.25,0.07999999999999996
set size 0.25,0.29333333333333333
set title 'mixed_pile_2000 at 1000003.1'
set xrange [0.666667:150]
set yrange [3.33333e-07:1e+06]
set ytics auto
set ytics add ('0' 1e-06)
set arrow 1 from graph 0, first 3.16228e-06 to graph 1, first 3.16228e-06 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 0.00061..0.0026 @ 2.8ms; cluster 0.0026 @ 9.9ms; float 0.024; double 0.0019" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P21 << EOD
2.304 0.00190496 1 0
2.36 0.00190478 7 0
2.072 0.0240261 0 0
2.838 0.00264896 2 0
2.314 0.00243894 3 0
2.286 0.00248173 4 0
2.108 0.000612406 5 0
1.933 0.000612406 6 0
9.027 0.00264904 8 0
9.163 0.00264904 9 0
9.918 0.00264904 10 0
EOD
plot $P21 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P21 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P21 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P21 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P21 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P21 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P21 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P21 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P21 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P21 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P21 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0.5,0.07999999999999996
set size 0.25,0.29333333333333333
set title 'mixed_pile_2000 at 1000000011.9'
set xrange [0.666667:150]
set yrange [3.33333e-07:1e+06]
set ytics auto
set ytics add ('0' 1e-06)
set arrow 1 from graph 0, first 3.16228e-06 to graph 1, first 3.16228e-06 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 0.00055..0.0025 @ 2.7ms; cluster 0.0025 @ 10ms; float 12; double 0.0019" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P22 << EOD
2.312 0.00190496 1 0
2.411 0.00190376 7 0
47.64 12.4764 0 0
2.666 0.00253995 2 0
2.184 0.00250475 3 0
2.285 0.00252139 4 0
2.183 0.000548808 5 0
1.957 0.000548808 6 0
9.542 0.00254003 8 0
9.293 0.00254003 9 0
10.2 0.00254003 10 0
EOD
plot $P22 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P22 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P22 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P22 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P22 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P22 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P22 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P22 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P22 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P22 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P22 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0.75,0.07999999999999996
set size 0.25,0.29333333333333333
set title 'mixed_pile_2000 at 10000000000037.3'
set xrange [0.666667:150]
set yrange [3.33333e-07:1e+06]
set ytics auto
set ytics add ('0' 1e-06)
set arrow 1 from graph 0, first 3.16228e-06 to graph 1, first 3.16228e-06 nohead dt 3 lc rgb '#999999'
set xlabel "ms per frame\nlpss 0.0005..0.0032 @ 2.7ms; cluster 0.0032 @ 12ms; float 1.7e5; double 0.0039" offset 0,0.3 font ',8.5'
set ylabel 'error' offset 1.5,0
$P23 << EOD
2.282 0.00386502 1 0
2.404 0.00190355 7 0
46.76 171983 0 0
2.7 0.0032169 2 0
2.407 0.00260268 3 0
2.038 0.0023219 4 0
2.103 0.000548838 5 0
2 0.00050477 6 0
8.829 0.00321696 8 0
12.33 0.00321696 9 0
12.48 0.00321696 10 0
EOD
plot $P23 using 1:($3 == 0 ? $2 : 1/0) with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5, $P23 using 1:($3 == 1 ? $2 : 1/0) with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5, $P23 using 1:($3 == 2 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5, $P23 using 1:($3 == 3 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5, $P23 using 1:($3 == 4 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5, $P23 using 1:($3 == 5 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5, $P23 using 1:($3 == 6 ? $2 : 1/0) with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5, $P23 using 1:($3 == 7 ? $2 : 1/0) with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5, $P23 using 1:($3 == 8 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5, $P23 using 1:($3 == 9 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5, $P23 using 1:($3 == 10 ? $2 : 1/0) with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5
unset arrow 1
unset label 999
set origin 0,0
set size 1,0.08
unset title
unset logscale
unset border
unset tics
unset grid
unset xlabel
unset ylabel
set xrange [0:1]
set yrange [0:1]
set lmargin 0
set rmargin 0
set tmargin 0
set bmargin 0
set key at graph 0.03, graph 0.95 left top Left reverse horizontal maxrows 3 width 3 spacing 1.5 font ',11'
plot NaN with points lc rgb '#9400d3' pt 9 ps 1.5 lw 1.5 title 'plain float Bullet', NaN with points lc rgb '#009e73' pt 5 ps 1.1 lw 1.5 title 'plain double Bullet', NaN with points lc rgb '#0072b2' pt 6 ps 0.9 lw 1.5 title 'lpss float L=16', NaN with points lc rgb '#0072b2' pt 6 ps 1.4 lw 1.5 title 'lpss float L=64', NaN with points lc rgb '#0072b2' pt 6 ps 1.9 lw 1.5 title 'lpss float L=128', NaN with points lc rgb '#0072b2' pt 6 ps 2.4 lw 1.5 title 'lpss float L=1024', NaN with points lc rgb '#0072b2' pt 6 ps 2.9 lw 1.5 title 'lpss float L=4096', NaN with points lc rgb '#d55e00' pt 12 ps 2.2 lw 1.5 title 'lpss double L=1024', NaN with points lc rgb '#e69f00' pt 4 ps 1.3 lw 1.5 title 'lpss-cluster L=16, 1 worker', NaN with points lc rgb '#e69f00' pt 4 ps 2 lw 1.5 title 'lpss-cluster L=16, 2 workers', NaN with points lc rgb '#e69f00' pt 4 ps 2.7 lw 1.5 title 'lpss-cluster L=16, 3 workers', NaN with points lc rgb 'black' pt 2 ps 3.2 lw 2 title 'x: the spheres did not collide', NaN with lines dt 3 lc rgb '#999999' title '0: error exactly 0 (below the line)'
unset multiplot
