#!/usr/bin/env bash
# Experiment E7 and the decisions experiment for the shipped per-vehicle detectors (issues 13
# and 14, models/README.md): each library vehicle is flown and scored with its own model
# models/tcn-STEM.qfdw and that model's calibration, into docs/results/vehicles/STEM/.
#   scripts/evaluate-vehicle-models.sh [QUADFDI] [FLIGHT_HOURS_PER_VEHICLE]
# The pooled false-alarm count over the vehicles is summed by hand in the README (each
# vehicle's decisions.md states its own count, hours and bound).
set -euo pipefail
cd "$(dirname "$0")/.."
quadfdi=${1:-build/release/src/quadfdi}
hours=${2:-10}
for vehicle in configs/vehicles/*.toml; do
  stem=$(basename "$vehicle" .toml)
  model=models/tcn-$stem.qfdw
  [[ -f $model ]] || { echo "evaluate-vehicle-models: $model: missing (train it: models/README.md)" >&2; exit 1; }
  "$quadfdi" evaluate -e e7 decisions --model-free "$model" --vehicle "$vehicle" --flights-per-class 5 \
    --flight-hours "$hours" --scale default -o "docs/results/vehicles/$stem" -q
done
