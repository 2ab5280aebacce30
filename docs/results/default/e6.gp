set terminal pngcairo size 900,520 font 'DejaVu Sans,10'
set output 'docs/results/default/e6.png'
set datafile separator ','
set key bottom right
set grid
set yrange [0:1.02]
set xlabel 'faulty samples in the window (2 ms each)'
set ylabel 'isolation accuracy'
set title "E6: the paper's rotation map vs the exact symmetry group (LQR, nominal, complete faults)" noenhanced
plot 'docs/results/default/e6.csv' using 1:3 with lines lw 2 title "exact group" noenhanced, 'docs/results/default/e6.csv' using 1:4 with lines lw 2 title "paper rotation map" noenhanced
