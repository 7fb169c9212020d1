#!/usr/bin/env bash
# One command: install what is missing, build, then
#   1. the whole test suite in a Release build (build/);
#   2. the whole suite again built with AddressSanitizer and
#      UndefinedBehaviorSanitizer (build-asan/): any report fails its test;
#   3. every reader's fuzz target for 15 s from a fixed seed, built with ASan
#      and UBSan (tools/fuzz.sh, build-fuzz/), so that a run is repeatable.
# This is what CI runs (.ci/run). --quick leaves out step 2 (local use).
# Usage: tools/test.sh [--quick]
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
case "${1:-}" in
  "") ;;
  --quick) quick=1 ;;
  *) echo "usage: tools/test.sh [--quick]" >&2; exit 2 ;;
esac
tools/install-deps.sh
start=$(date +%s)
step() { echo "== tools/test.sh: $1 ($(( $(date +%s) - start )) s so far)"; }

step "Release build and suite"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build
ctest --test-dir build --output-on-failure -j "$(nproc)"

if ((!quick)); then
  # Sanitizer build (docs/FUZZING.md): -O1 -g1 halves its build time;
  # file:line in reports stays. The whole suite runs, the longest seeded grids
  # on part of their points (tests/CMakeLists.txt); the benchmarks, which no
  # test runs, are not built.
  step "ASan + UBSan build and suite"
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" \
    -DRAPLAS_SANITIZE=ON -DRAPLAS_BUILD_BENCH=OFF >/dev/null
  cmake --build build-asan
  UBSAN_OPTIONS=print_stacktrace=1 ctest --test-dir build-asan --output-on-failure -j "$(nproc)"
fi

step "fuzz targets"
tools/fuzz.sh 15 1
step "done"
