#!/usr/bin/env python3
"""The frames of an animated scene (docs/ANIMATION.md), on the built-in
animation at a small size:

- `simulate --frames A:B` gives, for each frame, the figures of
  `simulate --frame F` run alone (any --threads, --jobs), totals that are their
  sums and worst case, and a CSV row per frame;
- `render --frames` writes one PNG per frame, byte-identical to
  `render --frame F` alone with another --threads; the frames differ;
- `simulate --frames --emit-jobs` run through GNU parallel and merged equals
  the direct run; merge refuses a missing frame and a frame of another run.

GNU parallel missing: that part says SKIP (a failure under CI=true)."""
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import testlib  # noqa: E402
from testlib import Checks

raplas = os.path.abspath(sys.argv[1])
scene = ["--set", "image.width=24", "--set", "image.height=24", "--set", "groups.size=8", "--set",
         "groups.shadow_size=8", "--set", "builtin_detail=2"]
config = ["--iccs", "3", "--fifo", "8"]


check = Checks()


def run(args, cwd, expect=0):
    out = subprocess.run([raplas] + args, cwd=cwd, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    if out.returncode != expect:
        print(f"FAIL raplas {' '.join(args)}: exit {out.returncode}, expected {expect}\n{out.stderr}")
        sys.exit(1)
    return out


def load(path):
    with open(path) as f:
        return json.load(f)


def without_wall(j):
    j = json.loads(json.dumps(j))
    j.get("totals", {}).pop("wall", None)
    for f in j.get("frames", []):
        f.pop("wall", None)
    return j


with tempfile.TemporaryDirectory() as d:
    # simulate --frames against each frame alone
    run(["simulate", "--frames", "1:3", "--jobs", "2", "--json", "all.json", "--csv", "all.csv", "-q"] + scene + config, d)
    whole = load(os.path.join(d, "all.json"))
    frames = whole["frames"]
    check([f["frame"] for f in frames] == [1, 2, 3], "frames 1:3 give frames 1, 2, 3 in order")
    common = ["scene", "config", "overrides", "config_hash", "resolved_config", "iccs", "fifo_depth", "format",
              "triangle_select", "rdf_empty_cycles", "overlap_passes", "clock_mhz", "animation"]
    for f in frames:
        run(["simulate", "--frame", str(f["frame"]), "--threads", "1", "--json", "one.json", "-q"] + scene + config, d)
        one = load(os.path.join(d, "one.json"))
        same = all(f[k] == one[k] for k in one if k not in common + ["iccs_detail", "wall", "inputs"])
        same = same and all(whole[k] == one[k] for k in common)
        check(same, f"frame {f['frame']} of --frames equals simulate --frame {f['frame']} --threads 1 alone")
        check(abs(f["fps_at_clock"] * f["time_ms"] - 1e3) < 1e-6, f"frame {f['frame']}: fps_at_clock = 1000 / time_ms")
    t = whole["totals"]
    cycles = [f["total_cycles"] for f in frames]
    check(t["total_cycles"] == sum(cycles) and t["frames"] == 3, "totals: the frames' cycles summed")
    check(t["worst_frame_cycles"] == max(cycles) and frames[cycles.index(max(cycles))]["frame"] == t["worst_frame"],
          "totals: the worst frame is the one of most cycles")
    check(t["passes"] == sum(f["passes"] for f in frames) and t["ray_groups"] == sum(f["ray_groups"] for f in frames),
          "totals: passes and ray groups summed")
    check(len(set(cycles)) > 1, "the frames differ in cycles (the animation moves)")
    check(whole["animation"] == {"frames": 48, "fps": 24.0}, "the built-in animation: 48 frames at 24 frames/s")
    with open(os.path.join(d, "all.csv")) as fh:
        rows = list(csv.DictReader(fh))
    check([r["frame"] for r in rows] == ["1", "2", "3"] and [int(r["total_cycles"]) for r in rows] == cycles,
          "CSV: a row per frame with its cycles")

    # render --frames against render --frame, other threads
    run(["render", "--frames", "0:2", "--out", "r_%02d.png", "--threads", "2", "--json", "r.json", "-q"] + scene, d)
    imgs = []
    for f in range(3):
        run(["render", "--frame", str(f), "--out", "one.png", "--threads", "1", "-q"] + scene, d)
        with open(os.path.join(d, f"r_{f:02d}.png"), "rb") as a, open(os.path.join(d, "one.png"), "rb") as b:
            img = a.read()
            check(img == b.read(), f"render --frames: frame {f}'s PNG equals render --frame {f} --threads 1")
            imgs.append(img)
    check(len(set(imgs)) == 3, "the three frames' images differ")
    check([f["frame"] for f in load(os.path.join(d, "r.json"))["frames"]] == [0, 1, 2], "render JSON: a report per frame")
    run(["render", "--frames", "0:2", "--out", "g_%d.png", "--gif", "anim.gif", "-q"] + scene, d)
    with open(os.path.join(d, "anim.gif"), "rb") as fh:
        gif = fh.read()
    # one graphic control extension (the frame's delay) per frame, and the looping extension
    check(gif[:6] == b"GIF89a" and gif.count(b"\x21\xf9\x04") == 3 and b"NETSCAPE2.0" in gif,
          "render --frames 0:2 --gif: an animated GIF of 3 frames that loops")

    # merge refuses a missing frame and a frame of another run
    run(["simulate", "--frame", "1", "--json", "f1.json", "-q"] + scene + config, d)
    run(["simulate", "--frame", "3", "--json", "f3.json", "-q"] + scene + config, d)
    run(["simulate", "--frame", "2", "--json", "other.json", "-q", "--iccs", "2"] + scene, d)
    out = run(["merge", "f1.json", "f3.json", "--json", "m.json"], d, expect=2)
    check("frame 2 is missing" in out.stderr and not os.path.exists(os.path.join(d, "m.json")),
          "merge of frames 1 and 3: frame 2 missing, nothing written")
    out = run(["merge", "f1.json", "other.json", "--json", "m.json"], d, expect=2)
    check("another run" in out.stderr, "merge of frames of two runs refused")

    # a sweep of a still and an animated scene: a row per point, the animated one the totals of its frames
    with open(os.path.join(d, "still.toml"), "w") as fh:
        fh.write('name = "still"\n')
    with open(os.path.join(d, "anim.toml"), "w") as fh:
        fh.write('name = "anim"\n[animation]\nbuiltin = "default"\nframes = 3\n')
    run(["sweep", "--scene", "still.toml", "--scene", "anim.toml", "--iccs", "1,3", "--fifo", "8", "--out", "sw.csv",
         "-q"] + scene, d)
    with open(os.path.join(d, "sw.csv")) as fh:
        rows = list(csv.DictReader(fh))
    check(len(rows) == 4 and [r["scene"] for r in rows] == ["still", "still", "anim", "anim"], "sweep: 4 rows in order")
    for r in rows:
        if r["scene"] == "still":
            check(r["frames"] == "1" and r["worst_frame_cycles"] == r["total_cycles"],
                  f"sweep, still scene at {r['iccs']} ICCs: one frame, the worst is the run")
            continue
        run(["simulate", "--scene", "anim.toml", "--frames", "all", "--iccs", r["iccs"], "--fifo", "8", "--json",
             "a.json", "-q"] + scene, d)
        t = load(os.path.join(d, "a.json"))["totals"]
        check(r["frames"] == "3" and int(r["total_cycles"]) == t["total_cycles"] and int(r["passes"]) == t["passes"]
              and int(r["worst_frame"]) == t["worst_frame"] and int(r["worst_frame_cycles"]) == t["worst_frame_cycles"],
              f"sweep, animated scene at {r['iccs']} ICCs: the row holds the totals and the worst frame of --frames all")
    check(float(rows[3]["speedup"]) > 1, "sweep: the animation's speedup over its smallest ICC count")

    # the job list through GNU parallel
    if shutil.which("parallel"):
        run(["simulate", "--frames", "1:3", "--emit-jobs", "jobs.txt", "--json", "jobs.json", "--csv", "jobs.csv", "-q"]
            + scene + config, d)
        for cmd in ("parallel < jobs.txt", "sh jobs.txt.merge"):
            p = subprocess.run(cmd, shell=True, cwd=d, capture_output=True, text=True)
            if p.returncode:
                print(f"FAIL {cmd}: exit {p.returncode}\n{p.stderr}")
                sys.exit(1)
        check(without_wall(load(os.path.join(d, "jobs.json"))) == without_wall(whole),
              "--emit-jobs through GNU parallel, merged: the JSON of simulate --frames (but wall)")
    elif testlib.in_ci():
        check(False, "GNU parallel is missing, and CI=true needs it")
    else:
        print("SKIP: GNU parallel is missing: the job list was not run")

check.finish()
