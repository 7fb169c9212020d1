#!/usr/bin/python3
"""Plot any sweep CSV (raplas sweep --out, or any CSV with a header row).

  tools/plot_sweep.py CSV --x COL --y COL [--series COL] [--facet COL] --out PNG
                      [--logx] [--logy] [--title TEXT] [--where COL=VALUE]...

--y may be any numeric column, `speedup` and `efficiency` among them (the
columns raplas sweep adds: over the base point of each series, docs/SWEEPS.md).
One line per value of --series, one
panel per value of --facet; --where keeps only the rows with COL=VALUE
(repeatable). With --x iccs and --y speedup the ideal (linear) speedup is drawn
dashed, and with --y efficiency the 100 % line.

The plot needs Debian's python3-matplotlib (tools/install-deps.sh installs
it). When another python3 comes first on PATH (a pyenv or conda interpreter
without matplotlib), the script runs itself again with /usr/bin/python3.
Exit codes: 0 written, 2 bad input (file, column, value), 1 internal error.
"""
import argparse
import csv
import difflib
import math
import os
import sys

SYSTEM_PYTHON = "/usr/bin/python3"


def need_matplotlib():
    """Imports matplotlib with the Agg backend, or re-executes with the
    system interpreter, which has Debian's python3-matplotlib."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt  # noqa: F401
        return plt
    except ImportError:
        here = os.path.realpath(sys.executable or "")
        if os.path.exists(SYSTEM_PYTHON) and here != os.path.realpath(SYSTEM_PYTHON) \
                and not os.environ.get("RAPLAS_PLOT_REEXEC"):
            os.environ["RAPLAS_PLOT_REEXEC"] = "1"
            os.execv(SYSTEM_PYTHON, [SYSTEM_PYTHON, os.path.abspath(__file__)] + sys.argv[1:])
        fail(f"matplotlib is missing for {sys.executable} (Debian: apt-get install python3-matplotlib, "
             f"or run tools/install-deps.sh)", code=1)


def fail(msg, code=2):
    print(f"plot_sweep: error: {msg}", file=sys.stderr)
    sys.exit(code)


# Axis labels with units for the columns raplas writes; any other column is
# labelled with its name.
LABELS = {
    "iccs": "ICCs (Intersection Calculation Cores)",
    "fifo_depth": "Triangle FIFO depth (records)",
    "sphere_fifo_depth": "Sphere FIFO depth (records)",
    "planeid_fifo_depth": "PlaneID FIFO depth (spheres)",
    "total_cycles": "total cycles",
    "time_ms": "time at the clock (ms)",
    "passes": "passes",
    "ray_groups": "ray groups",
    "speedup": "speedup (x, over the base point)",
    "efficiency": "efficiency (speedup per ICC, relative to the base)",
    "area": "area (slice-equivalents, area.model = blocks; docs/MODEL.md §6)",
    "area_time": "area x time (slice-equivalents x cycles)",
    "area_time_normalized": "area x time (normalised)",
    "rti_utilisation": "RTI utilisation (fraction of active cycles)",
    "triangle_link_avg_gbps": "Triangle Stream Link, average (GB/s)",
    "triangle_link_stall_cycles": "Triangle Stream Link stall cycles",
    "sphere_link_stall_cycles": "Sphere Stream Link stall cycles",
    "ray_triangle_tests": "ray-triangle tests",
    "sphere_hits": "sphere hits",
    "triangle_records_read": "triangle records read",
    "icc.rti_pipes": "Ray-Triangle Intersector pipes per ICC",
    "icc.psi_pipes": "Plane-Sphere Intersector pipes per ICC",
}


def no_column(opt, col, path, cols, extra=""):
    near = difflib.get_close_matches(col, sorted(cols), n=1)
    hint = f"; did you mean '{near[0]}'?" if near else f"; the header of {path} lists them"
    fail(f"{opt} {col}: no such column in {path}{extra}{hint}")


def label(col):
    return LABELS.get(col, col)


def number(text, col, line):
    try:
        x = float(text)
    except ValueError:
        fail(f"column '{col}' is not numeric: '{text}' (data row {line})")
    if not math.isfinite(x):
        fail(f"column '{col}' is not finite: '{text}' (data row {line})")
    return x


def read_csv(path):
    try:
        with open(path, newline="") as f:
            lines = [l for l in f if not l.startswith("#")]
    except OSError as e:
        fail(f"{path}: cannot read: {e.strerror}")
    rows = list(csv.DictReader(lines))
    if not rows:
        fail(f"{path}: no rows (a header and at least one row expected)")
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("--x", required=True, help="column for the x axis")
    ap.add_argument("--y", required=True, help="column for the y axis, or speedup / efficiency")
    ap.add_argument("--series", help="one line per value of this column")
    ap.add_argument("--facet", help="one panel per value of this column")
    ap.add_argument("--where", action="append", default=[], help="COL=VALUE: keep only these rows (repeatable)")
    ap.add_argument("--out", required=True, help="PNG to write")
    ap.add_argument("--logx", action="store_true")
    ap.add_argument("--logy", action="store_true")
    ap.add_argument("--title")
    a = ap.parse_args()
    if not a.out.endswith(".png"):
        fail(f"--out {a.out}: give a .png file")

    rows = read_csv(a.csv)
    cols = set(rows[0].keys())
    for w in a.where:
        if "=" not in w:
            fail(f"--where '{w}': expected COL=VALUE")
        c, v = w.split("=", 1)
        if c not in cols:
            no_column("--where", c, a.csv, cols)
        rows = [r for r in rows if r[c] == v]
        if not rows:
            fail(f"--where {w}: no row has it")
    for opt, c in (("--x", a.x), ("--series", a.series), ("--facet", a.facet)):
        if c and c not in cols:
            no_column(opt, c, a.csv, cols)
    if a.y not in cols:
        extra = " (raplas sweep writes speedup and efficiency)" if a.y in ("speedup", "efficiency") else ""
        no_column("--y", a.y, a.csv, cols, extra)

    plt = need_matplotlib()

    def sort_key(v):
        try:
            return (0, float(v), v)
        except ValueError:
            return (1, 0.0, v)

    facets = sorted({r[a.facet] for r in rows}, key=sort_key) if a.facet else [None]
    fig, axes = plt.subplots(1, len(facets), figsize=(5.5 * len(facets), 4.2), squeeze=False, sharey=True)
    for ax, fv in zip(axes[0], facets):
        sub = [r for r in rows if fv is None or r[a.facet] == fv]
        lines = sorted({r[a.series] for r in sub}, key=sort_key) if a.series else [None]
        xs_all = []
        for sv in lines:
            pts = sorted(((number(r[a.x], a.x, i), number(r[a.y], a.y, i)) for i, r in enumerate(sub, 1)
                          if sv is None or r[a.series] == sv), key=lambda p: p[0])
            if not pts:
                continue
            xs_all += [p[0] for p in pts]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", markersize=3.5, linewidth=1.3,
                    label=None if sv is None else f"{a.series} = {sv}")
        if a.x == "iccs" and xs_all and a.y in ("speedup", "efficiency"):
            lo, hi = min(xs_all), max(xs_all)
            if a.y == "speedup":
                ax.plot([lo, hi], [1, hi / lo], "k--", linewidth=0.8, label="ideal")
            else:
                ax.axhline(1.0, color="k", linestyle="--", linewidth=0.8, label="ideal")
        ax.set_xlabel(label(a.x))
        if ax is axes[0][0]:
            ax.set_ylabel(label(a.y))
        if a.logx:
            ax.set_xscale("log", base=2)
        if a.logy:
            ax.set_yscale("log")
        if fv is not None:
            ax.set_title(f"{a.facet} = {fv}", fontsize=10)
        ax.grid(True, linewidth=0.3)
        if a.series or (a.x == "iccs" and a.y in ("speedup", "efficiency")):
            ax.legend(fontsize=7)
    if a.title:
        fig.suptitle(a.title, fontsize=11)
    fig.tight_layout()
    tmp = a.out + ".tmp.png"
    try:
        fig.savefig(tmp, dpi=110)
        os.replace(tmp, a.out)
    except OSError as e:
        fail(f"{a.out}: cannot write: {e.strerror}")
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
