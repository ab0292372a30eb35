#!/usr/bin/env bash
# docs/guide/commands.md, "Deploying a calibration": the three commands as written there, from a simulated tracker
# dataset of the IRB 120 to a filtered RAPID module. Usage: readme_deploy.sh KINCAL SOURCE_DIR
set -euo pipefail
kincal="$1"
cd "$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$kincal" simulate --nominal examples/robots/irb120_mdh.yaml --truth examples/robots/irb120_as_measured.yaml \
  --protocol random --poses 200 --noise 10um --seed 1 --out "$work/tracker.csv" >/dev/null
"$kincal" identify --nominal examples/robots/irb120_mdh.yaml --data "$work/tracker.csv" --method least_squares \
  --out "$work/irb120_identified.yaml" >"$work/identify.txt"
grep -q '^least_squares: converged, 8 iterations, 200 measurements, residual RMS 1651.13 mm -> 0.0161773 mm' \
  "$work/identify.txt" || { echo "identify printed: $(cat "$work/identify.txt")"; exit 1; }
"$kincal" filter --nominal examples/robots/irb120_mdh.yaml --identified "$work/irb120_identified.yaml" \
  --program examples/programs/irb120_pick.mod --out "$work/filtered.mod" >"$work/filter.txt" 2>&1
grep -q '^rapid: 7 Cartesian and 1 joint targets; 8 filtered, 0 kept as written; max error of the identified arm' \
  "$work/filter.txt" || { echo "filter printed: $(cat "$work/filter.txt")"; exit 1; }
# Only the target numbers differ: with every number masked, the two modules are the same text.
mask() { sed -E 's/-?[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?/N/g' "$1"; }
diff <(mask examples/programs/irb120_pick.mod) <(mask "$work/filtered.mod")
# The filtered module is not the original: pPick2 moved.
! cmp -s examples/programs/irb120_pick.mod "$work/filtered.mod"
echo "README walk-through: identify converged, 8 of 8 targets filtered, only numbers changed"
