#!/usr/bin/env python3
"""A sharded simulation's job lists run through the real GNU parallel
(docs/SHARDING.md): `raplas simulate --shards N --emit-jobs FILE`, then
`parallel < FILE.traces && parallel < FILE && sh FILE.merge`, unchanged, and
the merged JSON (but for `wall`) and CSV equal the unsharded run's.

Without GNU parallel the check says SKIP and exits 77 (ctest: skipped); under
CI=true a missing GNU parallel is a failure (tools/install-deps.sh installs
Debian's `parallel`)."""
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
scene = ["--set", "image.width=24", "--set", "image.height=24", "--set", "groups.size=8", "--set", "groups.shadow_size=8"]
config = ["--iccs", "3", "--fifo", "4"]
shards = 4


def gnu_parallel():
    exe = shutil.which("parallel")
    if not exe:
        return None
    out = subprocess.run([exe, "--version"], capture_output=True, text=True, stdin=subprocess.DEVNULL)
    return exe if out.returncode == 0 and "GNU parallel" in out.stdout else None


if not gnu_parallel():
    if testlib.in_ci():
        print("FAIL: GNU parallel is missing (Debian's parallel, tools/install-deps.sh), and CI=true needs it")
        sys.exit(1)
    print("SKIP: GNU parallel is missing (Debian's parallel, tools/install-deps.sh): the job lists were not run")
    sys.exit(testlib.SKIP_EXIT)


check = Checks()


def sh(cmd, cwd):
    r = subprocess.run(cmd, shell=True, cwd=cwd, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    if r.returncode:
        print(f"FAIL {cmd}: exit {r.returncode}\n{r.stdout}{r.stderr}")
    return r.returncode == 0


def without_wall(path):
    j = json.load(open(path))
    j.pop("wall")
    return j


with tempfile.TemporaryDirectory() as tmp:
    subprocess.run([raplas, "simulate", *scene, *config, "--shards", str(shards), "--emit-jobs", "jobs",
                    "--json", "out.json", "--csv", "out.csv", "-q"], cwd=tmp, check=True)
    jobs = open(os.path.join(tmp, "jobs")).read().splitlines()
    check(len(jobs) == shards, f"{len(jobs)} shard lines for {shards} shards")
    ran = sh("parallel < jobs.traces && parallel < jobs && sh jobs.merge", tmp)
    check(ran, "parallel < jobs.traces && parallel < jobs && sh jobs.merge")
    subprocess.run([raplas, "simulate", *scene, *config, "--json", "whole.json", "--csv", "whole.csv", "-q"],
                   cwd=tmp, check=True)
    if ran:
        whole = without_wall(os.path.join(tmp, "whole.json"))
        merged = without_wall(os.path.join(tmp, "out.json"))
        diff = testlib.json_diff(merged, whole)
        check(not diff, f"merged JSON equals the unsharded run's but for wall ({whole['passes']} passes)"
              + "".join("\n     " + d for d in diff[:10]))
        check(open(os.path.join(tmp, "out.csv")).read() == open(os.path.join(tmp, "whole.csv")).read(),
              "merged CSV row equals the unsharded run's")
        wall = json.load(open(os.path.join(tmp, "out.json")))["wall"]
        check(wall.get("shards") == shards, f"wall names the {shards} shards")
        # Run again: every line is skipped, the merge gives the same bytes.
        before = open(os.path.join(tmp, "out.csv")).read()
        check(sh("parallel < jobs.traces && parallel < jobs && sh jobs.merge", tmp)
              and open(os.path.join(tmp, "out.csv")).read() == before, "the job lists run again give the same result")
check.finish()
