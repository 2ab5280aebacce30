#!/bin/sh
# Regenerates tests/golden/ from the current build (after a deliberate change in numerical
# behaviour). Review `git diff tests/golden` before committing. Usage: scripts/update-goldens.sh [quadfdi]
set -eu
cd "$(dirname "$0")/.."
Q=${1:-build/test/src/quadfdi}
G=tests/golden
"$Q" simulate --motor 2 --theta 0.3 --fault-step 60 --steps 120 --seed 1 --full-state --output - 2>/dev/null > $G/flight-motor2-theta0.3-seed1.csv
"$Q" simulate --controller cbf --motor 4 --theta 0 --fault-step 50 --steps 150 --seed 3 --output - 2>/dev/null > $G/flight-cbf-motor4-seed3.csv
# The same flags as Golden.ShippedModelDetections (tests/cli/golden_cli_test.cpp): the paper's LSTM
# under the persistence rule, not detect's defaults.
"$Q" simulate --motor 3 --theta 0 --fault-step 150 --steps 260 --seed 5 --output - 2>/dev/null |
  QUADFDI_KERNEL=generic "$Q" detect --model models/lstm-model-free.qfdw --rule persistence --input - -q > $G/detect-motor3-seed5.jsonl
# The dataset's content summary (count, sum, sum of squares per array): the test prints it.
bin=$(dirname "$Q")/../tests/cli_test
QUADFDI_GOLDEN_PRINT=1 "$bin" --gtest_filter=Golden.TinyDatasetContent > /dev/null 2> $G/dataset-tiny-seed2.txt
echo "update-goldens: done; review git diff $G" >&2
