#!/bin/sh
# `cmake --install` gives a quadfdi that runs from its prefix alone: it finds the shipped models
# and their calibrations under PREFIX/share/quadfdi (not in the source tree it was built from),
# the vehicle library under PREFIX/share/quadfdi/configs, and, in a build with training, hands
# train over to the installed quadfdi-training. Run by the test and lean presets' tests.
#   scripts/check-install.sh BUILD_DIR
set -eu
unset QUADFDI_MODEL  # it would win over the shipped models this checks
B=$(cd "$1" && pwd)
fail() { echo "check-install: $*" >&2; exit 1; }
tmp=$(mktemp -d "${TMPDIR:-/tmp}/quadfdi-install.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
P="$tmp/prefix with space"
cmake --install "$B" --prefix "$P" > "$tmp/install.log" || fail "cmake --install failed: $(tail -3 "$tmp/install.log")"
Q="$P/bin/quadfdi"
S="$P/share/quadfdi"
[ -x "$Q" ] || fail "no $Q"
for f in models/tcn-randomised.qfdw models/tcn-randomised.calibration.json models/tcn-crazyflie2.qfdw \
         configs/vehicles/crazyflie2.toml configs/randomisation-default.toml; do
  [ -f "$S/$f" ] || fail "not installed: $S/$f"
done
[ -e "$S/models/candidates" ] && fail "the candidates (measured, not shipped) were installed"
cd "$tmp"  # away from the source tree: nothing may be found relative to it
"$Q" simulate --motor 3 --theta 0 --fault-step 500 --steps 900 --seed 4 --output flight.csv 2> /dev/null
# The vehicle's own model and its calibration, from the prefix; the vehicle by its library name.
"$Q" detect --vehicle crazyflie2 --input flight.csv --output out.jsonl 2> err || fail "detect failed: $(cat err)"
grep -qF "detect: model $S/models/tcn-crazyflie2.qfdw (for --vehicle $S/configs/vehicles/crazyflie2.toml)" err ||
  fail "not the installed own model: $(head -3 err)"
grep -q "FAULT in motor 3" err || fail "no fault found in motor 3: $(cat err)"
# A vehicle with no model of its own: the installed general model.
cp "$S/configs/vehicles/crazyflie2.toml" mine.toml
"$Q" detect --vehicle mine.toml --input flight.csv --output out.jsonl 2> err || fail "detect failed: $(cat err)"
grep -qF "detect: model $S/models/tcn-randomised.qfdw (the general model: no tcn-mine.qfdw in $S/models for" err ||
  fail "not the installed general model: $(head -3 err)"
grep -q "warning: no calibration" err && fail "the installed general model ran without its calibration: $(cat err)"
# Shipped files named by their paths in the source tree, from here (which copy is opened: the
# vehicle-name check above and cli_options_test's ShippedFiles.*).
"$Q" detect --model models/tcn-racer250.qfdw --vehicle configs/vehicles/racer250.toml --input flight.csv \
  --output out.jsonl 2> err || fail "detect with the source tree's paths failed: $(cat err)"
grep -q "FAULT in motor 3" err || fail "detect with the source tree's paths: no fault in motor 3: $(cat err)"
if [ -x "$P/bin/quadfdi-training" ]; then
  "$Q" train --help > help 2>&1 || fail "train --help through the installed quadfdi-training failed: $(head -3 help)"
  grep -q "Train a" help || fail "train --help: $(head -3 help)"
fi
echo "check-install: quadfdi installed to a prefix runs its shipped models, calibrations and vehicle library from there"
