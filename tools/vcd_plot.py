#!/usr/bin/python3
"""Draws signals of a `raplas simulate --vcd` waveform over one pass, as a PNG.

  tools/vcd_plot.py waves.vcd --pass 3 --out pass.png [--signal NAME]...

NAME is a signal's hierarchical name without the leading "SystemC."
(e.g. raplas.icc_0.triangle_fifo.size); without --signal, the Figure-7 view:
both Stream Links' valid and stall, and ICC 0's Sphere FIFO, Decoder, PlaneID
FIFO, Triangle FIFO and RTI (the signals tools/waves.gtkw shows in GTKWave).
Time is in clock cycles from the start of the pass. Needs python3-matplotlib.
"""
import argparse
import sys

DEFAULT = ["raplas.sphere_valid", "raplas.sphere_stall", "raplas.triangle_valid", "raplas.triangle_stall",
           "raplas.icc_0.sphere_fifo.size", "raplas.icc_0.decoder.hold", "raplas.icc_0.decoder.decided",
           "raplas.icc_0.planeid_fifo.size", "raplas.icc_0.triangle_fifo.size", "raplas.icc_0.triangle_fifo.full",
           "raplas.icc_0.rti.busy", "raplas.icc_1.triangle_fifo.full"]


def read_vcd(path, names):
    """(period in ps, {name: [(time ps, value)]}, pass changes [(time, value)]) for the names asked."""
    ids, scope, want = {}, [], set(names) | {"raplas.pass", "raplas.clock"}
    traces = {}
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == "$scope":
                scope.append(t[2])
            elif t[0] == "$upscope":
                scope.pop()
            elif t[0] == "$var":
                name = ".".join(scope[1:] + [t[4]])  # without "SystemC"
                if name in want and name not in traces:
                    traces[name] = []
                    ids.setdefault(t[3], []).append(name)
            elif t[0] == "$enddefinitions":
                break
        missing = [n for n in want if n not in traces]
        if missing:
            sys.exit(f"vcd_plot: {path}: no signal {missing[0]} (names are hierarchical, e.g. raplas.icc_0.triangle_fifo.size)")
        now = 0
        for line in f:
            if not line or line[0] in "$\n":
                continue
            c = line[0]
            if c == "#":
                now = int(line[1:])
            elif c in "01xz":
                for n in ids.get(line[1:].strip(), ()):
                    traces[n].append((now, 1 if c == "1" else 0))
            elif c == "b":
                val, ident = line[1:].split()
                for n in ids.get(ident, ()):
                    traces[n].append((now, int(val.replace("x", "0").replace("z", "0"), 2)))
    clock = traces["raplas.clock"]
    rises = [t for t, v in clock if v == 1][:3]
    if len(rises) < 2:
        sys.exit(f"vcd_plot: {path}: fewer than two clock edges")
    return rises[1] - rises[0], traces, traces["raplas.pass"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("vcd")
    ap.add_argument("--pass", dest="pass_", type=int, default=1, help="the pass to draw (its index in the run)")
    ap.add_argument("--signal", action="append", help="a signal to draw (repeatable); default: the Figure-7 view")
    ap.add_argument("--out", required=True, help="PNG to write")
    ap.add_argument("--title")
    a = ap.parse_args()
    names = a.signal or DEFAULT
    period, traces, passes = read_vcd(a.vcd, names)
    starts = [t for t, v in passes if v == a.pass_]
    if not starts:
        sys.exit(f"vcd_plot: {a.vcd}: no pass {a.pass_} (passes {passes[0][1]} to {passes[-1][1]})")
    t0 = starts[0]
    later = [t for t, v in passes if t > t0 and v != a.pass_]
    t1 = later[0] if later else max(max((t for t, _ in tr), default=t0) for tr in traces.values())
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.exit(f"vcd_plot: matplotlib is missing for {sys.executable} (Debian: python3-matplotlib, run by "
                 "/usr/bin/python3, this script's interpreter)")
    fig, axes = plt.subplots(len(names), 1, figsize=(11, 0.62 * len(names) + 1.0), sharex=True)
    for ax, n in zip(axes, names):
        tr = traces[n]
        before = [v for t, v in tr if t <= t0]
        xs, ys = [0.0], [before[-1] if before else 0]
        for t, v in tr:
            if t0 < t < t1:
                xs.append((t - t0) / period)
                ys.append(v)
        xs.append((t1 - t0) / period)
        ys.append(ys[-1])
        ax.step(xs, ys, where="post", linewidth=0.8, color="tab:blue")
        top = max(ys) if ys else 1
        ax.set_ylim(-0.15 * max(top, 1), 1.15 * max(top, 1))
        ax.set_yticks([0, top] if top > 1 else [0, 1])
        ax.set_ylabel(n.replace("raplas.", ""), rotation=0, ha="right", va="center", fontsize=7)
        ax.tick_params(labelsize=7)
        ax.grid(axis="x", linewidth=0.3)
    axes[-1].set_xlabel("clock cycles from the start of the pass")
    fig.suptitle(a.title or f"{a.vcd}: pass {a.pass_}", fontsize=9)
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    print(f"wrote {a.out} ({(t1 - t0) // period} cycles, {len(names)} signals)")


if __name__ == "__main__":
    main()
