#!/usr/bin/env python3
"""sim.estimate = fifo_bound: over a seeded grid of scenes, ICC counts, FIFO
depths, per-pass host overheads, PSI pipe counts and stages, RTI pipe counts and stages, stall
policies, stall latencies and resume occupancies, triangle-stream lags, both Triangle Selector readings, the Ray
Data Fetcher's cycles on a triangle with no pair and overlapped passes,
  1. every pass's bound is at most the exact pass's cycles (with overlapped
     passes: every pass ends no later, counted from the start of the run);
  2. it equals them when no Triangle FIFO held the link and no PlaneID FIFO
     filled in the exact run (max occupancy below the depth, less the stall
     latency for a Triangle FIFO, in every ICC), and always when both FIFOs
     are deeper than two passes' triangles and spheres;
  3. the JSON says it is a lower bound and that nothing was checked, and the
     CSV's estimate column names the mode."""
import itertools
import json
import os
import random
import subprocess
import sys
import tempfile

from testlib import Checks, small_scenes, FOLLOW_WORKLOAD

raplas, root = sys.argv[1], os.path.abspath(sys.argv[2])
# configurations per scene: 4; the sanitizer build passes fewer (tests/CMakeLists.txt)
points_per_scene = int(sys.argv[3]) if len(sys.argv) > 3 else 4
scenes = small_scenes(root)


check = Checks()


def run(tmp, trace, args):
    path = os.path.join(tmp, "out.json")
    subprocess.run([raplas, "simulate", "--trace", trace, "--config", "paper", *FOLLOW_WORKLOAD, "--json", path, "-q"] + args, check=True)
    return json.load(open(path))


rng = random.Random(20071008)
with tempfile.TemporaryDirectory() as tmp:
    for name, args in scenes:
        trace = os.path.join(tmp, name + ".trace")
        subprocess.run([raplas, "trace", "--triangle-select", "any", "--out", trace, "-q"] + args, check=True)
        for i in range(points_per_scene):
            fifo = rng.choice([1, 2, 10, 100, 1000])
            policy = rng.choice(['any_full', 'needed_full'])
            latency = rng.choice([0, 2]) if policy == "any_full" and fifo > 2 else 0
            resume = rng.choice([-1, 0]) if fifo - latency > 1 else -1
            cfg = ["--iccs", str(rng.choice([1, 2, 5, 16])), "--set", f"fifo.triangle_depth={fifo}",
                   "--set", f"fifo.planeid_depth={rng.choice([1, 4, 1000])}",
                   "--set", f"fifo.sphere_depth={rng.choice([1, 10, 1000])}",
                   "--set", f"host.pass_overhead_cycles={rng.choice([0, 0, 5])}",
                   "--set", f"link.stall_policy={policy}",
                   "--set", f"link.stall_latency={latency}", "--set", f"link.resume_occupancy={resume}",
                   "--set", f"icc.psi_pipes={rng.choice([32, 8, 5])}",
                   "--set", f"icc.psi_stages={rng.choice([10, 3])}",
                   "--set", f"icc.rti_pipes={rng.choice([1, 2, 4])}",
                   "--set", f"icc.rti_stages={rng.choice([25, 4])}",
                   "--set", f"icc.triangle_select={'any' if i % 2 else 'both'}",
                   "--set", f"icc.rdf_empty_cycles={rng.choice([0, 1, 3])}",
                   "--set", f"link.triangle_lag_cycles={rng.choice([0, 7, 40])}",
                   "--set", f"host.overlap_passes={'true' if i % 4 >= 2 else 'false'}",
                   "--set", "sim.functional=trace"]
            what = f"{name} {' '.join(cfg)}"
            exact = run(tmp, trace, cfg)
            bound = run(tmp, trace, cfg + ["--set", "sim.estimate=fifo_bound"])
            e, b = exact["pass_cycles"], bound["pass_cycles"]
            check(len(e) == len(b) == exact["passes"], f"{what}: one bound per pass")
            if "host.overlap_passes=true" in cfg:
                # Overlapped passes start when the one before ends: the bound holds
                # for the end of every pass, counted from the start of the run.
                check(all(x <= y for x, y in zip(itertools.accumulate(b), itertools.accumulate(e))),
                      f"{what}: a pass ends later in the bound than in the exact run")
            else:
                check(all(x <= y for x, y in zip(b, e)), f"{what}: bound above the exact cycles of a pass")
            check(bound["total_cycles"] == sum(b) and bound["total_cycles"] <= exact["total_cycles"],
                  f"{what}: total {bound['total_cycles']} against exact {exact['total_cycles']}")
            # (a Triangle FIFO holds the link from depth - stall latency entries on)
            filled = any(c["triangle_fifo"]["max_occupancy"] >= c["triangle_fifo"]["depth"] - latency or
                         c["planeid_fifo"]["max_occupancy"] >= c["planeid_fifo"]["depth"]
                         for c in exact["iccs_detail"])
            if not filled:
                check(b == e, f"{what}: no FIFO filled, yet the bound differs from the exact count")
            est = bound.get("estimate", {})
            check(est.get("mode") == "fifo_bound" and est.get("lower_bound") is True, f"{what}: estimate block")
            check(not bound["functional_checked"], f"{what}: nothing is checked in fifo_bound")
            # Deep FIFOs: the exact run must equal the bound pass for pass.
            # (two passes' worth: with overlapped passes a FIFO holds the previous pass's triangles too)
            deep = 2 * max(exact["triangles"], exact["spheres"]) + 1
            deep_cfg = cfg + ["--set", f"fifo.triangle_depth={deep}", "--set", f"fifo.planeid_depth={deep}"]
            check(run(tmp, trace, deep_cfg)["pass_cycles"] == b, f"{what}: deep FIFOs, exact != bound")
            print(f"{what}: exact {exact['total_cycles']}, bound {bound['total_cycles']}"
                  f"{'' if filled else ' (no FIFO filled: equal)'}")

    # The CSV row says which kind of figure total_cycles is.
    csv_path = os.path.join(tmp, "out.csv")
    for est in ("exact", "sample_passes", "fifo_bound"):
        subprocess.run([raplas, "simulate", "--trace", os.path.join(tmp, "builtin.trace"), "--config", "paper", *FOLLOW_WORKLOAD, "-q",
                        "--set", f"sim.estimate={est}", "--csv", csv_path], check=True)
        header, row = open(csv_path).read().splitlines()
        cells = dict(zip(header.split(","), row.split(",")))
        check(cells.get("estimate") == est, f"CSV estimate column: {cells.get('estimate')} for sim.estimate={est}")

check.finish()
