set terminal pngcairo size 800,500 font 'DejaVu Sans,10'
set output 'docs/results/randomised/decisions/tradeoff.png'
set datafile separator ','
set logscale x
set grid
set key top right
set xlabel 'false alarms per flight hour (target; measured where any)'
set ylabel 'mild-fault (Θ 0.6–0.8) degraded delay, median [ms]'
set title 'Delay against false-alarm rate' noenhanced
plot 'docs/results/randomised/decisions/tradeoff.csv' every ::1 using 1:4 with linespoints lw 2 title 'against the target rate'
