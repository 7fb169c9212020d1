#!/usr/bin/env python3
"""tools/plot_sweep.py on a sweep CSV (the golden sweep table of the built-in
scene) and on small tables written here: a PNG for speedup, efficiency and any
column, by series and facet; integer ticks for integer columns; speedup and
efficiency over the base the axis names (the sweep's, or --base-iccs and
--base-fifo, the values recomputed from total_cycles); normalised axes that
name their reference; and one line, exit 2, for every bad input. What each
panel shows is read back from --axes-json."""
import csv
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from testlib import Checks

root = os.path.abspath(sys.argv[1])
tool = os.path.join(root, "tools", "plot_sweep.py")
table = os.path.join(root, "tests", "golden", "sweep_builtin.csv")


def run(args):
    return subprocess.run([sys.executable, tool] + args, capture_output=True, text=True)


check = Checks()


def plot(tmp, name, args):
    """Runs the tool; returns (process, axes JSON or None)."""
    out, js = os.path.join(tmp, name + ".png"), os.path.join(tmp, name + ".json")
    p = run(args + ["--out", out, "--axes-json", js])
    ok = p.returncode == 0 and os.path.exists(out) and open(out, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    return p, (json.load(open(js)) if ok and os.path.exists(js) else None)


def flat(text):
    return " ".join(text.split())


def golden_rows():
    with open(table, newline="") as f:
        return list(csv.DictReader(l for l in f if not l.startswith("#")))


def line(panel, label):
    return next((l for l in panel["lines"] if l["label"] == label), None)


def close(a, b):
    return abs(a - b) <= 1e-9 * max(1.0, abs(b))


with tempfile.TemporaryDirectory() as tmp:
    for y, extra in (("speedup", ["--series", "fifo_depth", "--facet", "variant", "--where", "scene=builtin"]),
                     ("efficiency", ["--series", "variant", "--where", "fifo_depth=1000"]),
                     ("total_cycles", ["--series", "variant", "--logx", "--logy", "--title", "cycles"])):
        out = os.path.join(tmp, y + ".png")
        p = run([table, "--x", "iccs", "--y", y, "--out", out] + extra)
        ok = p.returncode == 0 and os.path.exists(out) and open(out, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
        check(ok and os.path.getsize(out) > 10000, f"--y {y} {' '.join(extra)}: PNG written ({p.stderr.strip()})")

    # Small tables in the layout of raplas sweep: the varied key between config and overrides.
    rti = os.path.join(tmp, "rti.csv")
    with open(rti, "w") as f:
        f.write("scene,config,icc.rti_pipes,overrides,iccs,fifo_depth,total_cycles,passes,area_time\n")
        for pipes in (1, 2):
            for k in (1, 2):
                f.write(f"room,paper,{pipes},,{k},1000,{1000 // (k * pipes)},{k},{10 * pipes}\n")
    many = os.path.join(tmp, "many.csv")
    with open(many, "w") as f:
        f.write("scene,config,overrides,iccs,fifo_depth,total_cycles\n")
        for k in range(1, 31):
            f.write(f"room,paper,,{k},1000,{100000 // k + 7 * k}\n")
    norm = os.path.join(tmp, "norm.csv")
    with open(norm, "w") as f:
        f.write("scene,config,memory.system,overrides,iccs,fifo_depth,total_cycles,area_time,area_time_normalized\n")
        for k, (s_at, d_at) in zip((1, 2, 4), ((300.0, 100.0), (240.0, 160.0), (200.0, 400.0))):
            f.write(f"room,paper,streaming,,{k},1000,1,{s_at},{s_at / d_at!r}\n")
            f.write(f"room,paper,distributed,memory.system=distributed,{k},1000,1,{d_at},1\n")
    bare = os.path.join(tmp, "bare.csv")  # the same without the column the sweep's --normalize adds
    with open(norm) as f, open(bare, "w") as g:
        for r in f:
            g.write(r.rsplit(",", 1)[0] + "\n")

    # Integer keys get integer ticks: two values (1 and 2), thirty values, and an integer y.
    p, j = plot(tmp, "rti_x", [rti, "--x", "icc.rti_pipes", "--y", "area_time", "--where", "iccs=2"])
    ticks = j["panels"][0]["xticks"] if j else []
    check([t[0] for t in ticks] == [1.0, 2.0] and [t[1] for t in ticks] == ["1", "2"],
          f"--x icc.rti_pipes (values 1, 2): ticks {ticks} ({p.stderr.strip()})")
    p, j = plot(tmp, "many_x", [many, "--x", "iccs", "--y", "total_cycles"])
    ticks = j["panels"][0]["xticks"] if j else []
    check(len(ticks) >= 3 and all(float(t[0]).is_integer() and t[1] == f"{t[0]:g}" for t in ticks),
          f"--x iccs (values 1..30): integer ticks {[t[1] for t in ticks]}")
    p, j = plot(tmp, "rti_y", [rti, "--x", "iccs", "--y", "passes", "--series", "icc.rti_pipes"])
    ticks = j["panels"][0]["yticks"] if j else []
    check(ticks != [] and all(float(t[0]).is_integer() for t in ticks), f"--y passes (values 1, 2): integer ticks {ticks}")
    p, j = plot(tmp, "golden_x", [table, "--x", "iccs", "--y", "efficiency", "--where", "variant=streaming",
                                  "--series", "fifo_depth", "--logx"])
    ticks = j["panels"][0]["xticks"] if j else []
    check([t[1] for t in ticks] == ["1", "4", "16"], f"--x iccs --logx (1, 4, 16): ticks {[t[1] for t in ticks]}")

    # The area's unit follows the rows' area.model (the blocks model's slice-equivalents by default).
    pe = os.path.join(tmp, "pe.csv")
    with open(rti) as f, open(pe, "w") as g:
        for r in f:
            g.write(r.replace("paper,1,,", "paper,1,area.model=pe_units,").replace("paper,2,,", "paper,2,area.model=pe_units,"))
    for path, unit in ((rti, "slice-equivalents x cycles"), (pe, "PE units x cycles")):
        p, j = plot(tmp, "unit", [path, "--x", "icc.rti_pipes", "--y", "area_time", "--where", "iccs=2"])
        lab = flat(j["panels"][0]["ylabel"]) if j else ""
        check(unit in lab, f"--y area_time of {os.path.basename(path)}: '{lab}'")

    # Speedup and efficiency name their base; --base-iccs and --base-fifo recompute them.
    g = [r for r in golden_rows() if r["variant"] == "streaming"]
    cyc = {(int(r["iccs"]), int(r["fifo_depth"])): int(r["total_cycles"]) for r in g}
    p, j = plot(tmp, "eff_sweep", [table, "--x", "iccs", "--y", "efficiency", "--where", "variant=streaming",
                                   "--series", "fifo_depth"])
    lab = flat(j["panels"][0]["ylabel"]) if j else ""
    check("over 1 ICC at the same FIFO depth" in lab, f"efficiency without a base option names the sweep's: '{lab}'")
    p, j = plot(tmp, "eff_fifo", [table, "--x", "iccs", "--y", "efficiency", "--where", "variant=streaming",
                                  "--series", "fifo_depth", "--base-iccs", "1", "--base-fifo", "1000"])
    pan = j["panels"][0] if j else {"ylabel": "", "lines": []}
    l10 = line(pan, "fifo_depth = 10")
    want = [cyc[(1, 1000)] / cyc[(k, 10)] / k for k in (1, 4, 16)]
    check(l10 is not None and l10["x"] == [1, 4, 16] and all(close(a, b) for a, b in zip(l10["y"], want)),
          f"--base-iccs 1 --base-fifo 1000: efficiency at FIFO 10 over 1 ICC at FIFO 1000 "
          f"{l10['y'] if l10 else None} = {want}")
    check(want[0] < 1, f"  (the 1-ICC point at FIFO 10 is then below 1: {want[0]:.6f})")
    lab, title = flat(pan["ylabel"]), j["title"] if j else ""
    check("over 1 ICC at FIFO depth 1000" in lab and "base: 1 ICC at FIFO depth 1000" in title,
          f"the plot names the base: ylabel '{lab}', title '{title}'")
    p, j = plot(tmp, "speedup_k4", [table, "--x", "iccs", "--y", "speedup", "--where", "variant=streaming",
                                    "--where", "fifo_depth=10", "--base-iccs", "4"])
    pan = j["panels"][0] if j else {"ylabel": "", "lines": []}
    s = line(pan, "_child0") or (pan["lines"][0] if pan["lines"] else None)
    ideal = line(pan, "ideal")
    want = [cyc[(4, 10)] / cyc[(k, 10)] for k in (1, 4, 16)]
    check(s is not None and all(close(a, b) for a, b in zip(s["y"], want)) and
          "over 4 ICCs at the same FIFO depth" in flat(pan["ylabel"]),
          f"--base-iccs 4: speedup {s['y'] if s else None} = {want}, '{flat(pan['ylabel'])}'")
    check(ideal is not None and close(ideal["y"][0], 0.25) and close(ideal["y"][-1], 4.0),
          f"--base-iccs 4: the ideal line is K/4 ({ideal['y'] if ideal else None})")

    # Normalised axes name their reference.
    p, j = plot(tmp, "norm_read", [norm, "--x", "iccs", "--y", "area_time_normalized", "--series", "memory.system"])
    lab = flat(j["panels"][0]["ylabel"]) if j else ""
    check("normalised to the point with memory.system = distributed" in lab, f"area_time_normalized: '{lab}'")
    p, j = plot(tmp, "norm_compute", [bare, "--x", "iccs", "--y", "area_time_normalized", "--series", "memory.system",
                                      "--normalize", "memory.system=distributed"])
    pan = j["panels"][0] if j else {"ylabel": "", "lines": []}
    s = line(pan, "memory.system = streaming")
    check(s is not None and all(close(a, b) for a, b in zip(s["y"], [3.0, 1.5, 0.5])) and
          "memory.system = distributed" in flat(pan["ylabel"]),
          f"--normalize memory.system=distributed: {s['y'] if s else None} = [3, 1.5, 0.5], '{flat(pan['ylabel'])}'")

    bad_csv = os.path.join(tmp, "bad.csv")
    with open(bad_csv, "w") as f:
        f.write("iccs,total_cycles\n1,x\n")
    for args, needle in (
            ([table, "--x", "iccs", "--y", "nope"], "--y nope: no such column"),
            ([table, "--x", "nope", "--y", "speedup"], "--x nope: no such column"),
            ([table, "--x", "iccs", "--y", "speedup", "--series", "nope"], "--series nope: no such column"),
            ([table, "--x", "iccs", "--y", "speedup", "--where", "iccs=7"], "--where iccs=7: no row has it"),
            ([table, "--x", "iccs", "--y", "speedup", "--where", "iccs"], "expected COL=VALUE"),
            ([bad_csv, "--x", "iccs", "--y", "total_cycles"], "column 'total_cycles' is not numeric: 'x'"),
            ([os.path.join(tmp, "missing.csv"), "--x", "iccs", "--y", "speedup"], "missing.csv: cannot read"),
            ([table, "--x", "iccs", "--y", "speedup", "--out-of-place"], "unrecognized arguments"),
            ([table, "--x", "iccs", "--y", "efficiency", "--where", "variant=streaming", "--base-fifo", "7"],
             "no base point with iccs=1 and fifo_depth=7 for variant=streaming"),
            ([table, "--x", "iccs", "--y", "efficiency", "--where", "variant=streaming", "--base-iccs", "2"],
             "no base point with iccs=2"),
            ([table, "--x", "iccs", "--y", "efficiency", "--base-iccs", "0"], "--base-iccs 0: must be at least 1"),
            ([table, "--x", "iccs", "--y", "total_cycles", "--base-fifo", "1000"],
             "apply to --y speedup or efficiency"),
            ([bare, "--x", "iccs", "--y", "area_time_normalized", "--normalize", "memory.system=shared"],
             "--normalize memory.system=shared: no row has it"),
            ([bare, "--x", "iccs", "--y", "area_time_normalized", "--normalize", "memory.system"],
             "expected COL=VALUE"),
            ([bare, "--x", "iccs", "--y", "total_cycles", "--normalize", "memory.system=distributed"],
             "--normalize applies to --y area_time_normalized")):
        out = os.path.join(tmp, "bad.png")
        p = run(args + (["--out", out] if "--out" not in args else []))
        lines = p.stderr.strip().splitlines()
        check(p.returncode == 2 and needle in p.stderr and not os.path.exists(out),
              f"{' '.join(args[1:])}: exit {p.returncode}, {lines[-1] if lines else ''}")
check.finish()
