set terminal pngcairo size 900,520 font 'DejaVu Sans,10'
set output 'docs/results/default/e2.png'
set datafile separator ','
set key bottom right
set grid
set yrange [0:1.02]
set xlabel 'faulty samples in the window (2 ms each)'
set ylabel 'isolation accuracy'
set title "E2: LSTM vs MLP over partial faults of motor 2 (LQR, nominal; Θ_tol 0.95, identification |Θ̂−Θ| ≤ 0.05)" noenhanced
plot 'docs/results/default/e2.csv' using 1:3 with lines lw 2 title "LSTM, theta2 = 0.0" noenhanced, 'docs/results/default/e2.csv' using 1:4 with lines lw 2 title "MLP, theta2 = 0.0" noenhanced, 'docs/results/default/e2.csv' using 1:5 with lines lw 2 title "LSTM, theta2 = 0.3" noenhanced, 'docs/results/default/e2.csv' using 1:6 with lines lw 2 title "MLP, theta2 = 0.3" noenhanced, 'docs/results/default/e2.csv' using 1:7 with lines lw 2 title "LSTM, theta2 = 0.6" noenhanced, 'docs/results/default/e2.csv' using 1:8 with lines lw 2 title "MLP, theta2 = 0.6" noenhanced, 'docs/results/default/e2.csv' using 1:9 with lines lw 2 title "LSTM, theta2 = 0.9" noenhanced, 'docs/results/default/e2.csv' using 1:10 with lines lw 2 title "MLP, theta2 = 0.9" noenhanced
