#!/usr/bin/env python3
"""Compares raplas's memory estimates with measured peak RSS (docs/MEMORY.md).

  tools/memory_check.py [--raplas build/raplas] [--quick]

Runs each command below under /usr/bin/time -v with RAPLAS_MEMORY_LOG=1 and
prints a Markdown table: the largest estimate any check of the run made
(what the run was predicted to need at its peak) against the "Maximum
resident set size" GNU time reports. Needs the shared scenes beside the
checkout; takes a few minutes (--quick: the three smallest runs).
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SMALL = ["--set", "image.width=8", "--set", "image.height=8", "--set", "builtin_detail=0"]


def size(w):
    return ["--set", f"image.width={w}", "--set", f"image.height={w}"]


def scene(name):
    return ["--scene", os.path.join(ROOT, "scenes", f"{name}.toml")]


# (label, arguments after `raplas`, quick)
RUNS = [
    ("render, built-in scene, 1024x1024", ["render", "-q", "-o", "out.png"] + size(1024), False),
    ("render, bunny, 512x512", ["render", "-q", "-o", "out.png"] + scene("bunny") + size(512), False),
    ("render, conference, 256x256", ["render", "-q", "-o", "out.png"] + scene("conference") + size(256), False),
    ("trace, built-in scene, 256x256", ["trace", "-q", "-o", "builtin.trace"] + size(256), False),
    ("trace, bunny, 256x256", ["trace", "-q", "-o", "bunny.trace"] + scene("bunny") + size(256), False),
    ("trace, conference, 128x128", ["trace", "-q", "-o", "conf.trace"] + scene("conference") + size(128), False),
    ("simulate, built-in scene, 256x256, 16 ICCs", ["simulate", "-q", "--iccs", "16"] + size(256), False),
    ("simulate, bunny, 128x128, paper config, 48 ICCs",
     ["simulate", "-q", "--config", "paper", "--iccs", "48"] + scene("bunny") + size(128), False),
    ("simulate, conference, 128x128, 16 ICCs", ["simulate", "-q", "--iccs", "16"] + scene("conference") + size(128), False),
    ("simulate --trace (bunny 256x256 trace), 16 ICCs", ["simulate", "-q", "--iccs", "16", "--trace", "bunny.trace"], False),
    ("trace for the any-plane reading, bunny, 256x256",
     ["trace", "-q", "--triangle-select", "any", "-o", "bunny_any.trace"] + scene("bunny") + size(256), False),
    ("simulate --trace (bunny 256x256 any-plane trace), 16 ICCs, any-plane reading",
     ["simulate", "-q", "--iccs", "16", "--set", "icc.triangle_select=any", "--trace", "bunny_any.trace"], False),
    ("simulate, conference, 128x128, 16 ICCs, any-plane reading",
     ["simulate", "-q", "--iccs", "16", "--set", "icc.triangle_select=any"] + scene("conference") + size(128), False),
    ("simulate, 8x8 pixels, 4096 ICCs, FIFO depth 1", ["simulate", "-q", "--iccs", "4096", "--fifo", "1", "--set",
                                                       "fifo.planeid_depth=1"] + SMALL, True),
    ("simulate, 32x32 pixels, 16 ICCs, FIFO depths 10^6",
     ["simulate", "-q", "--iccs", "16", "--fifo", "1000000", "--set", "fifo.planeid_depth=1000000", "--set",
      "builtin_detail=0"] + size(32), True),
    ("render, built-in scene, 64x64", ["render", "-q", "-o", "out.png"], True),
]


def measure(raplas, args, cwd):
    env = dict(os.environ, RAPLAS_MEMORY_LOG="1")
    env.pop("RAPLAS_MAX_MEMORY", None)
    p = subprocess.run(["/usr/bin/time", "-v", raplas] + args, cwd=cwd, env=env, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"raplas {' '.join(args)}: exit {p.returncode}\n{p.stderr}")
    estimates = [int(m) for m in re.findall(r"raplas: memory: .*?: estimate (\d+) bytes", p.stderr)]
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", p.stderr).group(1)) * 1024
    return max(estimates), rss


def mib(b):
    return f"{b / 2**20:,.0f} MiB"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--raplas", default=os.path.join(ROOT, "build", "raplas"))
    ap.add_argument("--quick", action="store_true")
    a = ap.parse_args()
    raplas = os.path.abspath(a.raplas)
    print("| run | estimated peak | measured peak RSS | estimate / measured |")
    print("|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for label, args, quick in RUNS:
            if a.quick and not quick:
                continue
            est, rss = measure(raplas, args, tmp)
            print(f"| {label} | {mib(est)} | {mib(rss)} | {est / rss:.2f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
