#!/usr/bin/env bash
# One command on a fresh Debian 12: install what is missing, build, and run
# the main job on the built-in scene (no file needed): render it
# (render.png, render.json), then simulate it on the paper's machine at 1 and
# 16 ICCs (sim-1.json, sim.json) and print what the simulator found.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build
./build/raplas render --out render.png --json render.json
echo
./build/raplas simulate --config paper --iccs 1 --json sim-1.json -q
./build/raplas simulate --config paper --iccs 16 --json sim.json
# The system python3 (Debian's; tools/install-deps.sh installs it), whatever comes first on PATH.
/usr/bin/python3 - sim-1.json sim.json <<'PY'
import json, sys
one, six = (json.load(open(p)) for p in sys.argv[1:3])
speedup = one["total_cycles"] / six["total_cycles"]
print()
print(f"RAPLAS ('paper' machine, {six['clock_mhz']:.0f} MHz) on the built-in scene, "
      f"{six['ray_groups']} ray groups:")
for j in (one, six):
    print(f"  {j['iccs']:>2} ICC{'s' if j['iccs'] > 1 else ' '}: {j['total_cycles']:>10,} cycles = "
          f"{j['time_ms']:.3f} ms, functional_match {str(j['functional_match']).lower()}")
print(f"  speedup at 16 ICCs: {speedup:.2f} ({speedup / 16 * 100:.0f} % efficiency)")
print("wrote render.png, render.json, sim-1.json and sim.json")
PY
