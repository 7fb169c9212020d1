#!/usr/bin/env python3
"""The streamed simulation (the front end hands each ray group to the model as
it is traced, a window of passes in memory) and the whole-frame one
(`--whole-frame`: the whole trace first) give the same JSON apart from `wall`:
over the small scenes, both engines, the estimates, both functional modes,
both Triangle Selector readings, overlapped passes, shards, 1 to 3 front-end
threads and the smallest window (2 passes). A point also checks that the
streamed run's JSON is the same with another thread count and window.
A trace (`simulate --trace`) is read block by block the same way: read
whole, streamed from the file and from a pipe, it gives the same JSON; a
block damaged late in the stream, or a pipe that ends early, stops the run
with one line and exit 2 after the passes before it, and writes no JSON."""
import json
import struct
import os
import random
import subprocess
import sys
import tempfile

from testlib import engine_for, finish, json_diff, small_scenes, FOLLOW_WORKLOAD

raplas, root = sys.argv[1], os.path.abspath(sys.argv[2])
points_per_scene = int(sys.argv[3]) if len(sys.argv) > 3 else 6

# (machine settings, extra options); each point draws one and random ICC
# counts, FIFO depths, threads and windows.
VARIANTS = [
    (["sim.mode=netlist"], []),
    (["sim.mode=event"], []),
    (["sim.mode=event", "icc.triangle_select=any"], []),
    (["sim.mode=netlist", "icc.triangle_select=any", "sim.functional=trace"], []),
    (["sim.mode=event", "sim.functional=trace"], []),
    (["sim.estimate=fifo_bound"], []),
    (["sim.estimate=fifo_bound", "icc.triangle_select=any"], []),
    (["sim.estimate=sample_passes", "sim.sample_fraction=0.3"], []),
    (["host.overlap_passes=true", "sim.mode=event"], []),
    (["host.overlap_passes=true", "sim.mode=netlist", "icc.triangle_select=any"], []),
    (["sim.mode=event"], ["--shard", "1/3"]),
    (["sim.mode=netlist", "sim.fault=wrong_rti", "sim.fault_icc=1"], ["--shard", "0/2"]),
    (["sim.mode=event", "sim.fault=stuck_rti"], []),
]


def simulate(args, path, expect_ok=True):
    p = subprocess.run([raplas, "simulate", "-q", "--json", path] + args, capture_output=True, text=True)
    if expect_ok and p.returncode != 0:
        raise RuntimeError(f"raplas simulate {' '.join(args)}: exit {p.returncode}\n{p.stderr}")
    return p.returncode, json.load(open(path)) if os.path.exists(path) else None


# wall-clock figures: of a whole result ("wall") and of a shard's partial one
WALL = {"wall", "model_wall_s", "frontend_wall_s"}
rng = random.Random(20260125)
failures = points = 0
with tempfile.TemporaryDirectory() as tmp:
    for name, scene_args in small_scenes(root):
        for i in range(points_per_scene):
            sets, extra = VARIANTS[(i + len(name)) % len(VARIANTS)] if i < len(VARIANTS) else rng.choice(VARIANTS)
            iccs = rng.choice([2, 3, 5, 16]) if "sim.fault_icc=1" in sets else rng.choice([1, 2, 3, 5, 16])
            args = scene_args + ["--config", "paper", *FOLLOW_WORKLOAD, "--iccs", str(iccs), "--fifo", str(rng.choice([1, 3, 10, 1000]))]
            for s in sets:
                args += ["--set", "sim.mode=" + engine_for(name, s[9:]) if s.startswith("sim.mode=") else s]
            args += extra
            fault = any("fault" in s for s in sets)
            results = {}
            for label, opts in (("whole", ["--whole-frame"]),
                                ("streamed", ["--threads", str(rng.choice([1, 2, 3])), "--window", "2"]),
                                ("streamed again", ["--threads", str(rng.choice([1, 2, 3])), "--window", "5"])):
                path = os.path.join(tmp, f"{label}.json")
                if os.path.exists(path):
                    os.remove(path)
                code, j = simulate(args + opts, path, expect_ok=not fault)
                if j is not None:
                    j.pop("wall", None)
                results[label] = (code, j)
            points += 1
            for label in ("streamed", "streamed again"):
                d = [] if results[label][0] == results["whole"][0] else [f"exit {results[label][0]} != {results['whole'][0]}"]
                d += json_diff(results["whole"][1], results[label][1], WALL)
                if d:
                    failures += 1
                    print(f"FAIL {name} {' '.join(args)} ({label}):")
                    for line in d[:10]:
                        print("  " + line)
    # Traces, read whole, streamed from the file and from a pipe.
    for name, scene_args in small_scenes(root):
        trace = os.path.join(tmp, f"{name}.trace")
        subprocess.run([raplas, "trace", "-q", "-o", trace] + scene_args, check=True)
        data = open(trace, "rb").read()
        for sets in (["sim.mode=event"], ["sim.mode=netlist", "sim.functional=trace", "icc.triangle_select=both"],
                     ["sim.estimate=fifo_bound"]):
            args = ["--trace", trace, "--config", "paper", *FOLLOW_WORKLOAD, "--iccs", str(rng.choice([1, 3, 16])), "--fifo",
                    str(rng.choice([3, 1000]))]
            for x in sets:
                args += ["--set", "sim.mode=" + engine_for(name, x[9:]) if x.startswith("sim.mode=") else x]
            results = {}
            for label, opts, feed in (("whole", ["--whole-frame"], None), ("streamed", ["--window", "2"], None),
                                      ("piped", ["--window", "3"], data)):
                path = os.path.join(tmp, f"trace-{label}.json")
                if os.path.exists(path):
                    os.remove(path)
                a = list(args)
                if feed is not None:
                    a[1] = "/dev/stdin"
                p = subprocess.run([raplas, "simulate", "-q", "--json", path] + a + opts, input=feed,
                                   capture_output=True)
                j = json.load(open(path)) if p.returncode == 0 else None
                if j:
                    j.pop("wall", None)
                results[label] = j
            points += 1
            for label in ("streamed", "piped"):
                d = json_diff(results["whole"], results[label], WALL) if results["whole"] and results[label] else ["no result"]
                if d:
                    failures += 1
                    print(f"FAIL trace of {name} {' '.join(sets)} ({label}):")
                    for line in d[:10]:
                        print("  " + line)
        # The last GROUPS block damaged, and the stream cut before END: one line, exit 2, no JSON.
        blocks, at = [], 32
        while at + 20 <= len(data):
            kind, size = struct.unpack_from("<IQ", data, at)
            blocks.append((kind, at + 20, size))
            at += 20 + size
        kind, start, size = [b for b in blocks if b[0] == 2][-1]
        bad = bytearray(data)
        bad[start + size // 2] ^= 1
        for label, feed, want in (("damaged", bytes(bad), "checksum mismatch in GROUPS block"),
                                  ("cut", data[:start - 20], "without its END block")):
            path = os.path.join(tmp, f"{label}.json")
            p = subprocess.run([raplas, "simulate", "-q", "--json", path, "--trace", "/dev/stdin", "--iccs", "2"],
                               input=feed, capture_output=True, text=False)
            err = p.stderr.decode()
            ok = p.returncode == 2 and want in err and "stopped after" in err and err.count("\n") == 1 and \
                not os.path.exists(path)
            points += 1
            if not ok:
                failures += 1
                print(f"FAIL trace of {name}, {label}: exit {p.returncode}, {err!r}")
    print(f"{points} points, {failures} failures")
finish(failures)
