#!/usr/bin/env python3
"""Hybrid SIC against pure dynamic SIC over an ensemble (issue #24, docs/validation.md).

Reads the task directories of two steps of a study (default: the series B study,
data/studies/series-b.toml: step "sic", the biaxial SIC at dq = 1e-2, and step "sic-hybrid"),
and compares, up to epsilon_2 = 0.01 (or the smallest last equilibrium of either group):
  - the mean +- rms of q on a common epsilon_2 grid: the largest |mean_h - mean_d| over the
    combined scatter sqrt(rms_h^2 + rms_d^2) (they agree within their scatter when <= 1);
  - the strain jumps of the increments, Delta epsilon_2 between consecutive equilibria at
    q = k dq (the MD states and the on-grid static states of the hybrid), pooled over the
    samples: quantiles, and the two-sample Kolmogorov-Smirnov distance with its asymptotic p.
Writes OUT/hybrid_vs_dynamic.json and OUT/hybrid_vs_dynamic.png.

  /usr/bin/python3 scripts/validate_hybrid_sic.py [--study DIR] [--dynamic STEP]
      [--hybrid STEP] [--epsilon-2 X] [--out DIR]
"""
import argparse
import csv
import glob
import json
import math
import os

import numpy as np


def read_equilibria(path):
    with open(path) as f:
        rows = [r for r in csv.DictReader(f) if r.get("reached", "1") in ("1", "1.0")]
    on_grid = [r.get("on_grid", "1") == "1" for r in rows]
    col = lambda k: np.array([float(r[k]) for r in rows])  # noqa: E731
    return {"q_target": col("q_target"), "q": col("q"), "epsilon_2": col("epsilon_2"),
            "on_grid": np.array(on_grid)}


def curves_of(study, step):
    out = {}
    for d in sorted(glob.glob(os.path.join(study, step, "*"))):
        for name in ("sic_curve.csv", "curve.csv"):
            p = os.path.join(d, name)
            if os.path.exists(p):
                out[os.path.basename(d)] = read_equilibria(p)
                break
    return out


def md_steps_to(path, end):
    """MD steps of a SIC run up to its first equilibrium with epsilon_2 >= end (all of them when
    it never gets there)."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    key = "md_steps" if "md_steps" in rows[0] else "increment_steps"
    total = 0
    for r in rows:
        total += int(float(r[key]))
        if r.get("reached", "1") in ("1", "1.0") and float(r["epsilon_2"]) >= end:
            break
    return total


def monotone(c):
    """epsilon_2 and q up to the first maximum of epsilon_2 (a monotone abscissa)."""
    e2, q = c["epsilon_2"], c["q"]
    keep = e2 >= np.maximum.accumulate(e2)
    e2, first = np.unique(e2[keep], return_index=True)
    return e2, q[keep][first]


def jumps(c, end):
    """Delta epsilon_2 of every increment q = k dq -> (k + 1) dq that starts below `end`."""
    g = c["on_grid"]
    e2 = c["epsilon_2"][g]
    d = np.diff(e2)
    return d[e2[:-1] < end]


def ks(a, b):
    a, b = np.sort(a), np.sort(b)
    x = np.concatenate([a, b])
    fa = np.searchsorted(a, x, side="right") / a.size
    fb = np.searchsorted(b, x, side="right") / b.size
    d = float(np.max(np.abs(fa - fb)))
    n = a.size * b.size / (a.size + b.size)
    lam = (math.sqrt(n) + 0.12 + 0.11 / math.sqrt(n)) * d
    p = 2.0 * sum((-1) ** (k - 1) * math.exp(-2.0 * k * k * lam * lam) for k in range(1, 101))
    return d, min(max(p, 0.0), 1.0)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--study", default="results/studies/series-b")
    ap.add_argument("--dynamic", default="sic")
    ap.add_argument("--hybrid", default="sic-hybrid")
    ap.add_argument("--epsilon-2", type=float, default=0.01)
    ap.add_argument("--out", default="results/validation/hybrid-sic")
    a = ap.parse_args()
    groups = {"dynamic": curves_of(a.study, a.dynamic), "hybrid": curves_of(a.study, a.hybrid)}
    common = sorted(set(groups["dynamic"]) & set(groups["hybrid"]))
    if not common:
        raise SystemExit(f"no sample with both {a.dynamic} and {a.hybrid} under {a.study}")
    # A run that fails (no equilibrium at the next increment: the sample flows) before the target
    # holds its last q beyond its last equilibrium: an SIC curve is flat at failure. np.interp
    # continues each curve so.
    top = a.epsilon_2
    last = {g: {s: float(monotone(groups[g][s])[0][-1]) for s in common} for g in groups}
    grid = np.linspace(0.0, top, 201)
    stats = {}
    for g in groups:
        qs = np.array([np.interp(grid, *monotone(groups[g][s])) for s in common])
        stats[g] = {"mean": qs.mean(0), "rms": qs.std(0)}
    scatter = np.sqrt(stats["hybrid"]["rms"] ** 2 + stats["dynamic"]["rms"] ** 2)
    diff = np.abs(stats["hybrid"]["mean"] - stats["dynamic"]["mean"])
    ratio = np.where(scatter > 0, diff / np.maximum(scatter, 1e-300), 0.0)[1:]
    pooled = {g: np.concatenate([jumps(groups[g][s], top) for s in common]) for g in groups}
    d, p = ks(pooled["hybrid"], pooled["dynamic"])
    quant = {g: {k: float(np.quantile(pooled[g], v)) for k, v in
                 (("median", 0.5), ("p90", 0.9), ("p99", 0.99))} | {
                     "max": float(pooled[g].max()), "mean": float(pooled[g].mean()),
                     "count": int(pooled[g].size)} for g in groups}
    result = {
        "samples": common, "epsilon_2_top": top,
        "last_equilibrium_epsilon_2": last,
        "common_range_epsilon_2": min(min(v.values()) for v in last.values()),
        "max_mean_difference_over_scatter_in_common_range": float(
            ratio[grid[1:] <= min(min(v.values()) for v in last.values())].max(initial=0.0)),
        "max_mean_difference_over_scatter": float(ratio.max()),
        "mean_difference_over_scatter": float(ratio.mean()),
        "q_at_top": {g: [float(stats[g]["mean"][-1]), float(stats[g]["rms"][-1])]
                     for g in groups},
        "jumps": quant, "ks_distance": d, "ks_p": p,
    }
    steps = {}
    for s in common:
        steps[s] = {}
        for g, step in (("dynamic", a.dynamic), ("hybrid", a.hybrid)):
            d_ = os.path.join(a.study, step, s)
            name = "sic_curve.csv" if os.path.exists(os.path.join(d_, "sic_curve.csv")) else \
                "curve.csv"
            steps[s][g] = md_steps_to(os.path.join(d_, name), a.epsilon_2)
    result["md_steps_to_epsilon_2"] = steps
    result["md_steps_ratio"] = sum(v["dynamic"] for v in steps.values()) / max(
        1, sum(v["hybrid"] for v in steps.values()))
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "hybrid_vs_dynamic.json"), "w") as f:
        json.dump(result, f, indent=1)
    print(json.dumps(result, indent=1))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for g, colour in (("dynamic", "0.4"), ("hybrid", "#1f78b4")):
        m, r = stats[g]["mean"], stats[g]["rms"]
        ax[0].plot(grid, m, color=colour, label=f"{g} SIC, mean of {len(common)}")
        ax[0].fill_between(grid, m - r, m + r, color=colour, alpha=0.25)
        x = np.sort(pooled[g][pooled[g] > 0])
        ax[1].semilogx(x, np.arange(1, x.size + 1) / x.size, color=colour, label=g)
    ax[0].set_xlabel(r"$\epsilon_2$")
    ax[0].set_ylabel("$q$ (mean $\\pm$ rms)")
    ax[0].legend(fontsize=8)
    ax[1].set_xlabel(r"strain jump of an increment $\Delta\epsilon_2$")
    ax[1].set_ylabel("cumulative fraction")
    ax[1].set_title(f"KS distance {d:.3f} (p = {p:.2g})", fontsize=9)
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "hybrid_vs_dynamic.png"), dpi=130)


if __name__ == "__main__":
    main()
