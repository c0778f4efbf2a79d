set datafile separator ','
set terminal pngcairo size 1400,900 font 'Sans,11'
set output 'docs/results/stability/stability.png'
set title 'Stability suite: each metric as a fraction of its limit (<= limits: below 1 passes; >= limits shown inverted; 1e-4: zero, or a limit of 0 kept)'
set termoption noenhanced
set style data histogram
set style fill solid 0.6
set logscale y
set yrange [1e-4:10]
set ylabel 'value / limit'
set xtics rotate by 60 right font ',7'
set arrow from graph 0, first 1 to graph 1, first 1 nohead lc rgb 'red'
unset key
r(v,l,k) = strcol(6) eq '<=' ? (l == 0 ? (v == 0 ? 1e-4 : 10) : (v/l > 1e-4 ? v/l : 1e-4)) : (l == 0 ? (v >= 0 ? 1e-4 : 10) : (v > 0 ? (l/v > 1e-4 ? l/v : 1e-4) : 10))
plot 'docs/results/stability/stability.csv' every ::1 using (r($4,$5,0)):xtic(sprintf('%s %s', strcol(1), strcol(2)[1:3]))
