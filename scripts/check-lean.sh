#!/bin/sh
# The lean build (QUADFDI_WITH_TRAINING=OFF, `cmake --workflow --preset lean`): quadfdi runs the
# shipped models with no LibTorch in the process. Run by that preset's test step.
#   scripts/check-lean.sh build/lean/src/quadfdi
set -eu
Q=$1
cd "$(dirname "$0")/.."
fail() { echo "check-lean: $*" >&2; exit 1; }
# Library names only (ldd's first field): a load address such as 0x00007f69cdfc1000 contains "c10".
if ldd "$Q" | awk '{print $1}' | grep -Ei 'torch|c10|caffe2'; then fail "$Q links LibTorch"; fi
ldd "$Q" > /dev/null || fail "ldd failed on $Q"
"$Q" --help | grep -Eq '^ +(train|reproduce|convert-model) ' && fail "the lean build lists a training command"
said=$("$Q" train --scale tiny 2>&1) && fail "the lean build ran train"
[ "$said" = "quadfdi: error: train needs LibTorch, and this quadfdi was built without it (QUADFDI_WITH_TRAINING=OFF)" ] ||
  fail "train in the lean build: $said"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/quadfdi-lean.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
"$Q" simulate --motor 3 --theta 0 --fault-step 500 --steps 900 --seed 4 --output "$tmp/flight.csv" 2> /dev/null
for model in models/tcn-randomised.qfdw models/lstm-model-free.qfdw models/tcn-model-free.qfdw; do
  "$Q" detect --model "$model" --input "$tmp/flight.csv" --output "$tmp/out.jsonl" 2> "$tmp/err" || fail "detect failed: $(cat "$tmp/err")"
  grep -q "FAULT in motor 3" "$tmp/err" || fail "$model: no fault found in motor 3: $(cat "$tmp/err")"
done
echo "check-lean: $Q: no LibTorch linked; train refused in one line; detect finds the fault in motor 3 with both shipped models"
