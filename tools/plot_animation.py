#!/usr/bin/env python3
"""Plots of animations (docs/ANIMATION.md, docs/RESULTS.md "Animations"), with
Debian's python3-matplotlib:

  plot_animation.py cycles OUT.png LABEL=FRAMES.json...
      cycles per frame (log scale) of `raplas simulate --frames --json` results,
      one line each, and the frame rate at the clock on the right axis
  plot_animation.py host OUT.png BENCH.json
      per-frame host cost of `raplas_bench_animation --json`: the RAPLAS
      sphere rebuild (with its culling tree), the rigid-motion transform path,
      Embree's BVH build and refit, one panel per scene
  plot_animation.py sheet OUT.png COLUMNS FRAME.png...
      a contact sheet of rendered frames, labelled with their file names

Writes OUT.png atomically; a missing or malformed input is one line on
stderr and exit 2."""
import json
import os
import sys
import tempfile

USAGE = __doc__.split("\n\n")[1]


def fail(msg):
    print(f"plot_animation.py: error: {msg}", file=sys.stderr)
    sys.exit(2)


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except OSError as e:
        fail(f"{path}: {e.strerror}")
    except json.JSONDecodeError as e:
        fail(f"{path}: not JSON ({e.msg} at line {e.lineno})")


def save(fig, out):
    d = os.path.dirname(os.path.abspath(out))
    fd, tmp = tempfile.mkstemp(suffix=".png", dir=d)
    os.close(fd)
    try:
        fig.savefig(tmp, dpi=110, bbox_inches="tight")
        os.replace(tmp, out)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as p
    return p


def cycles(out, specs):
    p = plt()
    fig, ax = p.subplots(figsize=(7.5, 4.2))
    mhz = None
    for spec in specs:
        if "=" not in spec:
            fail(f"'{spec}': expected LABEL=FRAMES.json")
        label, path = spec.split("=", 1)
        j = load_json(path)
        try:
            frames = [f["frame"] for f in j["frames"]]
            cyc = [f["total_cycles"] for f in j["frames"]]
            mhz = j["clock_mhz"]
        except (KeyError, TypeError):
            fail(f"{path}: not a result of raplas simulate --frames --json (no frames array)")
        ax.plot(frames, cyc, marker=".", label=label)
    ax.set_yscale("log")
    ax.set_xlabel("frame")
    ax.set_ylabel("cycles per frame")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    if mhz:
        # frames per second at the clock: mhz * 1e6 / cycles
        import numpy as np

        def rate(x):
            return mhz * 1e6 / np.maximum(x, 1e-9)

        sec = ax.secondary_yaxis("right", functions=(rate, rate))
        sec.set_ylabel(f"frames/s at {mhz:g} MHz")
    save(fig, out)


def host(out, path):
    p = plt()
    j = load_json(path)
    try:
        scenes = j["scenes"]
    except (KeyError, TypeError):
        fail(f"{path}: not a result of raplas_bench_animation --json (no scenes)")
    fig, axes = p.subplots(1, len(scenes), figsize=(4.2 * len(scenes), 3.8), squeeze=False)
    for ax, s in zip(axes[0], scenes):
        try:
            fr = [f["frame"] for f in s["frames"]]
            rebuild = [1e3 * (f["spheres_rebuild_s"] + f["sphere_tree_s"]) for f in s["frames"]]
            build = [1e3 * f["embree"]["build_commit_s"] for f in s["frames"]]
            refit = [1e3 * f["embree"]["refit_s"] if f["embree"].get("refit_possible") else None for f in s["frames"]]
            transform = [1e3 * f["paths"]["transform"]["time_s"] if "transform" in f.get("paths", {}) else None
                         for f in s["frames"]]
        except (KeyError, TypeError):
            fail(f"{path}: scene {s.get('name', '?')}: a frame lacks the rebuild times")
        ax.plot(fr, rebuild, marker="o", color="C0", label="RAPLAS host: spheres + tree rebuilt")
        if any(t is not None for t in transform) and s.get("kind") == "rigid motion":
            ax.plot(fr, transform, marker="s", color="C1", label="RAPLAS host: centres transformed (not bit-identical)")
        ax.plot(fr, build, marker="^", color="C2", label="Embree 3: BVH build")
        if any(r is not None for r in refit):
            ax.plot(fr, refit, marker="v", color="C3", linestyle="--", label="Embree 3: BVH refit")
        ax.set_title(f"{s['name']} ({s.get('kind', '')}, {s['triangles']:,} triangles)", fontsize=9)
        ax.set_xlabel("frame")
        ax.set_ylabel("ms per frame")
        ax.set_ylim(bottom=0)
        ax.grid(True, alpha=0.3)
    handles = {}
    for ax in axes[0]:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(lab, h)
    fig.legend(handles.values(), handles.keys(), loc="lower center", ncol=2, fontsize=8, bbox_to_anchor=(0.5, -0.12))
    save(fig, out)


def sheet(out, columns, files):
    p = plt()
    import matplotlib.image as mpimg
    try:
        cols = int(columns)
    except ValueError:
        fail(f"COLUMNS '{columns}' is not an integer")
    if cols < 1 or not files:
        fail("give COLUMNS >= 1 and at least one frame PNG")
    rows = (len(files) + cols - 1) // cols
    fig, axes = p.subplots(rows, cols, figsize=(1.9 * cols, 2.0 * rows), squeeze=False)
    for k, ax in enumerate(axes.flat):
        ax.axis("off")
        if k < len(files):
            try:
                ax.imshow(mpimg.imread(files[k]))
            except (OSError, SyntaxError, ValueError) as e:
                fail(f"{files[k]}: not a readable PNG ({e})")
            ax.set_title(os.path.basename(files[k]), fontsize=7)
    save(fig, out)


def main(argv):
    if len(argv) < 3 or argv[0] not in ("cycles", "host", "sheet"):
        print(USAGE, file=sys.stderr)
        sys.exit(2)
    if argv[0] == "cycles":
        cycles(argv[1], argv[2:])
    elif argv[0] == "host":
        host(argv[1], argv[2])
    else:
        if len(argv) < 4:
            fail("sheet OUT.png COLUMNS FRAME.png...")
        sheet(argv[1], argv[2], argv[3:])


if __name__ == "__main__":
    main(sys.argv[1:])
