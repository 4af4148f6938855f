"""Tables of scripts/validate_crosscheck_convergence.sh: every curve minus the finest static one.

usage: crosscheck_convergence_table.py OUTDIR DQ FINEST_STATIC_STEP
"""
import csv
import math
import os
import sys


def curve(path, load_column):
    with open(path) as f:
        return {round(float(r[load_column]), 9): float(r["epsilon_2"]) for r in csv.DictReader(f)}


def largest_difference(a, b, lo, hi, dq):
    """max |a - b| over the states q = k dq in [lo, hi] that both curves hold."""
    worst = float("nan")
    for q, e in a.items():
        on_grid = abs(q / dq - round(q / dq)) < 1e-6
        if on_grid and lo <= q <= hi and q in b:
            d = abs(e - b[q])
            worst = d if math.isnan(worst) else max(worst, d)
    return worst


def main():
    out, dq, finest = sys.argv[1], float(sys.argv[2]), sys.argv[3]
    reference = curve(os.path.join(out, f"static-{finest}", "static_curve.csv"), "load")
    q_end = max(reference)
    bands = [0.0, 0.45, 0.735, 0.76, 0.80, q_end]
    bands = sorted({b for b in bands if b <= q_end} | {q_end})
    curves = []
    for name in sorted(os.listdir(out)):
        path = os.path.join(out, name)
        if name.startswith("static-") and name != f"static-{finest}":
            curves.append((name, curve(os.path.join(path, "static_curve.csv"), "load")))
        elif name.startswith("compare-"):
            curves.append((name, curve(os.path.join(path, "dynamic_curve.csv"), "q_target")))
    print(f"\nlargest |epsilon_2 - epsilon_2 of static step {finest}| at q = k {dq}, by band of q")
    header = ["curve"] + [f"{lo:.3g}-{hi:.3g}" for lo, hi in zip(bands, bands[1:])]
    print(" | ".join(header))
    for name, c in curves:
        cells = [f"{largest_difference(c, reference, lo, hi, dq):.2g}"
                 for lo, hi in zip(bands, bands[1:])]
        print(" | ".join([name] + cells))
    print("\nq1 by static step:")
    for name in sorted(os.listdir(out)):
        if name.startswith("static-"):
            with open(os.path.join(out, name, "q1.json")) as f:
                line = next((l for l in f if '"q1"' in l), "").strip().rstrip(",")
            print(f"  {name}: {line}")


if __name__ == "__main__":
    main()
