#!/usr/bin/env python3
"""tools/plot_anatomy.py on results of raplas simulate on the built-in scene
(4 ICCs at FIFO 10, 16 ICCs at FIFO 2): one file (both panels) and two (the
anatomy panel; the per-ICC panel with --per-icc). Read back from --axes-json:
the stacked shares are the JSON's held_by and undecided-only cycles over
total_cycles, stacked end to end up to the stalled share; a bin one run lacks
is 0; each bar names mean_holders; per ICC, alone and shared (held - alone)
stack to the held cycles (bars, or steps for hundreds of ICCs). The PNG is a
PNG and no temporary file is left. Every bad input is one line on stderr and
exit 2, nothing written.

  python3 tests/plot_anatomy_tool.py RAPLAS ROOT"""
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from testlib import FOLLOW_WORKLOAD, Checks

raplas = sys.argv[1]
root = os.path.abspath(sys.argv[2])
tool = os.path.join(root, "tools", "plot_anatomy.py")
SCENE = ["--set", "image.width=24", "--set", "image.height=24", "--set", "groups.size=4", "--set",
         "groups.shadow_size=4", "--set", "builtin_detail=2"]
PNG = b"\x89PNG\r\n\x1a\n"
check = Checks()


def simulate(out, *args):
    subprocess.run([raplas, "simulate", "-q", "--config", "paper", *FOLLOW_WORKLOAD, *SCENE,
                    "--set", "sim.functional=trace", *args, "--json", out], check=True)
    with open(out) as f:
        return json.load(f)


def run(args):
    return subprocess.run([sys.executable, tool] + args, capture_output=True, text=True)


def plot(tmp, name, args):
    """Runs the tool into tmp/name.png; returns (process, axes JSON or None)."""
    out, js = os.path.join(tmp, name + ".png"), os.path.join(tmp, name + ".axes.json")
    p = run(args + ["--out", out, "--axes-json", js])
    ok = p.returncode == 0 and os.path.exists(out) and open(out, "rb").read(8) == PNG
    check(ok, f"{name}: exit {p.returncode}, a PNG written {p.stderr.strip()}")
    return p, (json.load(open(js)) if ok and os.path.exists(js) else None)


def close(a, b):
    return abs(a - b) <= 1e-9 * max(1.0, abs(b))


def series(panel, name):
    return next((s for s in panel["series"] if s["name"] == name), None)


def bin_name(b):
    return f"held by {b} ICC{'' if b == '1' else 's'}"


def check_anatomy(panel, runs, labels, what):
    """The anatomy panel shows each run's bins and undecided-only cycles in % of total_cycles, stacked."""
    check(panel["categories"] == labels, f"{what}: one bar per file, labelled {panel['categories']}")
    names = []
    for r in runs:
        names += [bin_name(b["iccs"]) for b in r["stall_anatomy"]["held_by"] if bin_name(b["iccs"]) not in names]
    names.append("undecided spheres only")
    check([s["name"] for s in panel["series"]] == names, f"{what}: series {[s['name'] for s in panel['series']]}")
    for i, (r, lab) in enumerate(zip(runs, labels)):
        a, total = r["stall_anatomy"], r["total_cycles"]
        cycles = {bin_name(b["iccs"]): b["cycles"] for b in a["held_by"]}
        cycles["undecided spheres only"] = a["undecided_only_cycles"]
        got = [series(panel, n)["values"][i] if series(panel, n) else None for n in names]
        want = [100.0 * cycles.get(n, 0) / total for n in names]
        check(all(g is not None and close(g, w) for g, w in zip(got, want)),
              f"{what}, {lab}: shares {[round(g, 4) for g in got if g is not None]} = cycles / total_cycles "
              f"{[round(w, 4) for w in want]}")
        starts = [series(panel, n)["starts"][i] for n in names if series(panel, n)]
        ends = [s + g for s, g in zip(starts, got) if g is not None]
        check(close(starts[0], 0) and all(close(s, e) for s, e in zip(starts[1:], ends)) and
              close(ends[-1], 100.0 * a["triangle_link_stall_cycles"] / total),
              f"{what}, {lab}: stacked end to end to the stalled share {ends[-1]:.3f} %")
        check(any(f"mean holders {a['mean_holders']:.2f}" in t for t in panel["annotations"]),
              f"{what}, {lab}: mean holders {a['mean_holders']:.2f} annotated")


def check_icc(panel, r, label, what):
    """The per-ICC panel stacks alone and shared cycles to each ICC's held cycles."""
    held = [c["stall_cycles"]["link_blocked_triangle_fifo_full"] for c in r["iccs_detail"]]
    alone = [c["stall_cycles"]["link_blocked_triangle_fifo_alone"] for c in r["iccs_detail"]]
    sa, ss = panel["series"][0] if panel["series"] else None, panel["series"][1] if len(panel["series"]) > 1 else None
    ok = sa is not None and ss is not None and sa["name"].startswith("alone") and ss["name"].startswith("shared")
    check(ok and sa["values"] == alone and all(s == 0 for s in sa["starts"]),
          f"{what}: alone per ICC {sa['values'] if sa else None} = {alone}")
    check(ok and [a + s for a, s in zip(sa["values"], ss["values"])] == held and ss["starts"] == sa["values"],
          f"{what}: alone + shared stacked = held per ICC {held}")
    check(ok and len(held) == r["iccs"] and any(s > 0 for s in ss["values"]),
          f"{what}: {r['iccs']} ICCs, some cycles shared")
    check(panel["title"].startswith(label + ":"), f"{what}: the panel names its file: '{panel['title']}'")


with tempfile.TemporaryDirectory() as tmp:
    a_path, b_path = os.path.join(tmp, "k4.json"), os.path.join(tmp, "k16.json")
    a = simulate(a_path, "--iccs", "4", "--fifo", "10")
    b = simulate(b_path, "--iccs", "16", "--fifo", "2")
    check(len(b["stall_anatomy"]["held_by"]) > len(a["stall_anatomy"]["held_by"]) and
          a["stall_anatomy"]["undecided_only_cycles"] > 0,
          f"the runs: {len(a['stall_anatomy']['held_by'])} and {len(b['stall_anatomy']['held_by'])} bins, "
          f"undecided-only cycles {a['stall_anatomy']['undecided_only_cycles']}")

    out = os.path.join(tmp, "plots")
    os.mkdir(out)
    p, j = plot(out, "one", [a_path])
    if j:
        check(len(j["panels"]) == 2 and j["title"] == "", f"one file: two panels, no title ({len(j['panels'])})")
        check_anatomy(j["panels"][0], [a], ["k4"], "one file")
        check_icc(j["panels"][1], a, "k4", "one file")
    p, j = plot(out, "two", [a_path, b_path, "--label", "4 ICCs", "--label", "16 ICCs", "--title", "FIFOs"])
    if j:
        check(len(j["panels"]) == 1 and j["title"] == "FIFOs", f"two files: one panel, title '{j['title']}'")
        check_anatomy(j["panels"][0], [a, b], ["4 ICCs", "16 ICCs"], "two files")
    p, j = plot(out, "per_icc", [a_path, b_path, "--per-icc", "1"])
    if j:
        check(len(j["panels"]) == 2, "two files, --per-icc 1: two panels")
        check_anatomy(j["panels"][0], [a, b], ["k4", "k16"], "--per-icc 1")
        check_icc(j["panels"][1], b, "k16", "--per-icc 1")
    # Many ICCs (the 4-ICC run's figures spread over 300 made-up ICCs): drawn as steps, the same values.
    many = json.load(open(a_path))
    many["iccs"] = 300
    many["iccs_detail"] = [dict(many["iccs_detail"][k % 4], icc=k) for k in range(300)]
    for k, c in enumerate(many["iccs_detail"]):
        c["stall_cycles"] = dict(c["stall_cycles"])
        c["stall_cycles"]["link_blocked_triangle_fifo_alone"] -= k % 7
    many_path = os.path.join(tmp, "many.json")
    with open(many_path, "w") as f:
        json.dump(many, f)
    p, j = plot(out, "many", [many_path])
    if j:
        check_icc(j["panels"][1], many, "many", "300 ICCs")
    left = sorted(os.listdir(out))
    check(left == sorted(f"{n}{e}" for n in ("one", "two", "per_icc", "many") for e in (".png", ".axes.json")),
          f"only the PNGs and axes JSON in the output directory: {left}")

    # Bad inputs: one line, exit 2, nothing written.
    def variant(name, edit):
        j = json.load(open(a_path))
        edit(j)
        path = os.path.join(tmp, name)
        with open(path, "w") as f:
            json.dump(j, f)
        return path
    older = variant("older.json", lambda j: j.pop("stall_anatomy"))
    nokey = variant("nokey.json", lambda j: j["stall_anatomy"]["held_by"][1].pop("cycles"))
    noalone = variant("noalone.json", lambda j: j["iccs_detail"][2]["stall_cycles"].pop("link_blocked_triangle_fifo_alone"))
    other = os.path.join(tmp, "other.json")
    with open(other, "w") as f:
        f.write('{"rows": []}\n')
    text = os.path.join(tmp, "text.json")
    with open(text, "w") as f:
        f.write("total_cycles = 3\n")
    shard = os.path.join(tmp, "shard.json")
    subprocess.run([raplas, "simulate", "-q", "--config", "paper", *FOLLOW_WORKLOAD, *SCENE, "--iccs", "4",
                    "--set", "sim.functional=trace", "--shard", "0/2", "--json", shard], check=True)
    sampled = os.path.join(tmp, "sampled.json")
    simulate(sampled, "--iccs", "4", "--set", "sim.estimate=sample_passes")
    bad_out = os.path.join(tmp, "bad.png")
    for args, needle in (
            ([os.path.join(tmp, "missing.json")], "missing.json: cannot read"),
            ([text], "text.json: not JSON"),
            ([other], "other.json: no 'stall_anatomy'"),
            ([older], "older.json: no 'stall_anatomy': a result of an older raplas"),
            ([nokey], "nokey.json: no 'stall_anatomy.held_by[1].cycles'"),
            ([noalone], "noalone.json: no 'iccs_detail[2].stall_cycles.link_blocked_triangle_fifo_alone'"),
            ([shard], "shard.json: a partial result of raplas simulate --shard"),
            ([sampled], "sampled.json: an estimate (estimate.mode = sample_passes)"),
            ([a_path, b_path, "--label", "x"], "--label given 1 time for 2 files"),
            ([a_path, "--label", "x", "--label", "y"], "--label given 2 times for 1 file"),
            ([a_path, b_path, "--per-icc", "2"], "--per-icc 2: no such file"),
            ([a_path, "--out", os.path.join(tmp, "nodir", "x.png")], "nodir does not exist"),
            ([a_path, "--axes-json", os.path.join(tmp, "nodir", "x.json")], "nodir does not exist"),
            ([a_path, "--out", os.path.join(tmp, "x.svg")], "give a .png file"),
            ([a_path, "--no-such-option"], "unrecognized arguments")):
        p = run(args + (["--out", bad_out] if "--out" not in args else []))
        lines = p.stderr.splitlines()
        check(p.returncode == 2 and len(lines) == 1 and lines[0].startswith("plot_anatomy.py: error: ") and
              needle in lines[0] and not os.path.exists(bad_out) and not os.path.exists(os.path.join(tmp, "x.svg")),
              f"{' '.join(os.path.basename(x) for x in args)}: exit {p.returncode}, {len(lines)} line(s): "
              f"{lines[-1] if lines else ''}")
    check(sorted(f for f in os.listdir(tmp) if f.endswith(".tmp")) == [], "no temporary file left")
check.finish()
