#!/bin/sh
# Detector robustness beyond the training distribution (issue 6): healthy and faulty flights from
# plants, controllers and sensors the paper-setting networks never saw, through `quadfdi detect`.
# Prints a Markdown table. Usage: bench/detector-robustness.sh [quadfdi] [flights per row]
# The network and rule: by default the paper's windowed LSTM (models/lstm-model-free.qfdw) under the
# persistence rule, what detect ran by default when README's robustness table was measured (its LSTM
# column); detect's own defaults are now models/tcn-randomised.qfdw and the sequential rule.
# DETECT_OPTS adds options; a --model there replaces the LSTM (e.g. DETECT_OPTS="--model
# models/tcn-model-free.qfdw", README's TCN column), the rule staying persistence. MODEL_OPTS
# replaces the model and rule options outright: MODEL_OPTS="" runs detect's defaults.
set -eu
Q=${1:-build/release/src/quadfdi}
N=${2:-10}
R=$(cd "$(dirname "$0")/.." && pwd)
case " ${DETECT_OPTS:-} " in
  *" --model "* | *" --model="* | *" -m "*) MODEL_OPTS=${MODEL_OPTS---rule persistence} ;;
  *) MODEL_OPTS=${MODEL_OPTS---model $R/models/lstm-model-free.qfdw --rule persistence} ;;
esac
echo "detect options: ${MODEL_OPTS} ${DETECT_OPTS:-}" >&2
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cat > "$T/lag.toml" <<'TOML'
base = "nominal"
motor_time_constant = 0.015  # [s] real rotors: tens of ms
linear_drag = 0.002
TOML
cat > "$T/heavy.toml" <<'TOML'
base = "nominal"
mass = 0.034                  # Crazyflie 2.1 with a deck and a bigger battery
TOML
row() {  # name, simulate options
  name=$1; shift
  fa=0; det=0; right=0; delays=""
  i=1
  while [ "$i" -le "$N" ]; do
    "$Q" simulate "$@" --steps 3000 --seed $((100 + i)) --output "$T/h.csv" >/dev/null 2>&1
    if "$Q" detect $MODEL_OPTS ${DETECT_OPTS:-} --input "$T/h.csv" --output /dev/null 2>&1 | grep -q FAULT; then fa=$((fa + 1)); fi
    m=$(( (i % 4) + 1 ))
    f=$((${FAULT_BASE:-900} + 7 * i))  # fault steps spread over the detector's stride phase
    "$Q" simulate "$@" --motor $m --theta ${THETA:-0} --fault-step $f --steps $((f + 400)) --seed $((200 + i)) --output "$T/f.csv" >/dev/null 2>&1
    s=$("$Q" detect $MODEL_OPTS ${DETECT_OPTS:-} --input "$T/f.csv" --output /dev/null 2>&1 | grep "FAULT" || true)
    if [ -n "$s" ]; then
      det=$((det + 1))
      got=$(echo "$s" | sed -n 's/.*FAULT in motor \([0-9]\) at t = \([0-9.]*\) s.*/\1 \2/p')
      if [ "${got%% *}" = "$m" ]; then
        right=$((right + 1))
        delays="$delays $(echo "${got#* }" | awk -v f=$f '{printf "%d", ($1 - 0.002 * f) * 1000 + 0.5}')"
      fi
    fi
    i=$((i + 1))
  done
  med=$(echo $delays | tr ' ' '\n' | sort -n | awk '{a[NR]=$1} END {if (NR) print a[int((NR+1)/2)]; else print "–"}')
  worst=$(echo $delays | tr ' ' '\n' | sort -n | tail -1)
  echo "| $name | $fa/$N | $det/$N | $right/$N | ${med} / ${worst:-–} |"
}
echo "| condition | healthy flights with an alarm | faulty flights alarmed | right motor | delay median / worst [ms] |"
echo "|---|---|---|---|---|"
row "nominal plant, LQR (training conditions)"
row "perturbed plant (docs/model.md)" --params perturbed
row "perturbed-strong plant" --params perturbed-strong
row "CBF-QP safety filter" --controller cbf
row "authors' LQR weights (Q = I, R = I)" --lqr-weights authors
row "motor lag 15 ms + drag" --params "$T/lag.toml" --controller-params nominal
row "heavier vehicle (34 g), controller for 29.9 g" --params "$T/heavy.toml" --controller-params nominal
row "sensor noise 2 mm, 0.01 rad" --position-noise 0.002 --attitude-noise 0.01
THETA=0.3 row "partial fault Θ = 0.3 (nominal)"
FAULT_BASE=150 row "fault mid-manoeuvre (0.3–0.45 s after take-off from a random state)"
DETECT_OPTS="${DETECT_OPTS:-} --stride 1" row "nominal, detect --stride 1 (every sample evaluated)"
