#!/usr/bin/env python3
"""tools/waves.gtkw and tools/vcd_plot.py against a fresh waveform: every
signal the GTKWave save file shows exists in `raplas simulate --vcd`'s file by
that hierarchical name, and the plot of one pass is drawn from it."""
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from testlib import Checks  # noqa: E402

raplas, root = sys.argv[1], sys.argv[2]
check = Checks()


with tempfile.TemporaryDirectory() as tmp:
    vcd = os.path.join(tmp, "w.vcd")
    subprocess.run([raplas, "simulate", "-q", "--set", "image.width=8", "--set", "image.height=8", "--set",
                    "builtin_detail=0", "--iccs", "2", "--fifo", "4", "--vcd", vcd], check=True)
    names, scope = set(), []
    with open(vcd) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == "$scope":
                scope.append(t[2])
            elif t[0] == "$upscope":
                scope.pop()
            elif t[0] == "$var":
                names.add(".".join(scope + [t[4]]))
            elif t[0] == "$enddefinitions":
                break
    shown = [re.sub(r"\[\d+:\d+\]$", "", l.strip()) for l in open(os.path.join(root, "tools", "waves.gtkw"))
             if l.startswith("SystemC.")]
    check(len(shown) >= 15, f"the save file shows {len(shown)} signals")
    for n in shown:
        check(n in names, f"{n} is in the waveform")
    png = os.path.join(tmp, "pass.png")
    # (run as a program: its interpreter is the system's, which has Debian's matplotlib)
    p = subprocess.run([os.path.join(root, "tools", "vcd_plot.py"), vcd, "--pass", "3", "--out", png],
                       capture_output=True, text=True)
    check(p.returncode == 0 and os.path.getsize(png) > 10000, "vcd_plot.py draws pass 3" + (": " + p.stderr if p.returncode else ""))
    bad = subprocess.run([os.path.join(root, "tools", "vcd_plot.py"), vcd, "--signal",
                          "raplas.icc_9.nothing", "--out", png], capture_output=True, text=True)
    check(bad.returncode != 0 and "no signal raplas.icc_9.nothing" in bad.stderr, "an unknown signal is named")
check.finish()
