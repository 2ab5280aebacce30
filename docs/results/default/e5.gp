set terminal pngcairo size 900,520 font 'DejaVu Sans,10'
set output 'docs/results/default/e5.png'
set datafile separator ','
set key bottom right
set grid
set yrange [0:1.02]
set xlabel 'faulty samples in the window (2 ms each)'
set ylabel 'isolation accuracy'
set title "E5: nominal vs perturbed plants (the residual's model stays nominal)" noenhanced
plot 'docs/results/default/e5.csv' using 1:3 with lines lw 2 title "model-free, LQR, nominal" noenhanced, 'docs/results/default/e5.csv' using 1:4 with lines lw 2 title "model-based, LQR, nominal" noenhanced, 'docs/results/default/e5.csv' using 1:5 with lines lw 2 title "residual, LQR, nominal" noenhanced, 'docs/results/default/e5.csv' using 1:6 with lines lw 2 title "model-free, LQR, perturbed" noenhanced, 'docs/results/default/e5.csv' using 1:7 with lines lw 2 title "model-based, LQR, perturbed" noenhanced, 'docs/results/default/e5.csv' using 1:8 with lines lw 2 title "residual, LQR, perturbed" noenhanced, 'docs/results/default/e5.csv' using 1:9 with lines lw 2 title "model-free, LQR, perturbed-strong" noenhanced, 'docs/results/default/e5.csv' using 1:10 with lines lw 2 title "model-based, LQR, perturbed-strong" noenhanced, 'docs/results/default/e5.csv' using 1:11 with lines lw 2 title "residual, LQR, perturbed-strong" noenhanced
