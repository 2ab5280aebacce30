#!/usr/bin/env bash
# Per-vehicle detector training (issue 13's "training a user can afford") on each device asked
# for, one training at a time, with the 5-minute CPU recipe (configs/train-tcn-randomised.toml
# --vehicle); flags after -- change it (docs/networks.md measured the shipped 120-iteration recipe,
# configs/train-tcn-vehicle.toml, as "-- --max-iterations 120 --min-iterations 120 --lr-decay
# 0.983"). Prints one row per run:
# wall seconds, the mean split of an iteration (data / minibatches / held-out) and the final
# held-out accuracy.
# Usage: bench/train-devices.sh QUADFDI OUTDIR "cuda:16 cpu:16" [VEHICLE ...] [-- EXTRA TRAIN ARGS]
#   each device entry is DEVICE:THREADS (THREADS feed data generation and LibTorch's CPU pool).
set -uo pipefail
quadfdi=$1 outdir=$2 devices=$3
shift 3
vehicles=() extra=()
while (($#)); do
  if [[ $1 == -- ]]; then shift; extra=("$@"); break; fi
  vehicles+=("$1"); shift
done
((${#vehicles[@]})) || vehicles=(crazyflie2 racer250 quad450)
mkdir -p "$outdir"
printf '| vehicle | device | threads | wall [s] | iterations | data / minibatches / held-out per iteration [s] | held-out accuracy |\n|---|---|---|---|---|---|---|\n'
for v in "${vehicles[@]}"; do
  for d in $devices; do
    dev=${d%%:*} threads=${d##*:} tag=$v-$dev$threads
    start=$(date +%s.%N)
    "$quadfdi" train --config configs/train-tcn-randomised.toml --vehicle "configs/vehicles/$v.toml" \
      --device "$dev" --threads "$threads" -o "$outdir/$tag.qfdw" "${extra[@]}" 2>"$outdir/$tag.err" >/dev/null
    rc=$?
    wall=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN {print b - a}')
    if ((rc)); then printf '| %s | %s | %s | failed (exit %d): %s |||\n' "$v" "$dev" "$threads" "$rc" \
      "$(tail -1 "$outdir/$tag.err")"; continue; fi
    # "(… s: data D, train T, held-out H)" on every iteration line.
    split=$(grep -o 'data [0-9.]*, train [0-9.]*, held-out [0-9.]*' "$outdir/$tag.err" |
      awk '{d+=$2; t+=$4; h+=$6; n++} END {if (n) printf "%.2f / %.2f / %.2f", d/n, t/n, h/n}')
    iters=$(grep -c '^train: iteration' "$outdir/$tag.err")
    acc=$(tail -1 "$outdir/$tag.qfdw.log.csv" | cut -d, -f4)
    printf '| %s | %s | %s | %.0f | %s | %s | %s |\n' "$v" "$dev" "$threads" "$wall" "$iters" "$split" "$acc"
  done
done
