#!/usr/bin/env python3
"""The report of a granstab study (`granstab study FILE --report`, docs/studies.md).

    study_report.py OUT_DIR

Reads OUT_DIR/study.json (written by the runner) and the outputs of every finished task, writes
OUT_DIR/summary.csv and summary.json (one row per point; per group the mean +- rms of the
scalars; per-N fits), OUT_DIR/curves/*.csv (per group and step: mean +- rms of q and epsilon_v
on a common epsilon_2 grid) and OUT_DIR/plots/*.png. A group is the points that differ only in
the grid key `seed`. "rms" is the root mean square deviation from the mean over the group's
samples (divided by n, not n - 1), the width the reference study plots.
"""
import csv
import json
import math
import os
import sys

import numpy as np

GRID_POINTS = 201  # of the common epsilon_2 grid


def read_json(path):
    with open(path) as f:
        return json.load(f)


def read_curve(path):
    """q, epsilon_2, epsilon_v of a static_curve.csv or a biaxial CSV (SIC: equilibria only)."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if rows and "reached" in rows[0]:
        rows = [r for r in rows if r["reached"] in ("1", "1.0")]
    def column(name):
        return np.array([float(r[name]) if r[name] not in ("", "null") else np.nan for r in rows])
    return {k: column(k) for k in ("q", "epsilon_2", "epsilon_v")}


def scalars_of(command, directory):
    """The per-task numbers of the summary: prepared state, q1, biaxial end, times."""
    d = {}
    if command == "prepare":
        s = read_json(os.path.join(directory, "summary.json"))
        for k in ("phi", "z", "x0", "wall_seconds"):
            d[k] = s.get(k)
        d["x_s"] = s.get("measurements", {}).get("x_s")
    elif command == "q1":
        s = read_json(os.path.join(directory, "q1.json"))
        for k in ("q1", "criterion", "q_max_rigid", "n_sliding_at_q1", "steps", "wall_seconds"):
            d[k] = s.get(k)
    elif command == "biaxial":
        s = read_json(os.path.join(directory, "summary.json"))
        for k in ("stop_reason", "q_last_equilibrium", "steps", "wall_seconds"):
            d[k] = s.get(k)
        final = s.get("final", {})
        for k in ("q", "epsilon_2", "epsilon_v"):
            d["final_" + k] = final.get(k)
    elif command == "sic":
        s = read_json(os.path.join(directory, "sic.json"))
        for k in ("method", "stop_reason", "q_last", "epsilon_2_last", "stability_intervals",
                  "rearrangements", "md_steps", "static_states", "static_seconds",
                  "dynamic_seconds"):
            d[k] = s.get(k)
    elif command == "compare":
        s = read_json(os.path.join(directory, "compare.json"))
        for k, v in s.items():
            if isinstance(v, (int, float, str)) and not isinstance(v, bool):
                d[k] = v
    return d


def curve_file(command, directory):
    name = {"q1": "static_curve.csv", "biaxial": "curve.csv", "sic": "sic_curve.csv"}.get(command)
    return os.path.join(directory, name) if name else None


def mean_rms(values):
    v = np.asarray([x for x in values if x is not None and np.isfinite(x)], dtype=float)
    if v.size == 0:
        return None, None, 0
    m = float(v.mean())
    return m, float(np.sqrt(np.mean((v - m) ** 2))), int(v.size)


def fit_inverse_sqrt(n, y):
    """Least squares y = a + b / sqrt(N): (a, b); a is the large-N limit."""
    x = 1.0 / np.sqrt(np.asarray(n, dtype=float))
    y = np.asarray(y, dtype=float)
    if len(set(x)) < 2:
        return None, None
    b, a = np.polyfit(x, y, 1)
    return float(a), float(b)


def average_curves(curves):
    """Mean and rms of q and epsilon_v of several curves on a common grid of epsilon_2, from 0 to
    the smallest largest epsilon_2 (every sample contributes at every grid point). Each curve is
    taken up to its first maximum of epsilon_2 (a monotone abscissa)."""
    tops = []
    cleaned = []
    for c in curves:
        e2, ok = c["epsilon_2"], np.isfinite(c["epsilon_2"]) & np.isfinite(c["q"])
        e2, q, ev = e2[ok], c["q"][ok], c["epsilon_v"][ok]
        if e2.size < 2:
            continue
        keep = e2 >= np.maximum.accumulate(e2)  # drop the points where epsilon_2 goes back
        e2, q, ev = e2[keep], q[keep], ev[keep]
        e2, first = np.unique(e2, return_index=True)
        cleaned.append((e2, q[first], ev[first]))
        tops.append(e2[-1])
    if not cleaned:
        return None
    grid = np.linspace(max(c[0][0] for c in cleaned), min(tops), GRID_POINTS)
    qs = np.array([np.interp(grid, e2, q) for e2, q, _ in cleaned])
    evs = np.array([np.interp(grid, e2, ev) for e2, _, ev in cleaned])
    return {"epsilon_2": grid, "q_mean": qs.mean(0), "q_rms": qs.std(0),
            "epsilon_v_mean": evs.mean(0), "epsilon_v_rms": evs.std(0), "samples": len(cleaned)}


def label(values):
    return "_".join(f"{k}-{v}" for k, v in values.items()) or "all"


def report(out):
    plan = read_json(os.path.join(out, "study.json"))
    steps = plan["steps"]
    keys = list(plan["grid"])
    group_keys = [k for k in keys if k != "seed"]

    rows = []
    for point in plan["points"]:
        row = dict(point["values"])
        for step in steps:
            directory = os.path.join(out, point["steps"][step["name"]])
            row[step["name"] + ".done"] = os.path.exists(os.path.join(directory, ".done"))
            if row[step["name"] + ".done"]:
                for k, v in scalars_of(step["command"], directory).items():
                    row[step["name"] + "." + k] = v
        rows.append(row)
    columns = []
    for r in rows:
        columns += [c for c in r if c not in columns]

    # Groups: the points that differ only in the seed.
    groups = {}
    for point, row in zip(plan["points"], rows):
        g = tuple(point["values"][k] for k in group_keys)
        groups.setdefault(g, []).append((point, row))
    group_stats = []
    os.makedirs(os.path.join(out, "curves"), exist_ok=True)
    curves_of = {}
    for g, members in groups.items():
        values = dict(zip(group_keys, g))
        stats = {"values": values, "samples": len(members)}
        for c in columns:
            if c in keys or c.endswith(".done"):
                continue
            xs = [r.get(c) for _, r in members]
            if all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in xs if x is not None) \
                    and any(x is not None for x in xs):
                m, s, n = mean_rms(xs)
                stats[c] = {"mean": m, "rms": s, "n": n}
        for step in steps:
            if step["command"] not in ("q1", "biaxial"):
                continue
            files = []
            for point, row in members:
                if row.get(step["name"] + ".done"):
                    files.append(curve_file(step["command"], os.path.join(out, point["steps"][step["name"]])))
            avg = average_curves([read_curve(f) for f in files if os.path.exists(f)])
            if avg is None:
                continue
            name = os.path.join("curves", f"{step['name']}__{label(values)}.csv")
            with open(os.path.join(out, name), "w") as f:
                cols = ["epsilon_2", "q_mean", "q_rms", "epsilon_v_mean", "epsilon_v_rms"]
                f.write(",".join(cols) + "\n")
                for k in range(len(avg["epsilon_2"])):
                    f.write(",".join(repr(float(avg[c][k])) for c in cols) + "\n")
            stats[step["name"] + ".curve"] = {"file": name, "samples": avg["samples"],
                                              "mean_q_rms": float(avg["q_rms"].mean())}
            curves_of.setdefault(step["name"], []).append((values, avg))
        group_stats.append(stats)

    # Against N: the groups that differ only in n.
    scaling = []
    if "n" in group_keys:
        others = [k for k in group_keys if k != "n"]
        families = {}
        for s in group_stats:
            families.setdefault(tuple(s["values"][k] for k in others), []).append(s)
        for f, members in families.items():
            members.sort(key=lambda s: float(s["values"]["n"]))
            n = [float(s["values"]["n"]) for s in members]
            entry = {"values": dict(zip(others, f)), "n": n}
            for quantity in [c for c in members[0] if isinstance(members[0][c], dict) and "mean" in members[0][c]]:
                if not all(quantity in s and s[quantity]["mean"] is not None for s in members):
                    continue
                mean = [s[quantity]["mean"] for s in members]
                rms = [s[quantity]["rms"] for s in members]
                a, b = fit_inverse_sqrt(n, mean)
                wa, wb = fit_inverse_sqrt(n, rms)
                entry[quantity] = {"mean": mean, "rms": rms, "large_n_limit": a, "slope_mean": b,
                                   "width_intercept": wa, "width_slope": wb}
            scaling.append(entry)

    with open(os.path.join(out, "summary.csv.tmp"), "w", newline="") as f:
        w = csv.DictWriter(f, columns)
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if v is None else v) for k, v in r.items()})
    os.replace(os.path.join(out, "summary.csv.tmp"), os.path.join(out, "summary.csv"))
    summary = {"study": plan["study"], "points": rows, "groups": group_stats, "against_n": scaling}
    with open(os.path.join(out, "summary.json.tmp"), "w") as f:
        json.dump(summary, f, indent=1)
    os.replace(os.path.join(out, "summary.json.tmp"), os.path.join(out, "summary.json"))
    plots(out, curves_of, scaling)
    return summary


def plots(out, curves_of, scaling):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("study_report: no matplotlib, no plots", file=sys.stderr)
        return
    os.makedirs(os.path.join(out, "plots"), exist_ok=True)
    for step, groups in curves_of.items():
        fig, (aq, av) = plt.subplots(1, 2, figsize=(11, 4.2))
        for values, c in groups:
            name = ", ".join(f"{k} = {v}" for k, v in values.items()) + f" ({c['samples']})"
            line, = aq.plot(c["epsilon_2"], c["q_mean"], label=name)
            aq.fill_between(c["epsilon_2"], c["q_mean"] - c["q_rms"], c["q_mean"] + c["q_rms"],
                            color=line.get_color(), alpha=0.25)
            av.plot(c["epsilon_2"], c["epsilon_v_mean"], color=line.get_color())
            av.fill_between(c["epsilon_2"], c["epsilon_v_mean"] - c["epsilon_v_rms"],
                            c["epsilon_v_mean"] + c["epsilon_v_rms"], color=line.get_color(), alpha=0.25)
        aq.set_xlabel("epsilon_2"); aq.set_ylabel("q (mean +- rms)"); aq.legend(fontsize=7)
        av.set_xlabel("epsilon_2"); av.set_ylabel("epsilon_v (mean +- rms)")
        fig.suptitle(f"step {step}")
        fig.tight_layout()
        fig.savefig(os.path.join(out, "plots", f"curves_{step}.png"), dpi=110)
        plt.close(fig)
    q1_keys = sorted({k for e in scaling for k in e if k.endswith(".q1")})
    for key in q1_keys:
        fig, (am, aw) = plt.subplots(1, 2, figsize=(11, 4.2))
        for e in scaling:
            if key not in e:
                continue
            n = np.array(e["n"])
            name = ", ".join(f"{k} = {v}" for k, v in e["values"].items()) or key
            am.errorbar(n, e[key]["mean"], yerr=e[key]["rms"], marker="o", capsize=3, label=name)
            x = 1 / np.sqrt(n)
            pts = aw.plot(x, e[key]["rms"], "o", label=name)[0]
            if e[key]["width_slope"] is not None:
                xs = np.linspace(0, x.max() * 1.05, 20)
                aw.plot(xs, e[key]["width_intercept"] + e[key]["width_slope"] * xs, "--",
                        color=pts.get_color())
        am.set_xscale("log"); am.set_xlabel("N"); am.set_ylabel(f"{key} (mean +- rms)")
        am.legend(fontsize=7)
        aw.set_xlabel("1 / sqrt(N)"); aw.set_ylabel(f"rms of {key}"); aw.set_xlim(left=0)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "plots", f"{key.replace('.', '_')}_against_n.png"), dpi=110)
        plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    s = report(sys.argv[1])
    print(f"study report: {len(s['points'])} points, {len(s['groups'])} groups -> "
          f"{os.path.join(sys.argv[1], 'summary.json')}")
