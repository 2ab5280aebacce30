set terminal pngcairo size 900,520 font 'DejaVu Sans,10'
set output 'docs/results/rates-candidate/general-airframes-e3/e3.png'
set datafile separator ','
set key bottom right
set grid
set yrange [0:1.02]
set xlabel 'faulty samples in the window (2 ms each)'
set ylabel 'isolation accuracy'
set title "E3: test inputs from the LQR vs the CBF-QP safety filter (nominal; trained on LQR data)" noenhanced
plot 'docs/results/rates-candidate/general-airframes-e3/e3.csv' using 1:3 with lines lw 2 title "model-free, LQR, nominal" noenhanced, 'docs/results/rates-candidate/general-airframes-e3/e3.csv' using 1:4 with lines lw 2 title "model-based, LQR, nominal" noenhanced, 'docs/results/rates-candidate/general-airframes-e3/e3.csv' using 1:5 with lines lw 2 title "model-free, CBF-QP, nominal" noenhanced, 'docs/results/rates-candidate/general-airframes-e3/e3.csv' using 1:6 with lines lw 2 title "model-based, CBF-QP, nominal" noenhanced
