set terminal pngcairo size 900,520 font 'DejaVu Sans,10'
set output 'docs/results/default/e1.png'
set datafile separator ','
set key bottom right
set grid
set yrange [0:1.02]
set xlabel 'faulty samples in the window (2 ms each)'
set ylabel 'isolation accuracy'
set title "E1: complete failure of each motor, one network trained on motor 2 (LQR, nominal)" noenhanced
plot 'docs/results/default/e1.csv' using 1:3 with lines lw 2 title "motor 1" noenhanced, 'docs/results/default/e1.csv' using 1:4 with lines lw 2 title "motor 2" noenhanced, 'docs/results/default/e1.csv' using 1:5 with lines lw 2 title "motor 3" noenhanced, 'docs/results/default/e1.csv' using 1:6 with lines lw 2 title "motor 4" noenhanced
