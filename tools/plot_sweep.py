#!/usr/bin/python3
"""Plot any sweep CSV (raplas sweep --out, or any CSV with a header row).

  tools/plot_sweep.py CSV --x COL --y COL [--series COL] [--facet COL] --out PNG
                      [--logx] [--logy] [--title TEXT] [--where COL=VALUE]...
                      [--base-iccs K] [--base-fifo D] [--normalize KEY=VALUE]

--y may be any numeric column, `speedup` and `efficiency` among them (the
columns raplas sweep adds: over the base point of each series, docs/SWEEPS.md).
One line per value of --series, one
panel per value of --facet; --where keeps only the rows with COL=VALUE
(repeatable). With --x iccs and --y speedup the ideal (linear) speedup is drawn
dashed, and with --y efficiency the 100 % line.

Every speedup and efficiency axis names its base. Without --base-* it is the
sweep's: the point with `base_iccs` ICCs (the smallest of the series) and the
same FIFO depth and keys. --base-iccs K and --base-fifo D recompute `speedup`
and `efficiency` from `total_cycles` over the point with K ICCs and/or FIFO
depth D and everything else equal (the columns before `overrides`, or --series
and --facet, and the other of iccs and fifo_depth): `--base-iccs 1 --base-fifo
1000` takes efficiency at FIFO 10 against the 1-ICC run at FIFO 1000, not at
FIFO 10. Every normalised axis names its reference: `area_time_normalized` is
read as normalised to the KEY=VALUE points whose value is 1 (or, with
--normalize KEY=VALUE, recomputed from `area_time` over the point with
KEY=VALUE and everything else equal). A column whose values are all integers
(`iccs`, `fifo_depth`, `icc.rti_pipes`, ...) gets integer ticks.

The plot needs Debian's python3-matplotlib (tools/install-deps.sh installs
it). When another python3 comes first on PATH (a pyenv or conda interpreter
without matplotlib), the script runs itself again with /usr/bin/python3.
Exit codes: 0 written, 2 bad input (file, column, value, missing base point),
1 internal error.
"""
import argparse
import csv
import difflib
import json
import math
import os
import sys
import textwrap

from plot_common import need_matplotlib  # (beside this script)


def fail(msg, code=2):
    print(f"plot_sweep: error: {msg}", file=sys.stderr)
    sys.exit(code)


# Axis labels with units for the columns raplas writes; any other column is
# labelled with its name. Speedup, efficiency and area_time_normalized are
# labelled with their base or reference (base_label, normalized_label).
LABELS = {
    "iccs": "ICCs (Intersection Calculation Cores)",
    "fifo_depth": "Triangle FIFO depth (records)",
    "sphere_fifo_depth": "Sphere FIFO depth (records)",
    "planeid_fifo_depth": "PlaneID FIFO depth (spheres)",
    "total_cycles": "total cycles",
    "time_ms": "time at the clock (ms)",
    "passes": "passes",
    "ray_groups": "ray groups",
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
DERIVED = ("speedup", "efficiency")


def no_column(opt, col, path, cols, extra=""):
    near = difflib.get_close_matches(col, sorted(cols), n=1)
    hint = f"; did you mean '{near[0]}'?" if near else f"; the header of {path} lists them"
    fail(f"{opt} {col}: no such column in {path}{extra}{hint}")


def label(col, rows=()):
    if col in ("area", "area_time"):
        return area_label(col, rows)
    return LABELS.get(col, col)


def area_label(col, rows):
    """The area's unit, from the rows' overrides: the paper's PE units (area.model = pe_units) or
    the blocks model's slice-equivalents (the default; docs/MODEL.md §6)."""
    pe = [("area.model=pe_units" in r.get("overrides", "")) for r in rows] if rows and "overrides" in rows[0] else []
    if pe and all(pe):
        unit = "PE units, area.model = pe_units"
    elif pe and not any(pe):
        unit = "slice-equivalents, area.model = blocks"
    else:
        unit = "area units of each row's area.model"
    unit_short = unit.split(",")[0]
    if col == "area":
        return f"area ({unit}; docs/MODEL.md §6)"
    return f"area x time ({unit_short} x cycles)"


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
    reader = csv.DictReader(lines)
    rows = list(reader)
    if not rows:
        fail(f"{path}: no rows (a header and at least one row expected)")
    return reader.fieldnames, rows


def key_value(opt, text, cols, path):
    if "=" not in text:
        fail(f"{opt} '{text}': expected COL=VALUE")
    c, v = text.split("=", 1)
    if c not in cols:
        no_column(opt, c, path, cols)
    return c, v


def same_value(a, b):
    """CSV cells equal as written or as numbers (fifo_depth 1000 = 1000.0)."""
    if a == b:
        return True
    try:
        return float(a) == float(b)
    except ValueError:
        return False


def point_columns(header, a):
    """The columns that name a point, iccs and fifo_depth apart: those before
    `overrides` in a raplas sweep CSV (scene, config, the varied keys; a
    `variant` of a golden table), else scene and the --series and --facet
    columns."""
    if "overrides" in header:
        cols = header[:header.index("overrides")]
    else:
        cols = [c for c in ("scene", a.series, a.facet) if c and c in header]
    return [c for c in cols if c not in ("iccs", "fifo_depth")]


def int_or_text(v):
    x = float(v)
    return str(int(x)) if x == int(x) else v


def rebase(header, rows, kept, a, path):
    """Recomputes speedup and efficiency over the stated base (--base-iccs,
    --base-fifo) for every kept row, the base found among all rows; returns
    the base's description."""
    need = ["total_cycles", "iccs"] + (["fifo_depth"] if a.base_fifo is not None else [])
    for c in need:
        if c not in header:
            no_column("--base-iccs" if a.base_fifo is None else "--base-fifo", c, path, header,
                      " (the base is found by it)")
    ident = point_columns(header, a)
    by, used, keep = {}, set(), {id(r) for r in kept}
    for i, r in enumerate(rows, 1):
        k = tuple(r[c] for c in ident)
        by.setdefault(k, []).append((i, r))
    for k, group in by.items():
        for i, r in group:
            if id(r) not in keep:
                continue
            if a.base_iccs is not None:
                bk = a.base_iccs
            elif r.get("base_iccs", "") != "":
                bk = number(r["base_iccs"], "base_iccs", i)
            else:  # the smallest ICC count of the series (same FIFO depth), as the sweep does
                bk = min(number(x["iccs"], "iccs", j) for j, x in group
                         if "fifo_depth" not in header or same_value(x["fifo_depth"], r["fifo_depth"]))
            bf = r.get("fifo_depth") if a.base_fifo is None else str(a.base_fifo)
            base = [x for j, x in group if number(x["iccs"], "iccs", j) == bk and
                    ("fifo_depth" not in header or same_value(x["fifo_depth"], bf))]
            if not base:
                where = ", ".join(f"{c}={r[c]}" for c in ident)
                fifo = f" and fifo_depth={int_or_text(bf)}" if "fifo_depth" in header else ""
                fail(f"no base point with iccs={bk:g}{fifo} for {where or 'the rows'} in {path} "
                     f"(--base-iccs and --base-fifo name a point of the sweep)")
            cyc = number(r["total_cycles"], "total_cycles", i)
            if cyc <= 0:
                fail(f"column 'total_cycles' is not positive: '{r['total_cycles']}' (data row {i})")
            sp = number(base[0]["total_cycles"], "total_cycles", 0) / cyc
            r["speedup"] = repr(sp)
            r["efficiency"] = repr(sp * bk / number(r["iccs"], "iccs", i))
            r["base_iccs"] = f"{bk:g}"
            used.add(bk)
    for c in DERIVED + ("base_iccs",):
        if c not in header:
            header.append(c)
    k = used.pop() if len(used) == 1 else None
    k = f"{k:g} ICC{'s' if k != 1 else ''}" if k is not None else "the smallest ICC count of each series"
    f = f"FIFO depth {a.base_fifo}" if a.base_fifo is not None else "the same FIFO depth"
    return f"{k} at {f}"


def sweep_base(header, rows):
    """The base of the sweep's own speedup and efficiency columns, in words."""
    ks = {r.get("base_iccs", "") for r in rows}
    same = "the same FIFO depth and keys"
    if len(ks) == 1 and "" not in ks:
        k = int_or_text(ks.pop())
        return f"{k} ICC{'s' if k != '1' else ''} at {same}"
    return f"each series' base_iccs point at {same}"


def normalize(header, rows, kept, spec, path):
    """area_time_normalized of every kept row over the point with KEY=VALUE
    and everything else equal (as raplas sweep --normalize computes it)."""
    c, v = key_value("--normalize", spec, header, path)
    if "area_time" not in header:
        no_column("--normalize", "area_time", path, header)
    ident = [x for x in header[:header.index("overrides")] if x != c] if "overrides" in header else \
        [x for x in ("scene",) if x in header]
    ident += [x for x in ("iccs", "fifo_depth") if x in header and x != c]
    ref = {}
    for i, r in enumerate(rows, 1):
        if same_value(r[c], v):
            ref[tuple(r[x] for x in ident)] = number(r["area_time"], "area_time", i)
    if not ref:
        fail(f"--normalize {spec}: no row has it")
    for i, r in enumerate(rows, 1):
        k = tuple(r[x] for x in ident)
        if not any(r is x for x in kept):
            continue
        if k not in ref:
            fail(f"--normalize {spec}: no reference point for data row {i} "
                 f"({', '.join(f'{x}={r[x]}' for x in ident)})")
        r["area_time_normalized"] = repr(number(r["area_time"], "area_time", i) / ref[k])
    if "area_time_normalized" not in header:
        header.append("area_time_normalized")
    return f"{c} = {v}"


def normalized_reference(header, rows):
    """The KEY = VALUE whose points all have area_time_normalized 1 (what the
    sweep's --normalize named; the CSV does not record it), or None."""
    cand = (header[:header.index("overrides")] if "overrides" in header else []) + ["iccs", "fifo_depth"]
    for c in cand:
        if c not in header or c in ("scene", "config"):
            continue
        for v in sorted({r[c] for r in rows}):
            sel = [r for r in rows if r[c] == v]
            try:
                if sel and len(sel) < len(rows) and all(abs(float(r["area_time_normalized"]) - 1) < 1e-9
                                                        for r in sel):
                    return f"{c} = {v}"
            except ValueError:
                return None
    return None


def integer_valued(vals):
    return bool(vals) and all(float(v).is_integer() for v in vals)


def integer_ticks(ax, axis, vals, log):
    """Ticks at integers only: on x at the values themselves when there are
    few, else (and on y) at integers the locator picks."""
    from matplotlib.ticker import FixedLocator, FuncFormatter, MaxNLocator, NullLocator
    vs = sorted(set(vals))
    a = ax.xaxis if axis == "x" else ax.yaxis
    if axis == "y":
        if not log:
            a.set_major_locator(MaxNLocator(integer=True))
        return
    if len(vs) <= 12 and (log or len(vs) > 1):
        a.set_major_locator(FixedLocator(vs))
        a.set_minor_locator(NullLocator())
    elif log:
        return
    else:
        a.set_major_locator(MaxNLocator(integer=True))
    a.set_major_formatter(FuncFormatter(lambda x, _pos: f"{x:,.0f}" if abs(x) >= 10000 else f"{x:g}"))


def write_axes_json(path, fig, axes):
    """Each panel's title, axis labels, visible ticks with their labels and
    lines (label, x, y), and the figure's title (after the figure was drawn)."""
    def ticks(vals, labels, lim):
        lo, hi = min(lim), max(lim)
        return [[float(v), t.get_text()] for v, t in zip(vals, labels) if lo - 1e-9 * abs(lo) <= v <= hi + 1e-9 * abs(hi)]
    panels = []
    for ax in axes:
        panels.append({"title": ax.get_title(), "xlabel": ax.get_xlabel(), "ylabel": ax.get_ylabel(),
                       "xticks": ticks(ax.get_xticks(), ax.get_xticklabels(), ax.get_xlim()),
                       "yticks": ticks(ax.get_yticks(), ax.get_yticklabels(), ax.get_ylim()),
                       "lines": [{"label": l.get_label(), "x": [float(v) for v in l.get_xdata()],
                                  "y": [float(v) for v in l.get_ydata()]} for l in ax.get_lines()]})
    title = fig._suptitle.get_text() if fig._suptitle is not None else ""
    try:
        with open(path, "w") as f:
            json.dump({"title": title, "panels": panels}, f, indent=1)
    except OSError as e:
        fail(f"{path}: cannot write: {e.strerror}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("--x", required=True, help="column for the x axis")
    ap.add_argument("--y", required=True, help="column for the y axis, or speedup / efficiency")
    ap.add_argument("--series", help="one line per value of this column")
    ap.add_argument("--facet", help="one panel per value of this column")
    ap.add_argument("--where", action="append", default=[], help="COL=VALUE: keep only these rows (repeatable)")
    ap.add_argument("--base-iccs", type=int, metavar="K",
                    help="speedup and efficiency over the point with K ICCs (default: the sweep's base_iccs)")
    ap.add_argument("--base-fifo", type=int, metavar="D",
                    help="speedup and efficiency over the point with FIFO depth D (default: the same FIFO depth)")
    ap.add_argument("--normalize", metavar="KEY=VALUE",
                    help="area_time_normalized over the point with KEY=VALUE and everything else equal")
    ap.add_argument("--out", required=True, help="PNG to write")
    ap.add_argument("--logx", action="store_true")
    ap.add_argument("--logy", action="store_true")
    ap.add_argument("--title")
    ap.add_argument("--axes-json", metavar="FILE",
                    help="also write what each panel shows (labels, ticks, lines) as JSON, for checks")
    a = ap.parse_args()
    if not a.out.endswith(".png"):
        fail(f"--out {a.out}: give a .png file")
    for opt, v in (("--base-iccs", a.base_iccs), ("--base-fifo", a.base_fifo)):
        if v is not None and v < 1:
            fail(f"{opt} {v}: must be at least 1")

    header, rows = read_csv(a.csv)
    header = list(header)
    cols = set(header)
    for opt, c in (("--x", a.x), ("--series", a.series), ("--facet", a.facet)):
        if c and c not in cols:
            no_column(opt, c, a.csv, cols)
    rebased = a.base_iccs is not None or a.base_fifo is not None
    if a.y not in cols and not (a.y in DERIVED and rebased) and not (a.y == "area_time_normalized" and a.normalize):
        extra = (" (raplas sweep writes speedup and efficiency; --base-iccs computes them from total_cycles)"
                 if a.y in DERIVED else "")
        no_column("--y", a.y, a.csv, cols, extra)
    kept = rows
    for w in a.where:
        c, v = key_value("--where", w, cols, a.csv)
        kept = [r for r in kept if r[c] == v]
        if not kept:
            fail(f"--where {w}: no row has it")
    # Derived columns of the kept rows; their base or reference may be a row --where left out.
    ylabel = label(a.y, kept)
    if a.y in DERIVED:
        base = rebase(header, rows, kept, a, a.csv) if rebased else sweep_base(header, kept)
        ylabel = ("speedup (x) over " if a.y == "speedup" else "efficiency (speedup per ICC) over ") + base
    elif rebased:
        fail("--base-iccs and --base-fifo apply to --y speedup or efficiency")
    if a.normalize or a.y == "area_time_normalized":
        if a.y != "area_time_normalized":
            fail("--normalize applies to --y area_time_normalized")
        ref = normalize(header, rows, kept, a.normalize, a.csv) if a.normalize else \
            normalized_reference(header, rows)
        ylabel = (f"area x time, normalised to the point with {ref} (and the same other keys)" if ref else
                  "area x time, normalised to the sweep's --normalize point (not recorded in the CSV)")
    rows = kept

    plt = need_matplotlib(fail)

    def sort_key(v):
        try:
            return (0, float(v), v)
        except ValueError:
            return (1, 0.0, v)

    all_x = [number(r[a.x], a.x, i) for i, r in enumerate(rows, 1)]
    all_y = [number(r[a.y], a.y, i) for i, r in enumerate(rows, 1)]
    base_k = None
    if a.y == "speedup" and a.x == "iccs":
        ks = {number(r["base_iccs"], "base_iccs", i) for i, r in enumerate(rows, 1)} if "base_iccs" in header \
            else {min(all_x)}
        base_k = ks.pop() if len(ks) == 1 else None
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
        ideal = a.x == "iccs" and xs_all and (a.y == "efficiency" or (a.y == "speedup" and base_k))
        if ideal:
            lo, hi = min(xs_all), max(xs_all)
            if a.y == "speedup":
                ax.plot([lo, hi], [lo / base_k, hi / base_k], "k--", linewidth=0.8, label="ideal")
            else:
                ax.axhline(1.0, color="k", linestyle="--", linewidth=0.8, label="ideal")
        ax.set_xlabel(label(a.x, rows))
        if ax is axes[0][0]:
            ax.set_ylabel(textwrap.fill(ylabel, 48))
        if a.logx:
            ax.set_xscale("log", base=2)
        if a.logy:
            ax.set_yscale("log")
        if integer_valued(all_x):
            integer_ticks(ax, "x", all_x, a.logx)
        if integer_valued(all_y) and ax is axes[0][0]:
            integer_ticks(ax, "y", all_y, a.logy)
        if fv is not None:
            ax.set_title(f"{a.facet} = {fv}", fontsize=10)
        ax.grid(True, linewidth=0.3)
        if a.series or ideal:
            ax.legend(fontsize=7)
    title = a.title
    if rebased:
        title = (title + "\n" if title else "") + f"base: {base}"
    if title:
        fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    tmp = a.out + ".tmp.png"
    try:
        fig.savefig(tmp, dpi=110, bbox_inches="tight")
        os.replace(tmp, a.out)
    except OSError as e:
        fail(f"{a.out}: cannot write: {e.strerror}")
    if a.axes_json:
        write_axes_json(a.axes_json, fig, axes[0])
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
