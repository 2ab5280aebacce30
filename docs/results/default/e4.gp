set terminal pngcairo size 900,520 font 'DejaVu Sans,10'
set output 'docs/results/default/e4.png'
set datafile separator ','
set key bottom right
set grid
set yrange [0:1.02]
set xlabel 'faulty samples in the window (2 ms each)'
set ylabel 'isolation accuracy'
set title "E4: model-free (y, u) vs model-based (y, u, ỹ) vs residual-only features (LQR, nominal)" noenhanced
plot 'docs/results/default/e4.csv' using 1:3 with lines lw 2 title "model-free, LQR, nominal" noenhanced, 'docs/results/default/e4.csv' using 1:4 with lines lw 2 title "model-based, LQR, nominal" noenhanced, 'docs/results/default/e4.csv' using 1:5 with lines lw 2 title "residual, LQR, nominal" noenhanced
