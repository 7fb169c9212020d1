#!/usr/bin/env python3
"""The Triangle Stream Link's stall latency, restart and stall anatomy.

On the built-in scene, over ICC counts, FIFO depths, stall latencies and
resume occupancies (the engines' equality on them is tests/equivalence_modes.py):
  1. the anatomy adds up: its bins sum to the FIFO-held cycles, at most the
     link's stalled cycles; the cycles one ICC alone held the link sum, over
     the ICCs, to the first bin; every ICC's alone cycles are at most its
     held cycles; the ICCs' held cycles lie between the bins' lower and upper
     bounds; with one ICC every held cycle is its alone;
  2. a stall latency L never lets a Triangle FIFO overflow (largest
     occupancy at most the depth), and a FIFO that held the link reached
     depth - L entries;
  3. a hysteresis (resume occupancy 0) holds the link in longer stretches:
     no fewer FIFO-held cycles per stop than without it, on the same point."""
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from testlib import FOLLOW_WORKLOAD, Checks

raplas = sys.argv[1]
SCENE = ["--set", "image.width=24", "--set", "image.height=24", "--set", "groups.size=4", "--set",
         "groups.shadow_size=4", "--set", "builtin_detail=2"]
check = Checks()


def bounds(name):  # "1", "2", "3-4", ...: the bin's smallest and largest holder count
    lo, _, hi = name.partition("-")
    return int(lo), int(hi or lo)


def simulate(tmp, trace, *args):
    out = os.path.join(tmp, "out.json")
    subprocess.run([raplas, "simulate", "-q", "--trace", trace, "--config", "paper", *FOLLOW_WORKLOAD,
                    "--set", "sim.functional=trace", "--json", out, *args], check=True)
    with open(out) as f:
        return json.load(f)


with tempfile.TemporaryDirectory() as tmp:
    trace = os.path.join(tmp, "t.trace")
    subprocess.run([raplas, "trace", "-q", "--triangle-select", "any", "-o", trace, *SCENE], check=True)
    stops = {}
    for iccs, fifo, latency, resume in [(1, 10, 0, -1), (1, 10, 4, -1), (4, 10, 0, -1), (4, 10, 3, -1), (4, 10, 0, 0),
                                        (16, 5, 2, -1), (16, 5, 0, -1), (16, 5, 0, 0), (16, 100, 30, 20)]:
        what = f"{iccs} ICCs, FIFO {fifo}, latency {latency}, resume {resume}"
        j = simulate(tmp, trace, "--iccs", str(iccs), "--fifo", str(fifo), "--set", f"link.stall_latency={latency}",
                     "--set", f"link.resume_occupancy={resume}")
        a, icc = j["stall_anatomy"], j["iccs_detail"]
        bins = {b["iccs"]: b["cycles"] for b in a["held_by"]}
        held = [c["stall_cycles"]["link_blocked_triangle_fifo_full"] for c in icc]
        alone = [c["stall_cycles"]["link_blocked_triangle_fifo_alone"] for c in icc]
        check(sum(bins.values()) == a["fifo_held_cycles"] <= a["triangle_link_stall_cycles"] ==
              j["links"]["triangle"]["stall_cycles"], f"{what}: bins sum to the FIFO-held cycles, within the stalls")
        check(a["undecided_only_cycles"] == a["triangle_link_stall_cycles"] - a["fifo_held_cycles"],
              f"{what}: undecided-only cycles")
        check(sum(alone) == a["alone_cycles"] == bins["1"], f"{what}: alone cycles sum to the first bin")
        check(all(x <= y for x, y in zip(alone, held)), f"{what}: alone within held, per ICC")
        lo = sum(bounds(k)[0] * v for k, v in bins.items())
        hi = sum(bounds(k)[1] * v for k, v in bins.items())
        check(lo <= sum(held) == a["icc_held_cycles"] <= hi, f"{what}: ICC-held cycles {sum(held)} in [{lo}, {hi}]")
        if iccs == 1:
            check(alone == held and bins["1"] == a["fifo_held_cycles"], f"{what}: one ICC holds alone")
        occ = [c["triangle_fifo"]["max_occupancy"] for c in icc]
        check(all(o <= fifo for o in occ), f"{what}: no Triangle FIFO overflows (largest {max(occ)})")
        check(all(o >= fifo - latency for o, h in zip(occ, held) if h), f"{what}: a FIFO that held reached depth - L")
        if resume == 0 or (iccs, fifo, latency, resume) in [(4, 10, 0, -1), (16, 5, 0, -1)]:
            stops[(iccs, fifo, resume)] = a["fifo_held_cycles"]
    for iccs, fifo in [(4, 10), (16, 5)]:
        check(stops[(iccs, fifo, 0)] >= stops[(iccs, fifo, -1)],
              f"{iccs} ICCs, FIFO {fifo}: drained to 0 before restarting, the link is held no less "
              f"({stops[(iccs, fifo, 0)]} against {stops[(iccs, fifo, -1)]} cycles)")
    # at 16 ICCs the FIFOs of several ICCs hold the link together in some cycles
    j = simulate(tmp, trace, "--iccs", "16", "--fifo", "2")
    check(j["stall_anatomy"]["mean_holders"] > 1, f"16 ICCs, FIFO 2: stalls overlap (mean holders "
          f"{j['stall_anatomy']['mean_holders']:.2f})")
check.finish()
