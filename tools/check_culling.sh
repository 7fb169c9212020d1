#!/usr/bin/env bash
# Full check that sphere culling changes nothing: for every scene file given
# (default: every shipped scene), writes the profile trace with and without
# culling (`--no-cull`), for both Triangle Selector readings (`both`, and
# `any`, whose trace also carries the spheres cut by row planes only or
# column planes only), and compares them byte for byte: every group's
# plane-hit records, pair-less spheres, counts and nearest hits. Extra
# arguments after `--` go to every run (e.g. -- --format fp1-8-15).
#   tools/check_culling.sh [build/raplas] [scenes/x.toml ...] [-- extra args]
# Exit 0: identical everywhere; 1: a difference or a failed run; 77: a scene's
# mesh is missing (ctest counts it as skipped), unless CI=true, where a
# missing mesh fails the check.
set -euo pipefail
cd "$(dirname "$0")/.."
raplas=build/raplas
if [[ $# -gt 0 && -x "$1" && ! -d "$1" ]]; then raplas=$1; shift; fi
scenes=() extra=()
while [[ $# -gt 0 ]]; do
  if [[ $1 == -- ]]; then shift; extra=("$@"); break; fi
  scenes+=("$1"); shift
done
[[ ${#scenes[@]} -gt 0 ]] || scenes=(scenes/*.toml)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0 missing=0
for s in "${scenes[@]}"; do
  name=$(basename "$s" .toml)
  # A scene whose mesh file is not there is a skip, never a silent pass.
  if ! "$raplas" trace --scene "$s" --set image.width=1 --set image.height=1 --out "$tmp/probe.trace" -q 2>"$tmp/err"; then
    if grep -q "cannot open\|not found\|No such file" "$tmp/err"; then
      echo "$name: SKIPPED, mesh missing ($(head -1 "$tmp/err"))"
      missing=1
    else
      echo "$name: FAILED ($(head -1 "$tmp/err"))"
      status=1
    fi
    continue
  fi
  for reading in both any; do
    run() {  # run OUT [--no-cull]
      local out=$1; shift
      if ! "$raplas" trace --scene "$s" --triangle-select "$reading" --out "$out" -q "$@" "${extra[@]}" 2>"$tmp/err"; then
        echo "$name ($reading): FAILED ($(grep -v 'warning' "$tmp/err" | head -1))"
        return 1
      fi
    }
    if ! run "$tmp/$name.cull.trace" || ! run "$tmp/$name.full.trace" --no-cull; then
      status=1
      continue
    fi
    if cmp -s "$tmp/$name.cull.trace" "$tmp/$name.full.trace"; then
      echo "$name ($reading): identical traces ($(stat -c %s "$tmp/$name.full.trace") bytes)"
    else
      echo "$name ($reading): TRACES DIFFER"
      status=1
    fi
  done
done
if [[ $status -eq 0 && $missing -ne 0 ]]; then
  if [[ ${CI:-} == true ]]; then
    echo "check_culling: meshes missing under CI=true"
    exit 1
  fi
  exit 77
fi
exit $status
