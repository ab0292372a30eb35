#!/usr/bin/env bash
# The learned residual's UR10 study (examples/studies/learned_residual_ur10.yaml) end to end: with the
# plugin built against an install of this build, outside the tree (build_plugins.sh), convert series D of
# ../shared/data/ur10_ipa2021 with scripts/ur10_ipa2021_dataset into a temporary folder (the data never
# enters the build or the repository), run the study file with its dataset path pointed there, and check
# that every estimator scored its held-out rows and that the residual lowers the held-out RMS of the
# geometry. Exit 77 (skipped) without the shared data, unless KINCAL_REQUIRE_DATA=1.
#   tests/plugin/check_learned_residual_ur10.sh SOURCE_DIR PLUGINS
# (PLUGINS: build_plugins.sh's OUT, the ctest fixture kincal_plugins)
set -euo pipefail
SRC="$(realpath "$1")"
PLUGINS="$(realpath "$2")"
DATA="$SRC/../shared/data/ur10_ipa2021/Series_D/measurements_iso_cubes.csv"
if [ ! -f "$DATA" ]; then
  if [ "${KINCAL_REQUIRE_DATA:-0}" = "1" ]; then echo "check_learned_residual_ur10: no $DATA" >&2; exit 1; fi
  echo "check_learned_residual_ur10: no $DATA; skipped"
  exit 77
fi
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
fail() { echo "check_learned_residual_ur10: $*" >&2; exit 1; }
[ -d "$PLUGINS/learned" ] || fail "no plugin in $PLUGINS (build_plugins.sh first)"
"$SRC/scripts/ur10_ipa2021_dataset" "$DATA" --split even-odd --out "$WORK/ur10_ipa2021_d.csv" >/dev/null
# The study file as shipped, with its dataset (../../build/ur10_ipa2021_d.csv) and robots found from $WORK.
sed -e "s#\.\./\.\./build/ur10_ipa2021_d\.csv#$WORK/ur10_ipa2021_d.csv#" -e "s#\.\./robots/#$SRC/examples/robots/#" \
  "$SRC/examples/studies/learned_residual_ur10.yaml" >"$WORK/study.yaml"
grep -q "$WORK/ur10_ipa2021_d.csv" "$WORK/study.yaml" || fail "the study file's dataset path changed"
"$PLUGINS/prefix/bin/kincal" --plugin "$PLUGINS/learned/libkincal_learned_residual.so" study "$WORK/study.yaml" \
  --out "$WORK/out" >/dev/null 2>"$WORK/err" || { cat "$WORK/err" >&2; fail "the study failed"; }
python3 - "$WORK/out/heldout.csv" <<'PY' || fail "held-out rows"
import csv, math, sys
rms = {}
with open(sys.argv[1]) as f:
    for row in csv.DictReader(f):
        rms.setdefault(row["estimator"], []).append(float(row["error_mm"]))
names = ["geometry", "geometry+residual", "gravity", "gravity+residual"]
assert all(n in rms and len(rms[n]) > 100 for n in names), {k: len(v) for k, v in rms.items()}
r = {n: math.sqrt(sum(e * e for e in rms[n]) / len(rms[n])) for n in names}
print("held-out RMS (mm):", {n: round(math.sqrt(sum(e * e for e in v) / len(v)), 4) for n, v in rms.items()})
assert r["geometry+residual"] < r["geometry"], r
PY
