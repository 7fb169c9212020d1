#!/usr/bin/env bash
# Full check that sphere culling changes nothing: for every scene file given
# (default: every shipped scene whose mesh is present), writes the profile
# trace with and without culling (`--no-cull`) and compares them byte for
# byte: every group's plane-hit records, counts and nearest hits. Extra
# arguments after `--` go to both runs (e.g. -- --format fp1-8-15).
#   tools/check_culling.sh [build/raplas] [scenes/x.toml ...] [-- extra args]
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
status=0
for s in "${scenes[@]}"; do
  name=$(basename "$s" .toml)
  if ! "$raplas" trace --scene "$s" --out "$tmp/$name.cull.trace" -q "${extra[@]}" 2>"$tmp/err"; then
    echo "$name: skipped ($(head -1 "$tmp/err"))"
    continue
  fi
  "$raplas" trace --scene "$s" --out "$tmp/$name.full.trace" -q --no-cull "${extra[@]}"
  if cmp -s "$tmp/$name.cull.trace" "$tmp/$name.full.trace"; then
    echo "$name: identical traces ($(stat -c %s "$tmp/$name.full.trace") bytes)"
  else
    echo "$name: TRACES DIFFER"
    status=1
  fi
done
exit $status
