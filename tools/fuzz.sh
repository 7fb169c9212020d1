#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz) with clang in build-fuzz/ and runs
# each for SECONDS (default 20) on a copy of its seed corpus, so the checked-in
# corpus never grows. Fails when any target crashes, hangs, leaks, runs out of
# memory or throws anything but InputError. SEED (default 0: a new random
# seed each run) fixes libFuzzer's mutation sequence; tools/test.sh (CI) uses
# a fixed one, so that a CI run is repeatable. See docs/FUZZING.md.
# Usage: tools/fuzz.sh [SECONDS [SEED]]
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-20}
seed=${2:-0}
usage() { echo "usage: tools/fuzz.sh [SECONDS [SEED]]" >&2; exit 2; }
[[ "$secs" =~ ^[0-9]+$ ]] && ((secs > 0)) || usage
[[ "$seed" =~ ^[0-9]+$ ]] && ((seed < 4294967296)) || usage

cc=clang-14 cxx=clang++-14
command -v "$cxx" >/dev/null || { cc=clang; cxx=clang++; }
command -v "$cxx" >/dev/null || { echo "fuzz.sh: clang is not installed (tools/install-deps.sh)" >&2; exit 2; }

CC=$cc CXX=$cxx cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRAPLAS_FUZZ=ON >/dev/null
cmake --build build-fuzz -j2 --target fuzz

declare -A dict=([fuzz_obj]=obj.dict [fuzz_scene]=toml.dict [fuzz_config]=toml.dict [fuzz_trace]=trace.dict)
run=build-fuzz/run
rm -rf "$run"
mkdir -p "$run" build-fuzz/artifacts
failed=()
for t in fuzz_obj fuzz_scene fuzz_config fuzz_trace; do
  cp -r "tests/fuzz/corpus/$t" "$run/$t"
  log=$run/$t.log
  # Inputs that once crashed a reader but are too large to be seeds (they would
  # raise libFuzzer's input size limit): each is run once.
  regressions=(tests/fuzz/regressions/$t/*)
  if [[ -e "${regressions[0]}" ]] && ! build-fuzz/tests/fuzz/$t "${regressions[@]}" >"$run/$t-regressions.log" 2>&1; then
    echo "$t: FAILED on a regression input"
    grep -E "^(==[0-9]+==ERROR|SUMMARY|$t: |Running: )|runtime error" "$run/$t-regressions.log" | head -20 || true
    echo "  log: $run/$t-regressions.log"
    failed+=("$t")
    continue
  fi
  # -timeout: one input taking over 10 s is a hang; -rss_limit_mb: more than
  # 2 GB is a crash (out-of-memory); leaks are crashes (LeakSanitizer).
  if build-fuzz/tests/fuzz/$t -seed="$seed" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
       -dict="tests/fuzz/${dict[$t]}" -artifact_prefix="build-fuzz/artifacts/$t-" "$run/$t" >"$log" 2>&1; then
    execs=$(awk '/stat::number_of_executed_units/ {print $2}' "$log")
    echo "$t: ok, ${execs:-?} executions in ${secs} s (seed $(awk '/INFO: Seed:/ {print $3; exit}' "$log"))"
  else
    echo "$t: FAILED"
    grep -E "^(==[0-9]+==ERROR|SUMMARY|$t: )|runtime error|Test unit written" "$log" | head -20 || true
    echo "  log: $log; reproduce: build-fuzz/tests/fuzz/$t build-fuzz/artifacts/$t-<file>"
    failed+=("$t")
  fi
done
if ((${#failed[@]})); then
  echo "fuzz.sh: ${#failed[@]} target(s) failed: ${failed[*]}" >&2
  exit 1
fi
