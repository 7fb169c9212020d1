#!/usr/bin/env python3
"""Measured error of the estimate modes (sim.estimate = sample_passes and
fifo_bound) against the exact event mode, with the model's wall time of each.

For each scene (trace written once), ICC count and FIFO depth: per sample
fraction and seed, the sampled-pass estimate, its error, its 95 % half-width
and whether the exact value lies inside it; and the closed-form lower bound
(fifo_bound), its error and whether it lies at or below the exact value
(column inside_ci95: "inside its bound"). Both model wall times. Writes a
CSV and a Markdown table.

  tools/estimate_error.py [--raplas build/raplas] [--out docs/results/estimate_error]
      [--scene scenes/bunny.toml ...] [--iccs 1,16,48] [--fifo 10,1000]
      [--fractions 0.05,0.1,0.25] [--seeds 1,2,3]
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile


READING = ["any"]


def simulate(raplas, trace, iccs, fifo, extra, tmp):
    out = os.path.join(tmp, "sim.json")
    subprocess.run([raplas, "simulate", "--trace", trace, "--config", "paper", "--iccs", str(iccs),
                    "--fifo", str(fifo), "--set", "sim.functional=trace", "--set", f"icc.triangle_select={READING[0]}",
                    *extra, "--json", out, "-q"],
                   check=True)
    return json.load(open(out))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--raplas", default="build/raplas")
    ap.add_argument("--out", default="docs/results/estimate_error")
    ap.add_argument("--scene", action="append")
    ap.add_argument("--iccs", default="1,16,48")
    ap.add_argument("--fifo", default="10,1000")
    ap.add_argument("--fractions", default="0.05,0.1,0.25")
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--reading", choices=["both", "any"], default="any",
                    help="Triangle Selector reading, icc.triangle_select (docs/results/estimate_error.* were made with both)")
    a = ap.parse_args()
    READING[0] = a.reading
    scenes = a.scene or ["scenes/bunny.toml", "scenes/sportscar.toml", "scenes/conference.toml"]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for scene in scenes:
            name = os.path.splitext(os.path.basename(scene))[0]
            trace = os.path.join(tmp, name + ".trace")
            subprocess.run([a.raplas, "trace", "--scene", scene, "--out", trace, "-q"], check=True)
            for k in map(int, a.iccs.split(",")):
                for d in map(int, a.fifo.split(",")):
                    exact = simulate(a.raplas, trace, k, d, [], tmp)
                    bound = simulate(a.raplas, trace, k, d, ["--set", "sim.estimate=fifo_bound"], tmp)
                    x, y = exact["total_cycles"], bound["total_cycles"]
                    rows.append({
                        "estimate": "fifo_bound", "scene": name, "iccs": k, "fifo_depth": d, "fraction": "",
                        "seed": "", "passes": exact["passes"], "passes_simulated": 0,
                        "exact_cycles": x, "estimate_cycles": y, "error_pct": round(100.0 * (y - x) / x, 3),
                        "ci95_pct": "", "inside_ci95": y <= x,
                        "exact_model_s": round(exact["wall"]["model_s"], 3),
                        "estimate_model_s": round(bound["wall"]["model_s"], 3),
                    })
                    print(",".join(str(v) for v in rows[-1].values()), flush=True)
                    for frac in map(float, a.fractions.split(",")):
                        for seed in map(int, a.seeds.split(",")):
                            est = simulate(a.raplas, trace, k, d, ["--set", "sim.estimate=sample_passes",
                                                                   "--set", f"sim.sample_fraction={frac}",
                                                                   "--set", f"sim.sample_seed={seed}"], tmp)
                            e = est.get("estimate", {"ci95_cycles": 0.0, "passes_simulated": est["passes"]})
                            x, y = exact["total_cycles"], est["total_cycles"]
                            rows.append({
                                "estimate": "sample_passes", "scene": name, "iccs": k, "fifo_depth": d, "fraction": frac, "seed": seed,
                                "passes": exact["passes"], "passes_simulated": e["passes_simulated"],
                                "exact_cycles": x, "estimate_cycles": y,
                                "error_pct": round(100.0 * (y - x) / x, 3),
                                "ci95_pct": round(100.0 * e["ci95_cycles"] / x, 3),
                                "inside_ci95": abs(y - x) <= e["ci95_cycles"],
                                "exact_model_s": round(exact["wall"]["model_s"], 3),
                                "estimate_model_s": round(est["wall"]["model_s"], 3),
                            })
                            print(",".join(str(v) for v in rows[-1].values()), flush=True)
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    tmp_csv = a.out + ".csv.tmp"
    with open(tmp_csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    os.replace(tmp_csv, a.out + ".csv")
    # Markdown: per scene and fraction, over ICCs x FIFO x seeds
    lines = ["| scene | fraction | points | mean abs error | max abs error | mean 95 % half-width | inside half-width | model time, exact → estimate |",
             "|---|---|---|---|---|---|---|---|"]
    sampled = [r for r in rows if r["estimate"] == "sample_passes"]
    for name in dict.fromkeys(r["scene"] for r in sampled):
        for frac in dict.fromkeys(r["fraction"] for r in sampled):
            rs = [r for r in sampled if r["scene"] == name and r["fraction"] == frac]
            errs = [abs(r["error_pct"]) for r in rs]
            te = sum(r["exact_model_s"] for r in rs)
            ts = sum(r["estimate_model_s"] for r in rs)
            lines.append(f"| {name} | {frac:g} | {len(rs)} | {sum(errs) / len(errs):.2f} % | {max(errs):.2f} % | "
                         f"{sum(r['ci95_pct'] for r in rs) / len(rs):.2f} % | "
                         f"{sum(r['inside_ci95'] for r in rs)}/{len(rs)} | {te:.1f} s → {ts:.1f} s |")
    lines += ["", "Closed-form lower bound (`sim.estimate = fifo_bound`):", "",
              "| scene | FIFO depth | points | mean error | worst error | at or below exact | model time, exact → bound |",
              "|---|---|---|---|---|---|---|"]
    bounds = [r for r in rows if r["estimate"] == "fifo_bound"]
    for name in dict.fromkeys(r["scene"] for r in bounds):
        for d in dict.fromkeys(r["fifo_depth"] for r in bounds):
            rs = [r for r in bounds if r["scene"] == name and r["fifo_depth"] == d]
            errs = [r["error_pct"] for r in rs]
            te = sum(r["exact_model_s"] for r in rs)
            tb = sum(r["estimate_model_s"] for r in rs)
            lines.append(f"| {name} | {d} | {len(rs)} | {sum(errs) / len(errs):.2f} % | {min(errs):.2f} % | "
                         f"{sum(r['inside_ci95'] for r in rs)}/{len(rs)} | {te:.2f} s → {tb:.3f} s |")
    tmp_md = a.out + ".md.tmp"
    with open(tmp_md, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(tmp_md, a.out + ".md")
    print("\n".join(lines))


if __name__ == "__main__":
    sys.exit(main())
