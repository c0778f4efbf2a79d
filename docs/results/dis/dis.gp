set datafile separator ','
set terminal pngcairo size 1400,900 font 'Sans,11'
set output 'docs/results/dis/dis.png'
set title 'lpss-dis: Entity State PDUs per second'
set ylabel 'PDUs per second (log)'
set logscale y
set yrange [1:*]
set xrange [-0.6:*]
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set xtics rotate by -20 noenhanced
set key top left noenhanced
plot 'docs/results/dis/dis.csv' every ::1 using 4:xtic(stringcolumn(1).' / '.stringcolumn(3)) title 'lpss-dis (dead reckoned)', \
     '' every ::1 using 6 title 'one PDU per body per frame'
