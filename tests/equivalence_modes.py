#!/usr/bin/env python3
"""sim.mode=event must give exactly the results of the reference,
sim.mode=netlist (the SystemC netlist): every figure of `raplas simulate --json`
except wall-clock ones (every key present in either JSON, and the provenance
but for sim.mode), over a seeded grid of scenes, ICC counts, Triangle, Sphere
and PlaneID FIFO depths, per-pass host overheads, SystemC sync intervals, stall
policies, PSI pipe counts and stages, RTI pipe counts and stages,
triangle-stream lags, stall latencies and resume occupancies, both Triangle Selector readings, the Ray Data Fetcher's
cycles on a triangle with no pair, overlapped passes, both functional modes
and the group orders, at two points of the `paper` machine's own FIFO depths, and (but on the sports car) at three of
a lone ICC (or two) under the any-plane reading with shallow Sphere and PlaneID FIFOs. Each
scene's trace carries the pair-less spheres (it serves both readings); a trace
made for the row-and-column reading alone must give the same JSON under that
reading.

Arguments: RAPLAS ROOT [POINTS_PER_SCENE [REFERENCE_MODE [SCENES]]]: the
reference defaults to netlist; SCENES is a comma-separated list of small-scene
names, each optionally with its own number of points (builtin:30,sportscar:3;
default: every small scene, POINTS_PER_SCENE each)."""
import json
import os
import random
import subprocess
import sys
import tempfile

from testlib import PROVENANCE, finish, json_diff, provenance_diff, report, small_scenes, FOLLOW_WORKLOAD, NETLIST_SLOW

raplas, root = sys.argv[1], os.path.abspath(sys.argv[2])
# configurations per scene: 10; the sanitizer build passes fewer (tests/CMakeLists.txt)
points_per_scene = int(sys.argv[3]) if len(sys.argv) > 3 else 10
reference = sys.argv[4] if len(sys.argv) > 4 else "netlist"
SKIP = {"wall"} | PROVENANCE
scenes = small_scenes(root)
points = {name: points_per_scene for name, _ in scenes}
if len(sys.argv) > 5:
    wanted = dict((w.split(":") + [str(points_per_scene)])[:2] for w in sys.argv[5].split(","))
    scenes = [s for s in scenes if s[0] in wanted]
    points = {name: int(n) for name, n in wanted.items()}


rng = random.Random(20071007)
failures = checked = 0
with tempfile.TemporaryDirectory() as tmp:
    for name, args in scenes:
        trace = os.path.join(tmp, name + ".trace")
        subprocess.run([raplas, "trace", "--triangle-select", "any", "--out", trace, "-q"] + args, check=True)
        both_trace = os.path.join(tmp, name + "-both.trace")
        subprocess.run([raplas, "trace", "--out", both_trace, "-q"] + args, check=True)

        def simulate(trace_file, mode, cfg):
            path = os.path.join(tmp, mode + ".json")
            subprocess.run([raplas, "simulate", "--trace", trace_file, "--config", "paper", *FOLLOW_WORKLOAD, "--set", f"sim.mode={mode}",
                            "--json", path, "-q"] + cfg, check=True)
            return json.load(open(path))

        def check(cfg, with_both_trace):
            global failures, checked
            out = {mode: simulate(trace, mode, cfg) for mode in (reference, "event")}
            d = json_diff(out[reference], out["event"], SKIP) + provenance_diff(out[reference], out["event"], {"sim.mode"})
            if with_both_trace:  # the row-and-column trace gives the same figures under its reading
                d += [f"both-trace {x}" for x in json_diff(out["event"], simulate(both_trace, "event", cfg), SKIP)]
            checked += 1
            failures += report(name, cfg, d, out[reference]["total_cycles"])

        for i in range(points[name]):
            fifo = rng.choice([1, 2, 3, 10, 100, 1000])
            policy = rng.choice(['any_full', 'needed_full'])
            # the stall latency (any_full only, below the depth) and the resume occupancy (below depth - latency)
            latency = rng.choice([0, 0, 1, 3]) if policy == "any_full" else 0
            latency = latency if latency < fifo else 0
            resume = rng.choice([-1, -1, 0, (fifo - latency) // 2])
            resume = resume if resume < fifo - latency - 1 else -1
            check(["--iccs", str(rng.choice([1, 2, 3, 5, 16])), "--set", f"fifo.triangle_depth={fifo}",
                   "--set", f"link.stall_latency={latency}", "--set", f"link.resume_occupancy={resume}",
                   "--set", f"fifo.planeid_depth={rng.choice([1, 2, 16])}",
                   "--set", f"fifo.sphere_depth={rng.choice([1, 3, 1000])}",
                   "--set", f"host.pass_overhead_cycles={rng.choice([0, 0, 5])}",
                   "--set", f"sim.sync_cycles={rng.choice([4096, 333])}",
                   "--set", f"link.stall_policy={policy}",
                   "--set", f"icc.psi_pipes={rng.choice([32, 32, 8, 5])}",
                   "--set", f"icc.psi_stages={rng.choice([10, 10, 3])}",
                   "--set", f"icc.rti_pipes={rng.choice([1, 1, 2, 4])}",
                   "--set", f"icc.rti_stages={rng.choice([25, 25, 4])}",
                   "--set", f"icc.triangle_select={'any' if i % 2 else 'both'}",
                   "--set", f"icc.rdf_empty_cycles={rng.choice([0, 1, 1, 3])}",
                   "--set", f"link.triangle_lag_cycles={rng.choice([0, 0, 7, 40])}",
                   "--set", f"host.overlap_passes={'true' if i % 4 >= 2 else 'false'}",
                   "--set", f"sim.functional={rng.choice(['compute', 'trace'])}",
                   "--set", f"workload.group_order={rng.choice(['pixel', 'pixel', 'random', 'morton', 'strided'])}"],
                  i == 0)
        # the `paper` machine's own FIFO depths (its 1000-deep PlaneID FIFO too), besides the random grid
        check(["--iccs", "4", "--fifo", "1000", "--set", "sim.functional=trace"], False)
        check(["--iccs", "16", "--fifo", "100", "--set", "sim.functional=compute"], False)
        # a lone ICC under the any-plane reading with shallow Sphere and PlaneID FIFOs: its front end
        # counted, the cycles it holds with its Sphere FIFO full or filling jumped (models/event_engine.cpp, 8.);
        # the scenes the netlist runs in seconds
        for iccs, tri, sphere in (() if name in NETLIST_SLOW else ((1, 1000, 1), (1, 16, 3), (2, 1000, 2))):
            check(["--iccs", str(iccs), "--set", f"fifo.triangle_depth={tri}", "--set", f"fifo.sphere_depth={sphere}",
                   "--set", "fifo.planeid_depth=2", "--set", "icc.triangle_select=any", "--set", "sim.functional=trace"],
                  False)
print(f"{checked - failures} passed, {failures} failed")
finish(failures)
