#!/usr/bin/env python3
"""Smoke test: `raplas simulate` on the built-in scene and every shipped scene
(16x16 pixels to stay fast) with every shipped config exits 0, writes its
JSON, and reports functional_match. The shipped scenes need ../shared/scenes
(testlib: a skip when missing, a failure under CI=true)."""
import glob
import json
import os
import subprocess
import sys
import tempfile

from testlib import finish, need_shared

raplas, root = sys.argv[1], os.path.abspath(sys.argv[2])
scenes = [("built-in", [])]
if need_shared(root):
    scenes += [(os.path.basename(s), ["--scene", s]) for s in sorted(glob.glob(os.path.join(root, "scenes", "*.toml")))]
failures = 0
with tempfile.TemporaryDirectory() as tmp:
    for scene, scene_args in scenes:
        for config in sorted(glob.glob(os.path.join(root, "configs", "*.toml"))):
            name = f"{scene} x {os.path.basename(config)}"
            out = os.path.join(tmp, "out.json")
            cmd = [raplas, "simulate", "--config", config, "--iccs", "16", "--set", "image.width=16",
                   "--set", "image.height=16", "--json", out, "-q"] + scene_args
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
finish(failures)
