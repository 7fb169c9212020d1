#!/usr/bin/env bash
# One command: install what is missing, build, run the whole test suite in a
# Release build (build/), then every reader's fuzz target for 15 s from a
# fixed seed, built with ASan and UBSan (tools/fuzz.sh, build-fuzz/), so that
# a run is repeatable. This is what CI runs (.ci/run).
#
# --thorough adds the whole suite again built with AddressSanitizer and
# UndefinedBehaviorSanitizer (build-asan/): about 8 more minutes on 2 cores,
# run before landing a change to the models, the engines or memory handling
# (docs/FUZZING.md, "In tools/test.sh").
# Usage: tools/test.sh [--thorough]
set -euo pipefail
cd "$(dirname "$0")/.."
thorough=0
case "${1:-}" in
  "") ;;
  --thorough) thorough=1 ;;
  *) echo "usage: tools/test.sh [--thorough]" >&2; exit 2 ;;
esac
tools/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build
ctest --test-dir build --output-on-failure -j "$(nproc)"

tools/fuzz.sh 15 1

if ((thorough)); then
  # Sanitizer build (docs/FUZZING.md): any ASan or UBSan report fails its test.
  # -O1 -g1 halves its build time; file:line in reports stays. The whole suite
  # runs, the longest seeded grids on half their points (tests/CMakeLists.txt);
  # the benchmarks, which no test runs, are not built.
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" \
    -DRAPLAS_SANITIZE=ON -DRAPLAS_BUILD_BENCH=OFF >/dev/null
  cmake --build build-asan
  UBSAN_OPTIONS=print_stacktrace=1 ctest --test-dir build-asan --output-on-failure -j "$(nproc)"
fi
