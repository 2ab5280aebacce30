#!/usr/bin/env bash
# Experiment E7 and the decisions experiment per vehicle (issues 13 and 14, models/README.md).
#   scripts/evaluate-vehicle-models.sh [QUADFDI] [FLIGHT_HOURS_PER_VEHICLE] [library|held-out]
# library (default): each library vehicle (configs/vehicles/*.toml) is flown and scored with the
#   model `detect --vehicle` runs for it — its own models/tcn-STEM.qfdw, else the general
#   models/tcn-randomised.qfdw — and the calibration `detect --vehicle` runs with (the model's for
#   that vehicle, MODEL.STEM.calibration.json, where one is shipped — `evaluate` with one --vehicle
#   picks it as detect does — else the model's own), into docs/results/vehicles/STEM/, and its
#   body-rates model models/tcn-STEM-rates.qfdw where one is shipped into STEM-rates/; then
#   the summary docs/results/vehicles/README.md (scripts/summarise-vehicle-results.py), with the
#   general model's E7 of docs/results/randomised/e7.csv alongside when it is there.
# held-out: each airframe of configs/vehicles/held-out/ (no shipped model trained on it) is flown
#   with the general model twice: with its shipped calibration (what `detect --vehicle` runs) into
#   docs/results/held-out-vehicles/STEM/, and with a calibration made for that airframe (quadfdi
#   calibrate, 90 flight hours; made once, kept beside the results) into STEM-calibrated/; then the
#   summary docs/results/held-out-vehicles/README.md.
set -euo pipefail
cd "$(dirname "$0")/.."
quadfdi=${1:-build/release/src/quadfdi}
hours=${2:-40}
set_name=${3:-library}
general=models/tcn-randomised.qfdw
# 60 faulty flights per Θ: a Θ's interval coverage over 20 flights has a sampling spread of about
# ±7 points (flights, not samples, are the independent units), wider than issue 14's ±5.
evaluate() {  # MODEL VEHICLE OUTPUT_DIR [evaluate options]
  local model=$1 vehicle=$2 out=$3
  shift 3
  "$quadfdi" evaluate -e e7 decisions --model-free "$model" --vehicle "$vehicle" --flights-per-class 5 --faulty-per-theta 60 \
    --flight-hours "$hours" --scale default -o "$out" -q "$@"
}
case $set_name in
  library)
    for vehicle in configs/vehicles/*.toml; do
      stem=$(basename "$vehicle" .toml)
      # The model `detect --vehicle` runs: the vehicle's own (the quad450's since 2026-11-27 is the
      # general model fine-tuned on it, models/README.md), else the general one.
      model=models/tcn-$stem.qfdw
      [[ -f $model ]] || model=$general
      evaluate "$model" "$vehicle" "docs/results/vehicles/$stem"
      # Its body-rates model, which `detect --vehicle` runs on telemetry with p,q,r (models/README.md).
      rates=models/tcn-$stem-rates.qfdw
      [[ ! -f $rates ]] || evaluate "$rates" "$vehicle" "docs/results/vehicles/$stem-rates"
    done
    e7=docs/results/randomised/e7.csv
    python3 scripts/summarise-vehicle-results.py $([[ -f $e7 ]] && echo "$e7")
    ;;
  held-out)
    for vehicle in configs/vehicles/held-out/*.toml; do
      stem=$(basename "$vehicle" .toml)
      out=docs/results/held-out-vehicles
      evaluate "$general" "$vehicle" "$out/$stem"
      # The airframe's own calibration of the general model: the library calibrations' settings
      # (models/README.md, "2026-11-27: the failed statistic capped at 0.15"), on this airframe's
      # randomised flights.
      calibration=$out/$stem-calibrated/tcn-randomised.$stem.calibration.json
      mkdir -p "$out/$stem-calibrated"
      [[ -f $calibration ]] || "$quadfdi" calibrate --model "$general" --randomise configs/randomisation-default.toml \
        --vehicle "$vehicle" --flights 5400 --flight-seconds 60 --faulty-flights 1200 --seed 11 \
        --degraded-below 0.8 0.85 0.9 0.95 --false-alarms-per-hour 0.03 --interval belt --failed-cap 0.15 \
        -o "$calibration" -q
      evaluate "$general" "$vehicle" "$out/$stem-calibrated" --calibration "$calibration"
    done
    python3 scripts/summarise-vehicle-results.py --held-out
    ;;
  *) echo "evaluate-vehicle-models.sh: the set must be library or held-out, not '$set_name'" >&2; exit 2 ;;
esac
