#!/usr/bin/env python3
"""sim.estimate = sample_passes: the sampled passes' cycle counts equal the
exact run's for the same passes (passes are independent), the extrapolation
is N times the sample mean plus the primary passes, the 95 % half-width is
the finite-population one, and a fraction of 1 is the exact run."""
import json
import math
import os
import subprocess
import sys
import tempfile

from testlib import Checks, PROVENANCE, provenance_diff, FOLLOW_WORKLOAD

raplas = sys.argv[1]
base = ["simulate", "--config", "paper", *FOLLOW_WORKLOAD, "--iccs", "4", "--fifo", "10",
        "--set", "image.width=40", "--set", "image.height=32", "--set", "groups.shadow_size=4", "-q"]


def run(tmp, *extra):
    out = os.path.join(tmp, "out.json")
    subprocess.run([raplas, *base, *extra, "--json", out], check=True)
    j = json.load(open(out))
    for k in ("wall", "sim_cycles_per_second", "sim_icc_cycles_per_second"):  # wall-clock figures
        j.pop(k, None)
    return j


check = Checks()


with tempfile.TemporaryDirectory() as tmp:
    exact = run(tmp)
    passes, primary_passes = exact["passes"], exact["primary_passes"]
    check("estimate" not in exact and len(exact["pass_cycles"]) == passes, "exact run simulates every pass")
    full = run(tmp, "--set", "sim.estimate=sample_passes", "--set", "sim.sample_fraction=1")
    d = provenance_diff(full, exact, {"sim.estimate", "sim.sample_fraction"})
    check(not d, "fraction 1: only the estimate keys differ in the config " + "; ".join(d))
    def without_provenance(j):
        return {k: v for k, v in j.items() if k not in PROVENANCE}
    check(without_provenance(full) == without_provenance(exact), "fraction 1 gives the exact run")
    for frac, seed in ((0.1, 1), (0.1, 7), (0.25, 3)):
        j = run(tmp, "--set", "sim.estimate=sample_passes", "--set", f"sim.sample_fraction={frac}",
                "--set", f"sim.sample_seed={seed}")
        e = j["estimate"]
        idx, cyc = e["pass_index"], j["pass_cycles"]
        shadow_n = passes - primary_passes
        n = math.ceil(frac * shadow_n)
        check(idx[:primary_passes] == list(range(primary_passes)), f"{frac}/{seed}: every primary pass simulated")
        check(len(idx) == primary_passes + n and idx == sorted(set(idx)), f"{frac}/{seed}: {n} distinct shadow passes")
        check(all(exact["pass_cycles"][i] == c for i, c in zip(idx, cyc)),
              f"{frac}/{seed}: sampled passes have the exact run's cycle counts")
        prim = sum(cyc[:primary_passes])
        sample = cyc[primary_passes:]
        mean = sum(sample) / n
        var = sum((c - mean) ** 2 for c in sample) / (n - 1)
        want = prim + round(shadow_n * mean)
        ci = 1.96 * shadow_n * math.sqrt(var / n) * math.sqrt(1 - n / shadow_n)
        check(j["total_cycles"] == want, f"{frac}/{seed}: total = primary + N * mean ({want})")
        check(abs(e["ci95_cycles"] - ci) <= 1e-6 * max(1.0, ci), f"{frac}/{seed}: 95 % half-width {ci:.0f}")
        # The front end tracing only the sampled passes' shadow groups: the
        # same passes, cycles and estimate; the workload covers the traced groups.
        k = run(tmp, "--set", "sim.estimate=sample_passes", "--set", f"sim.sample_fraction={frac}",
                "--set", f"sim.sample_seed={seed}", "--sample-front-end")
        same = ("total_cycles", "pass_cycles", "estimate", "ray_groups", "passes", "functional_match", "rays_checked",
                "iccs_detail", "links")
        check(all(k[x] == j[x] for x in same), f"{frac}/{seed}: --sample-front-end: the same passes and estimate")
        groups = exact["ray_groups"] - exact["primary_groups"]
        iccs = len(exact["iccs_detail"])
        traced = sum(min(iccs, groups - (i - primary_passes) * iccs) for i in idx[primary_passes:])
        check(k["untraced_groups"] == groups - traced and "untraced_groups" not in j,
              f"{frac}/{seed}: --sample-front-end leaves {groups - traced} shadow groups untraced")
        check(k["workload"]["ray_triangle_tests"] < j["workload"]["ray_triangle_tests"] and
              k["workload_hash"] != j["workload_hash"], f"{frac}/{seed}: its workload covers the traced groups")
        err = (j["total_cycles"] - exact["total_cycles"]) / exact["total_cycles"]
        print(f"     error {100 * err:+.2f} % (exact {exact['total_cycles']}), half-width {100 * ci / exact['total_cycles']:.2f} %")
check.finish()
