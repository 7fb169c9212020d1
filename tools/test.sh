#!/usr/bin/env bash
# One command: install what is missing, build, run the whole test suite; then
# the suite again built with AddressSanitizer and UndefinedBehaviorSanitizer
# (build-asan/), then every fuzz target for 15 s from a fixed seed, so that a
# run is repeatable (tools/fuzz.sh, build-fuzz/).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build
ctest --test-dir build --output-on-failure -j "$(nproc)"

# Sanitizer build (docs/FUZZING.md): any ASan or UBSan report fails its test.
# -O1 -g1 halves its build time; file:line in reports stays. The whole suite
# runs, the event/cycle equivalence sweep included on half its grid
# (tests/CMakeLists.txt); the benchmarks, which no test runs, are not built.
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" \
  -DRAPLAS_SANITIZE=ON -DRAPLAS_BUILD_BENCH=OFF >/dev/null
cmake --build build-asan
UBSAN_OPTIONS=print_stacktrace=1 ctest --test-dir build-asan --output-on-failure -j "$(nproc)"

tools/fuzz.sh 15 1
