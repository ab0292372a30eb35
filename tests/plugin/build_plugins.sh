#!/usr/bin/env bash
# What the plugin tests share (the ctest fixture kincal_plugins): this build folder installed into
# OUT/prefix (the libraries and the kincal executable, component Unspecified), and the two example plugins
# configured with find_package(kincal) outside the source tree and built against that install alone:
# examples/plugin in OUT/plugin, examples/plugins/learned_residual in OUT/learned.
#   tests/plugin/build_plugins.sh SOURCE_DIR BUILD_DIR OUT
set -euo pipefail
SRC="$(realpath "$1")"
BUILD="$(realpath "$2")"
OUT="$3"
GEN=""
if command -v ninja >/dev/null; then GEN="-G Ninja"; fi
rm -rf "$OUT"
mkdir -p "$OUT"
cmake --install "$BUILD" --component Unspecified --prefix "$OUT/prefix" >/dev/null
# The plugins are compiled by the compiler that compiled kincal (each links its own copy of the static
# libraries, with that compiler's copies of the inline templates).
CXX_OF_BUILD="$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$BUILD/CMakeCache.txt")"
cmake -S "$SRC/examples/plugin" -B "$OUT/plugin" $GEN -DCMAKE_CXX_COMPILER="$CXX_OF_BUILD" \
  -DCMAKE_PREFIX_PATH="$OUT/prefix" >/dev/null
cmake --build "$OUT/plugin" >/dev/null
cmake -S "$SRC/examples/plugins/learned_residual" -B "$OUT/learned" $GEN -DCMAKE_CXX_COMPILER="$CXX_OF_BUILD" \
  -DCMAKE_PREFIX_PATH="$OUT/prefix" >/dev/null
cmake --build "$OUT/learned" >/dev/null
echo "build_plugins: $OUT"
