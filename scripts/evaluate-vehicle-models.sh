#!/usr/bin/env bash
# Experiment E7 and the decisions experiment for the shipped per-vehicle detectors (issues 13
# and 14, models/README.md): each library vehicle is flown and scored with the model `detect
# --vehicle` runs for it — its own models/tcn-STEM.qfdw, else the general models/tcn-randomised.qfdw —
# and that model's calibration, into docs/results/vehicles/STEM/.
#   scripts/evaluate-vehicle-models.sh [QUADFDI] [FLIGHT_HOURS_PER_VEHICLE]
# Then the summary docs/results/vehicles/README.md (scripts/summarise-vehicle-results.py), with the
# general model's E7 of docs/results/randomised/e7.csv alongside when it is there.
set -euo pipefail
cd "$(dirname "$0")/.."
quadfdi=${1:-build/release/src/quadfdi}
hours=${2:-40}
for vehicle in configs/vehicles/*.toml; do
  stem=$(basename "$vehicle" .toml)
  # The model `detect --vehicle` runs: the vehicle's own, else the general one (the quad450 since
  # 2026-11-25 late evening: the general model serves it better than its own did, models/README.md).
  model=models/tcn-$stem.qfdw
  [[ -f $model ]] || model=models/tcn-randomised.qfdw
  # 60 faulty flights per Θ: a Θ's interval coverage over 20 flights has a sampling spread of about
  # ±7 points (flights, not samples, are the independent units), wider than issue 14's ±5.
  "$quadfdi" evaluate -e e7 decisions --model-free "$model" --vehicle "$vehicle" --flights-per-class 5 --faulty-per-theta 60 \
    --flight-hours "$hours" --scale default -o "docs/results/vehicles/$stem" -q
done
general=docs/results/randomised/e7.csv
python3 scripts/summarise-vehicle-results.py $([[ -f $general ]] && echo "$general")
