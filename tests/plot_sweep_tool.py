#!/usr/bin/env python3
"""tools/plot_sweep.py on a sweep CSV (the golden sweep table of the built-in
scene): a PNG for speedup, efficiency and any column, by series and facet, and
one line, exit 2, for every bad input."""
import os
import subprocess
import sys
import tempfile

root = os.path.abspath(sys.argv[1])
tool = os.path.join(root, "tools", "plot_sweep.py")
table = os.path.join(root, "tests", "golden", "sweep_builtin.csv")
failures = 0


def run(args):
    return subprocess.run([sys.executable, tool] + args, capture_output=True, text=True)


def check(cond, what):
    global failures
    print(("ok   " if cond else "FAIL ") + what)
    failures += not cond


with tempfile.TemporaryDirectory() as tmp:
    for y, extra in (("speedup", ["--series", "fifo_depth", "--facet", "variant", "--where", "scene=builtin"]),
                     ("efficiency", ["--series", "variant", "--where", "fifo_depth=1000"]),
                     ("total_cycles", ["--series", "variant", "--logx", "--logy", "--title", "cycles"])):
        out = os.path.join(tmp, y + ".png")
        p = run([table, "--x", "iccs", "--y", y, "--out", out] + extra)
        ok = p.returncode == 0 and os.path.exists(out) and open(out, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
        check(ok and os.path.getsize(out) > 10000, f"--y {y} {' '.join(extra)}: PNG written ({p.stderr.strip()})")
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
            ([table, "--x", "iccs", "--y", "speedup", "--out-of-place"], "unrecognized arguments")):
        out = os.path.join(tmp, "bad.png")
        p = run(args + (["--out", out] if "--out" not in args else []))
        lines = p.stderr.strip().splitlines()
        check(p.returncode == 2 and needle in p.stderr and not os.path.exists(out),
              f"{' '.join(args[1:])}: exit {p.returncode}, {lines[-1] if lines else ''}")
print(f"{failures} failed")
sys.exit(1 if failures else 0)
