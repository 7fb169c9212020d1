#!/usr/bin/env python3
"""The RTL co-simulation check (docs/MODEL.md §2, "RTL co-simulation"):
sim.rtl = triangle_selector (the Verilog Triangle Selector and Triangle FIFO
of rtl/, Verilated) must give exactly what the netlist gives with the C++
block: every figure of `raplas simulate --json` but wall-clock ones, the
provenance but for sim.rtl (config_hash included: sim.rtl is result-neutral),
and functional_match, on the built-in scene and the small bunny over Triangle
FIFO depths from 1 up, 1 to 4 ICCs, both stall policies, the Ray Data
Fetcher's multi-entry pops (several RTI pipes, pair-less triangles dropped at
no cost) and overlapped passes. Then the broken variant built beside the RTL
(sim.fault = rtl_full_early: its full flag one entry early) must be caught:
the same comparison has to report differing figures.

Arguments: RAPLAS ROOT HAVE_RTL (ON/OFF: whether the build has the RTL)
[SCENES: comma-separated small scenes, default builtin,bunny_small; the
sanitizer build checks the built-in scene only].
Without the RTL, or without the shared scenes the small bunny needs, it says
SKIP and exits 77 (ctest: skipped); under CI=true either is a failure."""
import json
import os
import subprocess
import sys
import tempfile

from testlib import PROVENANCE, finish, in_ci, json_diff, provenance_diff, report, small_scenes, SKIP_EXIT, FOLLOW_WORKLOAD

raplas, root, have_rtl = sys.argv[1], os.path.abspath(sys.argv[2]), sys.argv[3]
scenes = (sys.argv[4] if len(sys.argv) > 4 else "builtin,bunny_small").split(",")
if have_rtl.upper() not in ("ON", "1", "TRUE", "YES"):
    if in_ci():
        print("FAIL: this build has no RTL co-simulation (Verilator was not found), and CI=true needs it")
        sys.exit(1)
    print("SKIP: this build has no RTL co-simulation (Verilator was not found: tools/install-deps.sh installs it)")
    sys.exit(SKIP_EXIT)

SKIP = {"wall"} | PROVENANCE
RTL = ["--set", "sim.rtl=triangle_selector"]
# (ICCs, Triangle FIFO depth, further settings): FIFO depths 1 to 1000, 1 to 4
# ICCs; the PlaneID FIFO shallow enough to hold the PSI now and then.
GRID = [
    (1, 1, []),
    (1, 3, ["--set", "link.stall_policy=needed_full"]),
    (2, 1000, ["--set", "host.overlap_passes=true"]),
    (4, 1, ["--set", "fifo.planeid_depth=2"]),
    (4, 2, ["--set", "icc.rti_pipes=4", "--set", "icc.rdf_empty_cycles=0", "--set", "link.stall_policy=needed_full"]),
    (4, 10, ["--set", "icc.rti_pipes=2", "--set", "host.overlap_passes=true", "--set", "link.triangle_lag_cycles=7"]),
    (3, 2, ["--set", "icc.rdf_empty_cycles=3", "--set", "sim.functional=trace"]),
]
# Where the broken variant must show: Triangle FIFOs that fill.
BROKEN = [(1, 3, []), (4, 2, [])]

failures = checked = 0
with tempfile.TemporaryDirectory() as tmp:
    for name, args in small_scenes(root):
        if name not in scenes:
            continue
        trace = os.path.join(tmp, name + ".trace")
        subprocess.run([raplas, "trace", "--triangle-select", "any", "--out", trace, "-q"] + args, check=True)

        def simulate(cfg, tag):
            path = os.path.join(tmp, tag + ".json")
            subprocess.run([raplas, "simulate", "--trace", trace, "--config", "paper", *FOLLOW_WORKLOAD,
                            "--set", "sim.mode=netlist", "--json", path, "-q"] + cfg, check=True)
            return json.load(open(path))

        def compare(cpp, rtl):
            return json_diff(cpp, rtl, SKIP) + provenance_diff(cpp, rtl, {"sim.rtl"})

        for i, (iccs, fifo, more) in enumerate(GRID):
            cfg = ["--iccs", str(iccs), "--fifo", str(fifo),
                   "--set", f"icc.triangle_select={'any' if i % 2 == 0 else 'both'}"] + more
            cpp, rtl = simulate(cfg, "cpp"), simulate(cfg + RTL, "rtl")
            d = compare(cpp, rtl)
            if cpp["functional_checked"] and not (cpp["functional_match"] and rtl["functional_match"]):
                d.append(f"functional_match: {cpp['functional_match']} (C++), {rtl['functional_match']} (RTL)")
            checked += 1
            failures += report(name, cfg + RTL, d, cpp["total_cycles"])

        for iccs, fifo, more in BROKEN:
            cfg = ["--iccs", str(iccs), "--fifo", str(fifo)] + more
            cpp = simulate(cfg, "cpp")
            broken = simulate(cfg + RTL + ["--set", "sim.fault=rtl_full_early"], "broken")
            d = json_diff(cpp, broken, SKIP)  # (the provenance differs by sim.fault)
            checked += 1
            if d:
                print(f"ok   {name} {' '.join(cfg)} sim.fault=rtl_full_early caught, {len(d)} differences: "
                      f"{cpp['total_cycles']} cycles, {broken['total_cycles']} with the broken RTL; " + "; ".join(d[:3]))
            else:
                failures += 1
                print(f"FAIL {name} {' '.join(cfg)}: the broken RTL (sim.fault=rtl_full_early) gives the same figures")
print(f"{checked - failures} passed, {failures} failed")
finish(failures)
