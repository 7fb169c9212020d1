#!/usr/bin/python3
"""Plot the stall anatomy of the Triangle Stream Link (docs/MODEL.md §3, "The
stall anatomy") from one or more results of `raplas simulate --json`.

  tools/plot_anatomy.py RESULT.json... --out PNG [--label TEXT]... [--per-icc I]
                        [--title TEXT] [--axes-json FILE]

Panel 1, one bar per file: the cycles in which the link stalled, split by how
many ICCs' Triangle FIFOs held it (the bins of stall_anatomy.held_by: 1, 2,
3-4, 5-8, ...) and the cycles only undecided spheres held it, stacked, in % of
the run's total_cycles: a bar's length is the share of the run the link
stalled. Each bar is annotated with mean_holders (1: the ICCs' stalls add up;
K: they all coincide).

Panel 2, with one file or --per-icc I (the I-th file, from 0): per ICC, the
cycles its Triangle FIFO held the link (link_blocked_triangle_fifo_full),
split into those in which it alone held it (link_blocked_triangle_fifo_alone)
and those shared with other ICCs (held - alone), stacked.

--label names the files in their order (repeatable, one per file; default:
each file's name without its extension). --axes-json FILE also writes what
each panel shows (categories, each series' name and values) as JSON, for checks.
The PNG is written atomically (a temporary file in its directory, then renamed).

A result of `simulate --frames`, a partial result of `simulate --shard` (merge
the shards first: raplas merge) and an estimate (sim.estimate = sample_passes
or fifo_bound: its anatomy counts the simulated passes only, or none) are
refused. The plot needs Debian's python3-matplotlib (tools/install-deps.sh
installs it); when another python3 without matplotlib comes first on PATH,
the script runs itself again with /usr/bin/python3.
Exit codes: 0 written, 2 bad input (one line on stderr), 1 internal error.
"""
import argparse
import json
import math
import os
import sys
import tempfile

from plot_common import need_matplotlib  # (beside this script)

PROG = "plot_anatomy.py"
WIDE = 256  # more ICCs than this: the per-ICC panel draws steps, not bars


def fail(msg, code=2):
    print(f"{PROG}: error: {msg}", file=sys.stderr)
    sys.exit(code)


class Parser(argparse.ArgumentParser):
    """argparse with its errors on one line (no usage), exit 2."""

    def error(self, message):
        fail(message)


def count(path, obj, key, where):
    """obj[key] as a finite number >= 0, or one line naming the file and key."""
    if not isinstance(obj, dict) or key not in obj:
        fail(f"{path}: no '{where}{key}'")
    v = obj[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
        fail(f"{path}: '{where}{key}' is not a count: {json.dumps(v)}")
    return v


def load(path):
    """The stall anatomy of one result of raplas simulate --json, checked."""
    try:
        with open(path, "rb") as f:
            text = f.read()
    except OSError as e:
        fail(f"{path}: cannot read: {e.strerror}")
    try:
        j = json.loads(text)
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        where = f" at line {e.lineno}" if isinstance(e, json.JSONDecodeError) else ""
        fail(f"{path}: not JSON ({getattr(e, 'msg', 'not UTF-8')}{where})")
    if not isinstance(j, dict):
        fail(f"{path}: not a result of raplas simulate --json (not a JSON object)")
    if "raplas_partial" in j:
        fail(f"{path}: a partial result of raplas simulate --shard; merge the shards first (raplas merge --json)")
    if "frames" in j and "stall_anatomy" not in j:
        fail(f"{path}: a result of raplas simulate --frames (an anatomy per frame, without the ICCs' figures); "
             f"give one frame's result (simulate --frame F --json)")
    if "stall_anatomy" not in j:
        if "total_cycles" in j and "iccs_detail" in j:
            fail(f"{path}: no 'stall_anatomy': a result of an older raplas simulate, which did not write it")
        fail(f"{path}: no 'stall_anatomy': not a result of raplas simulate --json")
    est = j.get("estimate")
    if isinstance(est, dict):
        mode = est.get("mode")
        why = ("a lower bound in closed form: nothing was simulated, its stall anatomy is empty"
               if mode == "fifo_bound" else
               "its total_cycles is estimated, its stall anatomy counts the simulated passes only")
        fail(f"{path}: an estimate (estimate.mode = {mode}): {why}; plot an exact run")
    a = j["stall_anatomy"]
    if not isinstance(a, dict):
        fail(f"{path}: 'stall_anatomy' is not an object")
    total = count(path, j, "total_cycles", "")
    if total == 0:
        fail(f"{path}: 'total_cycles' is 0")
    w = "stall_anatomy."
    stalled = count(path, a, "triangle_link_stall_cycles", w)
    held = count(path, a, "fifo_held_cycles", w)
    undecided = count(path, a, "undecided_only_cycles", w)
    mean = count(path, a, "mean_holders", w)
    bins = a.get("held_by")
    if not isinstance(bins, list):
        fail(f"{path}: no '{w}held_by' list")
    by = []
    for i, b in enumerate(bins):
        name = b.get("iccs") if isinstance(b, dict) else None
        if not isinstance(name, str) or not holders(name):
            fail(f"{path}: '{w}held_by[{i}].iccs' is not a holder count or range: {json.dumps(name)}")
        by.append((name, count(path, b, "cycles", f"{w}held_by[{i}].")))
    if sum(c for _, c in by) != held or held + undecided != stalled:
        fail(f"{path}: '{w}held_by' ({sum(c for _, c in by)}) and undecided_only_cycles ({undecided}) do not "
             f"add up to fifo_held_cycles ({held}) and triangle_link_stall_cycles ({stalled})")
    if stalled > total:
        fail(f"{path}: '{w}triangle_link_stall_cycles' ({stalled}) exceeds total_cycles ({total})")
    return {"json": j, "total": total, "stalled": stalled, "undecided": undecided, "mean": mean, "by": by}


def holders(name):
    """(lo, hi) of a held_by bin name ("1", "3-4"), or None."""
    lo, _, hi = name.partition("-")
    try:
        lo, hi = int(lo), int(hi or lo)
    except ValueError:
        return None
    return (lo, hi) if 1 <= lo <= hi else None


def per_icc(path, j):
    """[(icc, held, alone)] of a result's iccs_detail."""
    d = j.get("iccs_detail")
    if not isinstance(d, list) or not d:
        fail(f"{path}: no 'iccs_detail' list (the per-ICC panel needs it)")
    rows = []
    for k, c in enumerate(d):
        where = f"iccs_detail[{k}].stall_cycles."
        s = c.get("stall_cycles") if isinstance(c, dict) else None
        if not isinstance(s, dict):
            fail(f"{path}: no 'iccs_detail[{k}].stall_cycles'")
        held = count(path, s, "link_blocked_triangle_fifo_full", where)
        alone = count(path, s, "link_blocked_triangle_fifo_alone", where)
        if alone > held:
            fail(f"{path}: '{where}link_blocked_triangle_fifo_alone' ({alone}) exceeds "
                 f"link_blocked_triangle_fifo_full ({held})")
        icc = c.get("icc", k)
        rows.append((icc if isinstance(icc, int) and not isinstance(icc, bool) else k, held, alone))
    return rows


def bin_label(name):
    return f"held by {name} ICC{'' if name == '1' else 's'}"


def writable_dir(opt, path):
    d = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(d):
        fail(f"{opt} {path}: the directory {d} does not exist")
    if os.path.isdir(path):
        fail(f"{opt} {path}: is a directory")
    return d


def replace_atomically(path, write):
    """Calls write(temporary path) for a temporary file in path's directory,
    then renames it to path."""
    tmp = None
    try:
        fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", suffix=".tmp",
                                   dir=os.path.dirname(os.path.abspath(path)))
        os.close(fd)
        write(tmp)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except OSError as e:
        fail(f"{path}: cannot write: {e.strerror}")
    finally:
        if tmp is not None and os.path.exists(tmp):
            os.unlink(tmp)


def axes_json(fig, panels):
    """Per panel: its title, axis labels, categories (the tick labels of the
    category axis), each bar series' name, values (bar lengths) and starts,
    and the annotations."""
    import numpy as np
    out = []
    for ax, horizontal in panels:
        series = []
        for c in ax.containers:
            ps = list(c.patches)
            series.append({"name": c.get_label(),
                           "values": [float(p.get_width() if horizontal else p.get_height()) for p in ps],
                           "starts": [float(p.get_x() if horizontal else p.get_y()) for p in ps]})
        for p in ax.patches:  # the stepped series of a per-ICC panel of many ICCs
            if type(p).__name__ == "StepPatch":
                d = p.get_data()
                base = [float(b) for b in np.broadcast_to(d.baseline, np.shape(d.values))]
                series.append({"name": p.get_label(), "values": [float(v) - b for v, b in zip(d.values, base)],
                               "starts": base})
        ticks = ax.get_yticklabels() if horizontal else ax.get_xticklabels()
        out.append({"title": ax.get_title(), "xlabel": ax.get_xlabel(), "ylabel": ax.get_ylabel(),
                    "categories": [t.get_text() for t in ticks],
                    "series": series, "annotations": [t.get_text() for t in ax.texts]})
    title = fig._suptitle.get_text() if fig._suptitle is not None else ""
    return {"title": title, "panels": out}


def anatomy_panel(ax, runs, labels):
    """Stacked horizontal bars, one per run, in % of its total_cycles."""
    names = sorted({n for r in runs for n, _ in r["by"]}, key=holders)
    n = len(names)
    pos = list(range(len(runs)))
    left = [0.0] * len(runs)
    import matplotlib.pyplot as plt
    cmap = plt.get_cmap("viridis")
    for i, name in enumerate(names):
        vals = [100.0 * dict(r["by"]).get(name, 0) / r["total"] for r in runs]
        ax.barh(pos, vals, left=left, height=0.6, color=cmap(0.9 * i / max(n - 1, 1)), label=bin_label(name))
        left = [a + b for a, b in zip(left, vals)]
    vals = [100.0 * r["undecided"] / r["total"] for r in runs]
    ax.barh(pos, vals, left=left, height=0.6, color="0.8", hatch="//", edgecolor="0.55", linewidth=0,
            label="undecided spheres only")
    ends = [100.0 * r["stalled"] / r["total"] for r in runs]
    top = max(ends) if max(ends) > 0 else 1.0
    for p, e, r in zip(pos, ends, runs):
        ax.text(e + 0.02 * top, p, f"{e:.1f} % stalled, mean holders {r['mean']:.2f}",
                va="center", ha="left", fontsize=8)
    ax.set_xlim(0, top * 1.6)
    ax.set_yticks(pos)
    ax.set_yticklabels(labels)
    ax.set_ylim(len(runs) - 0.5, -0.5)  # the first file on top
    ax.set_xlabel("Triangle Stream Link stalled cycles (% of the run's total cycles)")
    ax.set_title("stalled cycles by how many ICCs' Triangle FIFOs held the link", fontsize=10)
    ax.grid(True, axis="x", linewidth=0.3)
    ax.set_axisbelow(True)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)


def icc_panel(ax, rows, label):
    from matplotlib.ticker import FuncFormatter, MaxNLocator
    x = [r[0] for r in rows]
    alone = [r[2] for r in rows]
    shared = [r[1] - r[2] for r in rows]
    names = ("alone (no other ICC's FIFO held it)", "shared (held - alone)")
    if len(rows) > WIDE and hasattr(ax, "stairs") and x == list(range(x[0], x[0] + len(x))):
        # Thousands of bars take seconds to draw; a stepped outline per series is the same picture.
        edges = [x[0] - 0.5 + i for i in range(len(x) + 1)]
        held = [a + s for a, s in zip(alone, shared)]
        ax.stairs(alone, edges, baseline=0, fill=True, color="tab:blue", label=names[0])
        ax.stairs(held, edges, baseline=alone, fill=True, color="tab:orange", label=names[1])
    else:
        kw = {"width": 1.0 if len(rows) > 64 else 0.8, "linewidth": 0}
        ax.bar(x, alone, color="tab:blue", label=names[0], **kw)
        ax.bar(x, shared, bottom=alone, color="tab:orange", label=names[1], **kw)
    ax.set_xlim(min(x) - 0.6, max(x) + 0.6)
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.yaxis.set_major_locator(MaxNLocator(integer=True))
    ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:,.0f}"))
    ax.set_xlabel("ICC")
    ax.set_ylabel("cycles its Triangle FIFO\nheld the link")
    ax.set_title(f"{label}: per ICC, the cycles its Triangle FIFO held the Triangle Stream Link", fontsize=10)
    ax.grid(True, axis="y", linewidth=0.3)
    ax.set_axisbelow(True)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)


def main():
    ap = Parser(prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", nargs="+", metavar="RESULT.json", help="results of raplas simulate --json")
    ap.add_argument("--out", required=True, metavar="PNG", help="PNG to write")
    ap.add_argument("--label", action="append", default=[], help="a file's label, in the files' order (repeatable)")
    ap.add_argument("--per-icc", type=int, metavar="I", help="per-ICC panel of the I-th file (0: the first; "
                    "default: with one file, that file)")
    ap.add_argument("--title")
    ap.add_argument("--axes-json", metavar="FILE",
                    help="also write what each panel shows (categories, series and values) as JSON, for checks")
    a = ap.parse_args()
    if not a.out.endswith(".png"):
        fail(f"--out {a.out}: give a .png file")
    writable_dir("--out", a.out)
    if a.axes_json:
        writable_dir("--axes-json", a.axes_json)
    if a.label and len(a.label) != len(a.results):
        fail(f"--label given {len(a.label)} time{'s' if len(a.label) != 1 else ''} for {len(a.results)} "
             f"file{'s' if len(a.results) != 1 else ''}: give one per file, in their order, or none")
    if a.per_icc is not None and not 0 <= a.per_icc < len(a.results):
        fail(f"--per-icc {a.per_icc}: no such file (0 to {len(a.results) - 1})")
    labels = a.label or [os.path.splitext(os.path.basename(p))[0] for p in a.results]
    runs = [load(p) for p in a.results]
    detail = a.per_icc if a.per_icc is not None else (0 if len(runs) == 1 else None)
    rows = per_icc(a.results[detail], runs[detail]["json"]) if detail is not None else None

    plt = need_matplotlib(fail)
    h1 = 1.3 + 0.5 * len(runs)
    if rows is None:
        fig, ax1 = plt.subplots(figsize=(10, h1))
        panels = [(ax1, True)]
    else:
        fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(10, h1 + 3.4), gridspec_kw={"height_ratios": [h1, 3.4]})
        panels = [(ax1, True), (ax2, False)]
    anatomy_panel(ax1, runs, labels)
    if rows is not None:
        icc_panel(ax2, rows, labels[detail])
    if a.title:
        fig.suptitle(a.title, fontsize=11)
    fig.tight_layout()
    replace_atomically(a.out, lambda tmp: fig.savefig(tmp, format="png", dpi=110, bbox_inches="tight"))
    if a.axes_json:
        text = json.dumps(axes_json(fig, panels), indent=1) + "\n"

        def write(tmp):
            with open(tmp, "w") as f:
                f.write(text)
        replace_atomically(a.axes_json, write)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
