#!/usr/bin/env python3
"""tools/experiments.py on a scene the project does not ship: tests/scenes/room.obj
(a room open at the front and the top, three boxes on its floor; 248 triangles,
made by make_room() below: `tests/experiments_any_scene.py --write-mesh PATH`).

  experiments_any_scene.py RAPLAS SOURCE_DIR

1. `experiments.py all --quick --mesh room.obj --out TMP`: every experiment that
   takes any scene writes its tables and plots into TMP (and its work files into
   TMP/work), and their numbers are sane: speedups of 1 at 1 ICC and at most the
   ICC count, the cycles those of `raplas simulate` run by hand on the same scene,
   efficiencies under the ceiling of unbounded FIFOs, fifo's answer for every
   combination of the open choices (FIFO_GRID) agreeing with the depths it tried
   and never falling as the ICC count rises, its SRAM the depth times the record
   bytes the model's area block counts, no marks against the paper (which has no
   figures for this scene) but the paper's Table 5 beside it, no Embree column
   (the benchmark knows the shipped scenes only), and so on.
2. `fig8 --quick --mesh room.obj --scene room.toml`: two scenes of one name are
   kept apart, each with the cycles of its own `raplas simulate`.
3. Bad input: one line on stderr, exit 2, nothing written.
"""
import csv
import importlib.util
import itertools
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from testlib import Checks


def make_room():
    """The OBJ text: a 2 x 1 x 2 room (floor, back, left and right walls; open at +z and at the
    top, so that the automatic camera, in front and above, sees into it) with three boxes."""
    v, f = [], []

    def quad(a, b, d, n):  # n x n grid on the parallelogram a, b = a + u, d = a + v
        base = len(v)
        for j in range(n + 1):
            for i in range(n + 1):
                s, t = i / n, j / n
                v.append(tuple(a[k] + s * (b[k] - a[k]) + t * (d[k] - a[k]) for k in range(3)))
        for j in range(n):
            for i in range(n):
                p = base + j * (n + 1) + i + 1
                f.append((p, p + 1, p + n + 2))
                f.append((p, p + n + 2, p + n + 1))

    quad((-1, 0, 1), (1, 0, 1), (-1, 0, -1), 4)      # floor
    quad((-1, 0, -1), (1, 0, -1), (-1, 1, -1), 4)    # back wall
    quad((-1, 0, 1), (-1, 0, -1), (-1, 1, 1), 4)     # left wall
    quad((1, 0, -1), (1, 0, 1), (1, 1, -1), 4)       # right wall

    def box(x0, z0, s, h, n=2):
        x1, z1 = x0 + s, z0 + s
        quad((x0, h, z1), (x1, h, z1), (x0, h, z0), n)
        quad((x0, 0, z1), (x1, 0, z1), (x0, h, z1), n)
        quad((x1, 0, z0), (x0, 0, z0), (x1, h, z0), n)
        quad((x0, 0, z0), (x0, 0, z1), (x0, h, z0), n)
        quad((x1, 0, z1), (x1, 0, z0), (x1, h, z1), n)

    box(-0.7, -0.6, 0.4, 0.5)
    box(0.2, -0.4, 0.5, 0.3)
    box(-0.1, 0.3, 0.3, 0.7)
    return ("# A room open at the front (+z) and the top, with three boxes: 248 triangles.\n"
            "# Made by tests/experiments_any_scene.py --write-mesh (make_room); public domain.\n" +
            "".join("v %g %g %g\n" % p for p in v) + "".join("f %d %d %d\n" % t for t in f))


if len(sys.argv) == 3 and sys.argv[1] == "--write-mesh":
    with open(sys.argv[2], "w") as fh:
        fh.write(make_room())
    sys.exit(0)

raplas, root = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
tool = os.path.join(root, "tools", "experiments.py")
spec = importlib.util.spec_from_file_location("experiments", tool)
exp = importlib.util.module_from_spec(spec)  # its grids (FIFO_GRID, QUICK_PLAN): main() does not run
spec.loader.exec_module(exp)
mesh = os.path.join(root, "tests", "scenes", "room.obj")
QUICK_SIZE, QUICK_ICCS, QUICK_FIFOS = 16, [1, 2, 4], [10, 1000]


check = Checks()


def experiments(args, cwd=None):
    return subprocess.run([sys.executable, tool, "--raplas", raplas] + args, capture_output=True, text=True, cwd=cwd)


def rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def simulate(args, iccs, fifo, sets=(), size=QUICK_SIZE, whole=False):
    """total_cycles of `raplas simulate` run by hand as the experiments' sweeps run it (with `whole`,
    its JSON)."""
    with tempfile.TemporaryDirectory() as d:
        js = os.path.join(d, "sim.json")
        cmd = [raplas, "simulate"] + args + ["--config", "paper", "--iccs", str(iccs), "--fifo", str(fifo),
                                             "--set", f"image.width={size}", "--set", f"image.height={size}",
                                             "--set", "sim.functional=trace", "-q", "--json", js]
        for x in sets:
            cmd += ["--set", x]
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode != 0:
            check(False, f"raplas simulate {' '.join(args)}: exit {p.returncode}: {p.stderr.strip()}")
            return None
        with open(js) as fh:
            j = json.load(fh)
            return j if whole else j["total_cycles"]


def config_value(key):
    """A key of `raplas simulate --config paper --dump-config`, as its TOML text."""
    out = subprocess.run([raplas, "simulate", "--config", "paper", "--dump-config"], capture_output=True,
                         text=True).stdout
    section = ""
    for line in out.splitlines():
        if line.startswith("["):
            section = line.strip("[] \n") + "."
        elif "=" in line and not line.startswith("#"):
            k, v = (x.strip() for x in line.split("=", 1))
            if section + k == key:
                return v.strip('"')
    return None


def close(a, b, rel=1e-3):
    return abs(a - b) <= rel * max(abs(a), abs(b), 1e-12)


check(open(mesh).read() == make_room(), f"{mesh} is what make_room() writes")

with tempfile.TemporaryDirectory() as tmp:
    out = os.path.join(tmp, "out")
    os.mkdir(out)
    p = experiments(["all", "--quick", "--mesh", mesh, "--out", out], cwd=tmp)
    if not check(p.returncode == 0, f"experiments.py all --quick --mesh room.obj: exit {p.returncode}"):
        print(p.stderr[-3000:])
        sys.exit(1)
    outputs = ["fig8.png", "fig8.csv", "fig8.md", "fig9.png", "fig9.csv", "fig9.md", "fig10.png", "fig10.csv",
               "fig10.md", "table5.csv", "table5.md", "table5_cpu.json", "beyond.png", "beyond.csv", "beyond.md",
               "crossover.csv", "fifo.png", "fifo.csv", "fifo.md", "fifo_points.csv", "readings.csv",
               "readings.md", "realtime.png", "realtime.csv", "realtime.md", "realtime_check.csv",
               "anatomy.png", "anatomy.csv", "anatomy.md",
               "sweeps/streaming.csv", "sweeps/shared.csv", "sweeps/distributed_rti.csv"]
    missing = [x for x in outputs if not os.path.isfile(os.path.join(out, x))]
    check(not missing, f"every table and plot is in --out ({len(outputs)} files; missing: {missing})")
    pngs = [x for x in outputs if x.endswith(".png") and x not in missing]
    badpng = [x for x in pngs if open(os.path.join(out, x), "rb").read(8) != b"\x89PNG\r\n\x1a\n"
              or os.path.getsize(os.path.join(out, x)) < 10000]
    check(not badpng, f"the plots are PNG images of some size ({len(pngs)}; bad: {badpng})")
    check(os.path.isdir(os.path.join(out, "work")), "the work files went to OUT/work (the default outside the checkout)")
    check(not os.path.exists(os.path.join(tmp, "work")) and set(os.listdir(tmp)) == {"out"},
          f"nothing was written beside --out ({sorted(os.listdir(tmp))})")
    if missing:
        sys.exit(1)

    # The sweep rows are the scene's: 248 triangles, the cycles raplas simulate gives by hand.
    sw = rows(os.path.join(out, "sweeps", "streaming.csv"))
    check(len(sw) == len(QUICK_ICCS) * len(QUICK_FIFOS) and all(r["triangles"] == "248" for r in sw),
          f"sweeps/streaming.csv: {len(sw)} rows of the 248-triangle room")
    f8 = rows(os.path.join(out, "fig8.csv"))
    by8 = {(int(r["iccs"]), int(r["fifo_depth"])): r for r in f8}
    check(set(by8) == {(k, f) for k in QUICK_ICCS for f in QUICK_FIFOS} and {r["scene"] for r in f8} == {"room"},
          f"fig8.csv: the room at ICCs {QUICK_ICCS} x FIFOs {QUICK_FIFOS}")
    for k in (1, 4):
        want = simulate(["--mesh", mesh], k, 1000)
        got = int(by8[(k, 1000)]["total_cycles"]) if (k, 1000) in by8 else None
        check(got == want, f"fig8.csv: {k} ICC(s), FIFO 1000: {got} cycles, raplas simulate by hand: {want}")
    for f in QUICK_FIFOS:
        sp = [float(by8[(k, f)]["speedup"]) for k in QUICK_ICCS]
        eff = [float(by8[(k, f)]["efficiency"]) for k in QUICK_ICCS]
        check(sp[0] == 1 and all(1 < s <= k + 1e-9 for s, k in zip(sp[1:], QUICK_ICCS[1:])) and
              all(a < b for a, b in zip(sp, sp[1:])) and all(0 < e <= 1 + 1e-9 for e in eff),
              f"fig8, FIFO {f}: speedups {sp} rise from 1 and stay at most the ICC count")
    for k in QUICK_ICCS:
        check(int(by8[(k, 10)]["total_cycles"]) >= int(by8[(k, 1000)]["total_cycles"]),
              f"fig8, {k} ICCs: FIFO 10 takes no fewer cycles than FIFO 1000")
    md = open(os.path.join(out, "fig8.md")).read()
    check("room" in md and "Scenes: room (`room.obj`); 16x16 pixels" in md and "over 90 %" in md,
          "fig8.md names the scene and its image, and the paper's result beside it")

    f9 = rows(os.path.join(out, "fig9.csv"))
    check(len(f9) == len(QUICK_ICCS) and all(0 < float(r[c]) < 1e3 for r in f9
                                              for c in ("ratio_demand_rti", "ratio_demand_ideal", "ratio_stream")),
          f"fig9.csv: {len(f9)} rows of positive area x time ratios")
    f10 = rows(os.path.join(out, "fig10.csv"))
    check(len(f10) == len(QUICK_ICCS) and all(int(r["shared_triangle_records"]) > 0 and
                                               int(r["streaming_cycles"]) == int(by8[(int(r["iccs"]), 1000)]["total_cycles"])
                                               for r in f10),
          "fig10.csv: the streaming cycles of fig8 over a shared memory that read triangles")

    t5 = rows(os.path.join(out, "table5.csv"))
    r = t5[0] if t5 else {}
    check(len(t5) == 1 and r.get("cycles_1") == by8[(1, 1000)]["total_cycles"] and
          r.get("cycles_4") == by8[(4, 1000)]["total_cycles"] and float(r["ms_1"]) > float(r["ms_4"]) > 0 and
          float(r["cpu_raplas_render_s"]) > 0,
          f"table5.csv: 1 and 4 ICCs of the room, the CPU render time ({r.get('cpu_raplas_render_s')} s)")
    check(r.get("cpu_embree_s") == "" and r.get("paper_ms_1") == "",
          "table5.csv: no Embree time (not a scene the benchmark knows) and no paper figures for the room")
    md = open(os.path.join(out, "table5.md")).read()
    check("Embree 3 not timed" in md and "318.6 ms" in md,
          "table5.md says why Embree is missing and shows the paper's Table 5 beside the room")

    be = rows(os.path.join(out, "beyond.csv"))
    cr = rows(os.path.join(out, "crossover.csv"))
    check({int(x["image"]) for x in be} == {16, 32} and len(cr) == 2 and max(int(x["iccs"]) for x in be) == 16,
          f"beyond.csv: 16x16 and 32x32 up to 16 ICCs ({len(be)} rows), crossover.csv: {len(cr)} rows")

    # fifo: every combination of the open choices (FIFO_GRID) x the quick plan's ICC counts, each
    # answer the smallest depth of the ladder reaching the target, consistent with the points tried.
    grid = [(key, [str(v).lower() if isinstance(v, bool) else str(v) for v in values])
            for key, values, _ in exp.FIFO_GRID]
    # (the combinations the model allows: a stall latency only under any_full)
    allowed = [x for x in itertools.product(*[v for _, v in grid])
               if exp.fifo_combination_allowed(dict(zip([k for k, _ in grid], x)))]
    combos = len(allowed)
    plan_k = {k: QUICK_SIZE * scale for k, scale in exp.QUICK_PLAN["fifo_iccs"]}
    ladder, target = exp.QUICK_PLAN["fifo_depths"], exp.QUICK_PLAN["fifo_target"]
    ans = rows(os.path.join(out, "fifo.csv"))
    pts = rows(os.path.join(out, "fifo_points.csv"))
    cells = {(a["combination"], int(a["iccs"])): a for a in ans}
    check(len(ans) == combos * len(plan_k) == len(cells) and
          {tuple(a[key] for key, _ in grid) for a in ans} == set(allowed) and all(int(a["image"]) == plan_k[int(a["iccs"])] for a in ans),
          f"fifo.csv: {len(ans)} answers, the {combos} combinations of {[k for k, _ in grid]} x ICCs "
          f"{sorted(plan_k)} on images {plan_k}")
    tried = {}
    for x in pts:
        tried.setdefault((x["combination"], int(x["iccs"])), {})[int(x["fifo_depth"])] = x
    check(all(abs(float(x["efficiency"]) - int(x["base_cycles"]) / int(x["total_cycles"]) / int(x["iccs"])) < 1e-4
              and (float(x["efficiency"]) >= target) == (x["meets_target"] == "True") and
              float(x["efficiency"]) <= float(cells[(x["combination"], int(x["iccs"]))]["ceiling_unbounded_fifos"])
              + 1e-3 for x in pts) and len(pts) > 0,
          f"fifo_points.csv: {len(pts)} points, each efficiency over its base, none above its ceiling")
    consistent, reached = True, 0
    for key, a in cells.items():
        t = tried.get(key, {})
        # the ladder's depths this combination allows at this ICC count (deeper than its stall latency)
        lad = [d for d in ladder if exp.fifo_depth_allowed({k: a[k] for k, _ in grid}, key[1], d)]
        d = int(a["smallest_depth"]) if a["smallest_depth"] else None
        if d is not None:
            reached += 1
            i = lad.index(d)
            ok = (d in t and t[d]["meets_target"] == "True" and
                  all(t[e]["meets_target"] == "False" for e in t if e < d) and
                  (i == 0 or lad[i - 1] in t) and a["limited_by"] == "" and all(e in lad for e in t))
        elif a["limited_by"] == "depth":
            ok = max(lad) in t and all(x["meets_target"] == "False" for x in t.values())
        else:
            ok = not t and float(a["ceiling_unbounded_fifos"]) < target and a["limited_by"] in (
                "group count", "RTI work", "triangle stream")
        if not ok:
            check(False, f"fifo.csv {key}: answer '{a['smallest_depth']}' ({a['limited_by']}) against the depths "
                         f"tried {sorted(t)}")
        consistent &= ok
    check(consistent and 0 < reached < len(cells),
          f"fifo.csv: every answer agrees with the depths tried ({reached} of {len(cells)} reach "
          f"{100 * target:.0f} %; the shallower ladder depth always tried, none meeting the target)")
    inf = float("inf")
    mono = []
    for name in {a["combination"] for a in ans}:
        ds = [int(cells[(name, k)]["smallest_depth"] or 0) or inf for k in sorted(plan_k)]
        if any(x > y for x, y in zip(ds, ds[1:])):
            mono.append((name, ds))
    check(not mono, f"fifo.csv: the smallest depth never falls as the ICC count rises (none = above every depth)"
                    f"{': ' + str(mono) if mono else ''}")
    entry = int(config_value("link.sphere_record_bytes")) + int(config_value("link.triangle_record_bytes"))
    check(all(int(a["entry_bytes"]) == entry and
              (a["sram_bytes_per_icc"] == "" if not a["smallest_depth"] else
               int(a["sram_bytes_per_icc"]) == int(a["smallest_depth"]) * entry ==
               int(a["sphere_fifo_bytes"]) + int(a["triangle_fifo_bytes"])) for a in ans) and
          all(int(x["sram_bytes_per_icc"]) == int(x["fifo_depth"]) * entry for x in pts),
          f"fifo.csv: SRAM per ICC = depth x {entry} bytes (sphere + triangle record, from --dump-config)")
    j = simulate(["--mesh", mesh], 1, 10, ["area.model=blocks", "sim.estimate=fifo_bound"], whole=True)
    if j:
        f = j["area"]["per_icc"]["fifos"]
        area_bytes = (f["sphere"] + f["triangle"]) / float(config_value("area.sram_byte"))
        check(abs(area_bytes - 10 * entry) < 1e-6,
              f"the model's area block prices a 10-deep Sphere and Triangle FIFO at {area_bytes:g} bytes (fifo: "
              f"{10 * entry})")
    # A key that cannot change a 1-ICC run (the group order) shares the base run among its values; the
    # default combination's base equals a random-order run by hand.
    changes = [key for key, _, one_icc in exp.FIFO_GRID if one_icc]
    bases = {}
    for a in ans:
        bases.setdefault((a["image"],) + tuple(a[key] for key in changes), set()).add(a["base_cycles"])
    default = cells[("default", min(plan_k))]
    by_hand = simulate(["--mesh", mesh], 1, max(ladder), ["workload.group_order=random"])
    check(all(len(v) == 1 for v in bases.values()) and by_hand == int(default["base_cycles"]),
          f"fifo: one base for every group order ({default['base_cycles']} cycles; random order by hand: {by_hand})")
    x = next(x for x in pts if x["combination"] == "default" and int(x["image"]) == 2 * QUICK_SIZE)
    by_hand = simulate(["--mesh", mesh], int(x["iccs"]), int(x["fifo_depth"]), size=2 * QUICK_SIZE)
    check(by_hand == int(x["total_cycles"]),
          f"fifo_points.csv: {x['iccs']} ICCs at FIFO {x['fifo_depth']} on {2 * QUICK_SIZE}x{2 * QUICK_SIZE}: "
          f"{x['total_cycles']} cycles, raplas simulate by hand: {by_hand}")
    md = open(os.path.join(out, "fifo.md")).read()
    check(md.count("\n| ") == combos + 1 and "40KB SRAM" in md and "none: ceiling" in md,
          "fifo.md: one row per combination, the paper's 40 KB beside the answers, the reason for each none")

    rd = rows(os.path.join(out, "readings.csv"))
    md = open(os.path.join(out, "readings.md")).read()
    check(len(rd) == 9 and all(x["scene"] == "room" for x in rd) and not any(m in md for m in ("✓", "✗", " ~")),
          f"readings: the 9 combinations for the room ({len(rd)} rows), no marks against the paper")
    # anatomy: every combination of ANATOMY_GRID and every workload change, at every FIFO depth; the
    # ratio and flat marks follow from the speedups; the anatomy's shares are shares; one speedup by hand.
    an = rows(os.path.join(out, "anatomy.csv"))
    an_combos = 1
    for _, v in exp.ANATOMY_GRID:
        an_combos *= len(v)
    k_mid, k_max = sorted(QUICK_ICCS)[-2], max(QUICK_ICCS)
    check(len(an) == (an_combos + len(exp.ANATOMY_WORKLOAD)) * len(QUICK_FIFOS),
          f"anatomy.csv: {len(an)} rows, ({an_combos} combinations + {len(exp.ANATOMY_WORKLOAD)} workload changes) x "
          f"{len(QUICK_FIFOS)} FIFO depths")
    bad = [x for x in an if abs(float(x["ratio"]) - float(x[f"speedup{k_max}"]) / float(x[f"speedup{k_mid}"])) > 0.01
           or (x["flat"] == "True") != (float(x["ratio"]) <= exp.FLAT)
           or not 0 <= float(x[f"held_share{k_max}"]) <= 1 or not 0 <= float(x[f"alone_share{k_max}"]) <= 1
           or (float(x[f"held_share{k_max}"]) > 0 and float(x[f"mean_holders{k_max}"]) < 1)]
    check(not bad, f"anatomy.csv: ratios, flat marks and shares consistent ({len(bad)} rows not)")
    x = next(x for x in an if x["what"] == "grid" and x["icc.triangle_select"] == "any" and
             x["link.stall_latency_per_icc"] != "0" and x["link.resume_occupancy"] == "0" and
             x["workload.group_order"] == "random" and int(x["fifo_depth"]) == min(QUICK_FIFOS))
    sets = [f"{k}={x[k]}" for k, _ in exp.ANATOMY_GRID]
    one = simulate(["--mesh", mesh], 1, max(QUICK_FIFOS), [s for s in sets if "per_icc" not in s and "order" not in s])
    most = simulate(["--mesh", mesh], k_max, min(QUICK_FIFOS), sets)
    check(one and most and abs(one / most - float(x[f"speedup{k_max}"])) < 0.001,
          f"anatomy.csv: the speedup at {k_max} ICCs, FIFO {min(QUICK_FIFOS)}, stall latency "
          f"{x['link.stall_latency_per_icc']} per ICC: {x[f'speedup{k_max}']}, by hand {one / most if most else 0:.3f}")
    rt = rows(os.path.join(out, "realtime.csv"))
    ck = rows(os.path.join(out, "realtime_check.csv"))
    check(len(rt) == 4 and all(float(x["frame_ms"]) > 0 and x["embree_rays_ms"] == "" for x in rt) and len(ck) == 2,
          f"realtime: {len(rt)} frame times, no Embree column, {len(ck)} checks of the estimate")

    # Two inputs of one name (the sweep's scene column says room for both), in order: a scene
    # file whose camera differs, beside the mesh.
    scene = os.path.join(tmp, "room.toml")
    with open(scene, "w") as fh:
        fh.write(f'name = "room"\nmesh = "{mesh}"\n\n[camera]\neye = [0.0, 0.8, 2.6]\nlook_at = [0.0, 0.3, 0.0]\n')
    out2 = os.path.join(tmp, "out2")
    os.mkdir(out2)
    p = experiments(["fig8", "--quick", "--mesh", mesh, "--scene", scene, "--out", out2])
    check(p.returncode == 0, f"fig8 --mesh room.obj --scene room.toml: exit {p.returncode}" +
          ("" if p.returncode == 0 else f": {p.stderr.strip().splitlines()[-1:]}"))
    f8 = rows(os.path.join(out2, "fig8.csv")) if p.returncode == 0 else []
    one = {x["scene"]: int(x["total_cycles"]) for x in f8 if x["iccs"] == "1" and x["fifo_depth"] == "1000"}
    want = {"room": simulate(["--mesh", mesh], 1, 1000), "room-2": simulate(["--scene", scene], 1, 1000)}
    check(one == want and want["room"] != want["room-2"],
          f"fig8.csv keeps the two rooms apart, in order: {one}, by hand {want}")

    # Bad input: one line, exit 2, nothing written.
    empty = os.path.join(tmp, "empty")
    os.mkdir(empty)
    afile = os.path.join(tmp, "a_file")
    open(afile, "w").close()
    nomesh = os.path.join(tmp, "nomesh.toml")
    with open(nomesh, "w") as fh:
        fh.write('mesh = "no-such-mesh.obj"\n')
    cases = [
        (["fig8", "--mesh", mesh, "--out", os.path.join(tmp, "nodir")], "no such directory"),
        (["fig8", "--mesh", mesh, "--out", afile], "not a directory"),
        (["fig8", "--scene", mesh, "--out", empty], "give it as --mesh"),
        (["fig8", "--mesh", scene, "--out", empty], "give it as --scene"),
        (["fig8", "--mesh", os.path.join(tmp, "missing.obj"), "--out", empty], "missing.obj: no such file"),
        (["fig8", "--scene", nomesh, "--out", empty], "mesh 'no-such-mesh.obj' not found"),
        (["sensitivity", "--mesh", mesh, "--out", empty], "runs on the shipped scenes"),
        (["fig8", "--mesh", mesh, "--out", empty, "--iccs", "2,4"], "give 1 and at least one more"),
        (["fig8", "--mesh", mesh, "--out", empty, "--iccs", "1,1e3"], "'1e3' is not an integer"),
        (["fig8", "--mesh", mesh, "--out", empty, "--size", "0"], "out of range"),
        (["fig8", "--mesh", mesh], "the following arguments are required: --out"),
        (["fig8", "--mesh", mesh, "--out", empty, "--raplas", os.path.join(tmp, "no-raplas")], "no such executable"),
    ]
    if os.geteuid() != 0:  # root writes anywhere
        ro = os.path.join(tmp, "readonly")
        os.mkdir(ro, 0o500)
        cases.append((["fig8", "--mesh", mesh, "--out", ro], "cannot write there"))
    for args, needle in cases:
        p = subprocess.run([sys.executable, tool] + (["--raplas", raplas] if "--raplas" not in args else []) + args,
                           capture_output=True, text=True)
        lines = p.stderr.strip().splitlines()
        one_line = len(lines) == 1 or (len(lines) > 1 and lines[0].startswith("usage:"))
        check(p.returncode == 2 and needle in p.stderr and one_line and not os.listdir(empty) and
              not os.path.exists(os.path.join(tmp, "nodir")),
              f"{' '.join(a if not a.startswith(tmp) else os.path.basename(a) for a in args)}: exit {p.returncode}, "
              f"{lines[-1] if lines else ''}")
check.finish()
