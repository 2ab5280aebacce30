set terminal pngcairo size 800,500 font 'DejaVu Sans,10'
set output '/work/runs/slew/cand120/x500-heading/tradeoff.png'
set datafile separator ','
set logscale x
set grid
set key top right
set xlabel 'false alarms per flight hour'
set ylabel 'mild-fault (Θ 0.6–0.8) degraded delay, median [ms]'
set title 'Delay against false-alarm rate (thresholds re-solved per target)' noenhanced
plot '/work/runs/slew/cand120/x500-heading/tradeoff.csv' every ::1 using 2:4 with linespoints lw 2 title 'measured rate', '/work/runs/slew/cand120/x500-heading/tradeoff.csv' every ::1 using 1:4 with linespoints lw 1 dt 2 title 'target rate'
