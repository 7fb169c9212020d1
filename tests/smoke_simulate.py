#!/usr/bin/env python3
"""Smoke test: `raplas simulate` on every shipped scene with every shipped config
(16x16 pixels to stay fast) exits 0, writes its JSON, and reports functional_match."""
import glob
import json
import os
import subprocess
import sys
import tempfile

raplas, root = sys.argv[1], os.path.abspath(sys.argv[2])
shared = os.path.join(os.path.dirname(root), "shared", "scenes")
failures = 0
with tempfile.TemporaryDirectory() as tmp:
    for scene in sorted(glob.glob(os.path.join(root, "scenes", "*.toml"))):
        for config in sorted(glob.glob(os.path.join(root, "configs", "*.toml"))):
            name = f"{os.path.basename(scene)} x {os.path.basename(config)}"
            if not os.path.isdir(shared):
                print(f"skip {name}: no {shared}")
                continue
            out = os.path.join(tmp, "out.json")
            cmd = [raplas, "simulate", "--scene", scene, "--config", config, "--iccs", "16",
                   "--set", "image.width=16", "--set", "image.height=16", "--json", out, "-q"]
            p = subprocess.run(cmd, capture_output=True, text=True)
            if p.returncode != 0:
                print(f"FAIL {name}: exit {p.returncode}: {p.stderr.strip()}")
                failures += 1
                continue
            j = json.load(open(out))
            ok = j["functional_match"] and j["total_cycles"] > 0 and j["passes"] > 0
            print(f"{'ok  ' if ok else 'FAIL'} {name}: {j['total_cycles']} cycles, {j['passes']} passes, "
                  f"functional_match {j['functional_match']}")
            failures += not ok
print(f"{failures} failed")
sys.exit(1 if failures else 0)
