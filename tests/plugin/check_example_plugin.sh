#!/usr/bin/env bash
# The example plugin (examples/plugin) built from outside the source tree against an installed kincal,
# then run by the installed `kincal`: listed by `methods`; example_least_squares (kincal's least_squares
# built by the plugin) identifies the same robot to the last digit alone, after least_squares in a
# pipeline and in a study beside the built-in estimators; the plugin's own test (the conformance kits)
# passes; a name taken, a missing file, a library without the entry point and a
# plugin built against another version: exit 2, one line.
# The install and both plugins' builds are build_plugins.sh's (the ctest fixture kincal_plugins), in PLUGINS.
#   tests/plugin/check_example_plugin.sh SOURCE_DIR BUILD_DIR PLUGINS
set -euo pipefail
SRC="$(realpath "$1")"
BUILD="$(realpath "$2")"
PLUGINS="$(realpath "$3")"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
fail() { echo "check_example_plugin: $*" >&2; exit 1; }
[ -d "$PLUGINS/plugin" ] && [ -d "$PLUGINS/learned" ] || fail "no plugins in $PLUGINS (build_plugins.sh first)"
# The plugin's own test on the installed conformance kits: example_least_squares recovers a simulated
# truth, example_newton reaches the targets the identified arm reaches, on jacobian's joints.
[ -x "$PLUGINS/plugin/kincal_example_plugin_test" ] || fail "the plugin's test was not built (GoogleTest not found?)"
"$PLUGINS/plugin/kincal_example_plugin_test" --gtest_brief=1 >"$WORK/plugin_test.txt" 2>&1 \
  || { cat "$WORK/plugin_test.txt" >&2; fail "the plugin's own test"; }
K="$PLUGINS/prefix/bin/kincal"
P="$PLUGINS/plugin/libkincal_example_plugin.so"
R="$SRC/examples/robots"
cd "$WORK"

"$K" --plugin "$P" methods >methods.txt
grep -q "example_least_squares" methods.txt && grep -q "example_newton" methods.txt || fail "methods does not list the plugin"
# The option docs the plugin registered, as the built-in methods' are printed.
"$K" --plugin "$P" methods --options example_newton | grep -q "step_tolerance" \
  || fail "methods --options does not print the plugin compensator's keys"
"$K" --plugin "$P" methods --options example_least_squares | grep -q "max_iterations" \
  || fail "methods --options does not print the plugin estimator's keys"
KINCAL_PLUGIN_PATH=":$P:" "$K" methods | grep -q example_newton \
  || fail "KINCAL_PLUGIN_PATH not read"

"$K" simulate --nominal "$R/seed_nominal.yaml" --truth "$R/seed_identified.yaml" --protocol random --poses 60 \
  --noise 5um --seed 7 --out data.csv >/dev/null
"$K" identify --nominal "$R/seed_nominal.yaml" --data data.csv --method least_squares --out ls.yaml >/dev/null
"$K" identify --plugin "$P" --nominal "$R/seed_nominal.yaml" --data data.csv --method example_least_squares \
  --out plugin.yaml >/dev/null
cmp -s ls.yaml plugin.yaml || fail "example_least_squares differs from least_squares"
"$K" identify --nominal "$R/seed_nominal.yaml" --data data.csv --method least_squares,least_squares \
  --out ls2.yaml >/dev/null
"$K" --plugin "$P" identify --nominal "$R/seed_nominal.yaml" --data data.csv \
  --method least_squares,example_least_squares --out pipeline.yaml >/dev/null
cmp -s ls2.yaml pipeline.yaml || fail "the pipeline least_squares,example_least_squares differs"

cat >study.yaml <<YAML
name: a plugin beside the built-in methods
seed: 3
trials: 2
robots: {nominal: $R/seed_nominal.yaml, truth: $R/seed_identified.yaml}
datasets:
  - {name: random, simulate: {protocol: random, poses: 60, noise: 5um}}
estimators:
  - least_squares
  - example_least_squares
  - {name: twice, method: "least_squares,least_squares"}
  - {name: then_plugin, method: "least_squares,example_least_squares"}
compensators: [jacobian, example_newton]
validation:
  - {name: targets, random_targets: 20}
YAML
"$K" study study.yaml --out study --plugin "$P" >/dev/null 2>&1
python3 - study <<'PY' || fail "study rows differ"
import csv, sys
def rows(name, skip):
    with open(f"{sys.argv[1]}/{name}") as f:
        r = list(csv.DictReader(f))
    by = {}
    for row in r:
        key = tuple(v for k, v in row.items() if k not in skip and k not in ("item", "estimator"))
        by.setdefault(row["estimator"], []).append(key)
    return by
for name, skip in (("results.csv", ()), ("parameters.csv", ())):
    by = rows(name, skip)
    assert by["least_squares"] == by["example_least_squares"], name
    assert by["twice"] == by["then_plugin"], name
with open(f"{sys.argv[1]}/results.csv") as f:
    r = [row for row in csv.DictReader(f) if row["estimator"] == "least_squares"]
jac = [row for row in r if row["compensator"] == "jacobian"]
new = [row for row in r if row["compensator"] == "example_newton"]
assert len(jac) == len(new) == 2 and all(int(n["converged"]) >= 18 for n in new), [n["converged"] for n in new]
PY

# The same plugin in the Python module (its own static copy of kincal, its own registries), when built.
if [ -d "$BUILD/python" ] && ls "$BUILD"/python/kincal*.so >/dev/null 2>&1 && /usr/bin/python3 -c "import numpy" 2>/dev/null; then
  PYTHONPATH="$BUILD/python" /usr/bin/python3 - "$P" "$R" <<'PY' || fail "the plugin in Python"
import sys, numpy as np, kincal
kincal.load_plugin(sys.argv[1])
kincal.load_plugin(sys.argv[1])  # the same file again: nothing new
nominal = kincal.load_robot(sys.argv[2] + "/seed_nominal.yaml")
truth = kincal.load_robot(sys.argv[2] + "/seed_identified.yaml")
data = kincal.simulate(nominal, truth, protocol="random", poses=50, noise=5e-6, seed=2)
a, _ = kincal.identify(nominal, data, "least_squares")
b, report = kincal.identify(nominal, data, "example_least_squares")
assert np.array_equal(a.parameters, b.parameters) and report["estimator"] == "least_squares", report["estimator"]
PY
else
  echo "check_example_plugin: the Python module is not built; its part skipped"
fi

# The learned residual plugin (built the same way) is listed beside the example's (tested in
# learned_residual_test).
"$K" --plugin "$P" --plugin "$PLUGINS/learned/libkincal_learned_residual.so" methods | grep -q "learned_residual" \
  || fail "the learned residual plugin is not listed"

# Refusals: exit 2 and one line each.
expect_refusal() {
  local what="$1" pattern="$2"; shift 2
  set +e; "$@" >out.txt 2>err.txt; local rc=$?; set -e
  [ "$rc" = 2 ] || fail "$what: exit $rc, expected 2"
  [ "$(wc -l <err.txt)" = 1 ] || fail "$what: not one line: $(cat err.txt)"
  grep -q -- "$pattern" err.txt || fail "$what: unexpected message: $(cat err.txt)"
}
cp "$P" copy.so
expect_refusal "name taken" "name 'example_least_squares' is taken" "$K" --plugin "$P" --plugin copy.so methods
expect_refusal "missing file" "no such file" "$K" methods --plugin missing.so
cat >no_entry.cc <<'CXX'
extern "C" int not_a_kincal_plugin() { return 1; }
CXX
c++ -shared -fPIC no_entry.cc -o no_entry.so
expect_refusal "no entry point" "no entry point" "$K" --plugin no_entry.so methods
cat >other_version.cc <<'CXX'
#include "framework/plugin.h"
#undef KINCAL_VERSION_STRING
#define KINCAL_VERSION_STRING "0.0.1-other"
KINCAL_PLUGIN(registrar) { (void)registrar; }
CXX
# framework/plugin.h declares the model registrations, whose interface is Eigen's: its headers too.
c++ -std=c++17 -shared -fPIC -I"$PLUGINS/prefix/include/kincal" $(pkg-config --cflags eigen3) other_version.cc \
  -o other_version.so
expect_refusal "another version" "built against kincal 0.0.1-other, this is kincal" "$K" --plugin other_version.so methods
echo "check_example_plugin: ok"
