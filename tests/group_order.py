#!/usr/bin/env python3
"""workload.group_order: the model issues a trace's groups in another order.

Every order gives the same workload (workload_hash, group and pass counts) and,
at one ICC without overlapped passes, the same cycles (each pass is one group,
timed alone); the random order is the same for the same seed and another for
another seed; shards of a permuted run merge into the whole run; a streamed
run and a whole-frame one agree; functional_match holds throughout."""
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from testlib import Checks, FOLLOW_WORKLOAD, json_diff

raplas = sys.argv[1]
ORDERS = ["pixel", "random", "morton", "strided"]
SCENE = ["--set", "image.width=24", "--set", "image.height=24", "--set", "groups.size=4", "--set",
         "groups.shadow_size=4", "--set", "builtin_detail=2"]


check = Checks()


def simulate(tmp, *args):
    out = os.path.join(tmp, "out.json")
    subprocess.run([raplas, "simulate", "-q", "--config", "paper", *FOLLOW_WORKLOAD, "--json", out, *args], check=True)
    with open(out) as f:
        return json.load(f)


with tempfile.TemporaryDirectory() as tmp:
    trace = os.path.join(tmp, "t.trace")
    subprocess.run([raplas, "trace", "-q", "-o", trace, *SCENE], check=True)
    one = {o: simulate(tmp, "--trace", trace, "--iccs", "1", "--set", f"workload.group_order={o}") for o in ORDERS}
    many = {o: simulate(tmp, "--trace", trace, "--iccs", "6", "--fifo", "4", "--set", f"workload.group_order={o}")
            for o in ORDERS}
    for o in ORDERS:
        check(one[o]["total_cycles"] == one["pixel"]["total_cycles"], f"{o}: 1 ICC, the same cycles as pixel order")
        for k in ("workload_hash", "passes", "ray_groups"):
            check(many[o][k] == many["pixel"][k], f"{o}: 6 ICCs, the same {k}")
        check(many[o]["functional_match"], f"{o}: functional_match")
        check(many[o]["resolved_config"]["workload.group_order"] == o, f"{o}: reported in resolved_config")
    check(len({many[o]["total_cycles"] for o in ORDERS}) > 1, "the orders do not all give the same cycles at 6 ICCs")
    check(len({many[o]["config_hash"] for o in ORDERS}) == len(ORDERS), "each order its own config_hash")
    seeded = [simulate(tmp, "--trace", trace, "--iccs", "6", "--fifo", "4", "--set", "workload.group_order=random",
                       "--set", f"workload.group_seed={s}")["total_cycles"] for s in (1, 1, 2)]
    check(seeded[0] == seeded[1] == many["random"]["total_cycles"], "random: the same seed, the same cycles")
    check(seeded[2] != seeded[0], "random: another seed, other cycles")
    # Shards of a permuted run merge into the whole run; a scene gives what its trace gives.
    parts = []
    for i in range(3):
        p = os.path.join(tmp, f"part{i}.json")
        subprocess.run([raplas, "simulate", "-q", "--trace", trace, "--config", "paper", *FOLLOW_WORKLOAD, "--iccs",
                        "6", "--fifo", "4", "--set", "workload.group_order=strided", "--shard", f"{i}/3", "--json", p],
                       check=True)
        parts.append(p)
    merged = os.path.join(tmp, "merged.json")
    subprocess.run([raplas, "merge", "-q", *parts, "--json", merged], check=True)
    with open(merged) as f:
        m = json.load(f)
    d = json_diff(m, many["strided"], {"wall"})
    check(not d, "strided: 3 shards merged = the whole run" + ("" if not d else ": " + "; ".join(d[:3])))
    scene = simulate(tmp, *SCENE, "--iccs", "6", "--fifo", "4", "--set", "workload.group_order=morton")
    d = json_diff(scene, many["morton"], {"wall"})
    check(not d, "morton: from the scene = from its trace" + ("" if not d else ": " + "; ".join(d[:3])))
    jobs = simulate(tmp, *SCENE, "--iccs", "6", "--fifo", "4", "--set", "workload.group_order=random", "--jobs", "2")
    d = json_diff(jobs, many["random"], {"wall"})
    check(not d, "random: --jobs 2 = the whole run" + ("" if not d else ": " + "; ".join(d[:3])))
check.finish()
