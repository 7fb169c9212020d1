#!/usr/bin/env python3
"""sim.functional = trace (masks and hits read from the trace) and = compute
(the model's intersectors compute them, the default) must give the same
timing: over a seeded grid of scenes, number formats, ICC counts, FIFO
depths, both Triangle Selector readings and both engines, `raplas simulate`
gives identical JSON in the two modes apart from what only compute reports:
the functional check (functional_checked, functional_match, rays_checked) and
each ICC's RTI hits, which the trace mode does not compute (it reports 0)."""
import copy
import json
import os
import random
import subprocess
import sys
import tempfile

from testlib import PROVENANCE, engine_for, finish, json_diff, provenance_diff, report, small_scenes, FOLLOW_WORKLOAD

raplas, root = sys.argv[1], os.path.abspath(sys.argv[2])
points_per_trace = int(sys.argv[3]) if len(sys.argv) > 3 else 3
COMPUTE_ONLY = {"wall", "functional_checked", "functional_match", "rays_checked"} | PROVENANCE
FORMATS = ["float32", "fp1-8-15", "float64"]


def without_rti_hits(j):
    j = copy.deepcopy(j)
    for icc in j["iccs_detail"]:
        del icc["rti"]["hits"]
    return j


rng = random.Random(20071008)
failures = points = 0
with tempfile.TemporaryDirectory() as tmp:
    for name, args in small_scenes(root):
        for fmt in FORMATS:
            trace = os.path.join(tmp, f"{name}-{fmt}.trace")
            subprocess.run([raplas, "trace", "--triangle-select", "any", "--format", fmt, "--out", trace, "-q"] + args,
                           check=True)
            for i in range(points_per_trace):
                cfg = ["--iccs", str(rng.choice([1, 2, 5, 16])), "--fifo", str(rng.choice([1, 3, 10, 100, 1000])),
                       "--set", f"icc.triangle_select={rng.choice(['any', 'both'])}",
                       "--set", f"sim.mode={engine_for(name, rng.choice(['netlist', 'event']))}",
                       "--set", f"numerics.format={fmt}"]
                out = {}
                for mode in ("compute", "trace"):
                    path = os.path.join(tmp, mode + ".json")
                    subprocess.run([raplas, "simulate", "--trace", trace, "--config", "paper", *FOLLOW_WORKLOAD, "--set",
                                    f"sim.functional={mode}", "--json", path, "-q"] + cfg, check=True)
                    out[mode] = json.load(open(path))
                c, t = out["compute"], out["trace"]
                d = json_diff(without_rti_hits(c), without_rti_hits(t), COMPUTE_ONLY)
                d += provenance_diff(c, t, {"sim.functional"})
                # what only compute reports is there, and says what it should
                if not (c["functional_checked"] and c["functional_match"] and c["rays_checked"] > 0):
                    d.append(f"compute: functional check {c['functional_checked']}/{c['functional_match']}")
                if t["functional_checked"] or t["rays_checked"] != 0:
                    d.append("trace: claims a functional check")
                hits = sum(icc["rti"]["hits"] for icc in c["iccs_detail"])
                if hits == 0 or any(icc["rti"]["hits"] for icc in t["iccs_detail"]):
                    d.append(f"RTI hits: compute {hits}, trace not 0")
                points += 1
                failures += report(name, cfg, d, c["total_cycles"])
print(f"{points - failures} passed, {failures} failed")
finish(failures)
