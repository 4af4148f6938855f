#!/usr/bin/env python3
"""Pictures of a `granstab sic` output directory (issue #24), PNG and SVG in that directory:

  sic_curve       q and epsilon_v against epsilon_2, each state coloured by the method that
                  produced it (static stepping or MD); with a second directory (a pure dynamic
                  run of the same sample), its curve in grey beneath
  sic_jumps       the strain jump of every rearrangement against the q it ended at
  rearrangement_K the force network before and after each pictured rearrangement

Usage: plot_sic.py DIR [REFERENCE_DIR]     (run by `granstab plot DIR`)
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

COLOURS = {"static": "#1f78b4", "dynamic": "#e31a1c"}


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(row for row in f if not row.startswith("#")))


def save(fig, directory, name):
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(directory, f"{name}.{ext}"), dpi=150)
    plt.close(fig)


def equilibria(rows):
    return [r for r in rows if r["reached"] == "1"]


def plot_curve(d, info, rows, reference):
    fig, axes = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
    for ax, key, label in ((axes[0], "q", "$q$"), (axes[1], "epsilon_v", r"$\epsilon_v$")):
        if reference:
            ax.plot([float(r["epsilon_2"]) for r in reference], [float(r[key]) for r in reference],
                    "-", color="0.6", lw=1.0, label="pure dynamic SIC")
        ax.plot([float(r["epsilon_2"]) for r in rows], [float(r[key]) for r in rows], "-",
                color="0.2", lw=0.6)
        for method, colour in COLOURS.items():
            pts = [r for r in rows if r["method"] == method]
            ax.plot([float(r["epsilon_2"]) for r in pts], [float(r[key]) for r in pts], ".",
                    color=colour, ms=3 if method == "static" else 6,
                    label=("static stepping" if method == "static" else "MD (rearrangement)"))
        ax.set_ylabel(label)
    axes[1].set_xlabel(r"$\epsilon_2$")
    axes[0].legend(fontsize=8)
    axes[0].set_title(f"{info['method']} SIC, N = {info['n_disks']}, dq = {info['dq']}: "
                      f"{info['stability_intervals']} stability intervals, "
                      f"{info['rearrangements']} rearrangements ({info['stop_reason']})",
                      fontsize=9)
    fig.tight_layout()
    save(fig, d, "sic_curve")


def plot_jumps(d, info):
    jumps = info.get("rearrangement_jump_epsilon_2", [])
    if not jumps:
        return
    q = info["rearrangement_q_to"]
    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.semilogy(q, [max(abs(j), 1e-12) for j in jumps], "o", color=COLOURS["dynamic"])
    ax.set_xlabel("$q$ at the end of the rearrangement")
    ax.set_ylabel(r"strain jump $\Delta\epsilon_2$")
    ax.set_title("rearrangements (MD from the last stable state to the next increment)",
                 fontsize=9)
    fig.tight_layout()
    save(fig, d, "sic_jumps")


def network_panel(ax, d, stem, title):
    with open(os.path.join(d, stem + "_disks.csv")) as f:
        head = f.readline().split()
    L1, L2 = float(head[2]), float(head[4])
    periodic = head[6] == "periodic"
    contacts = read_csv(os.path.join(d, stem + "_network.csv"))
    fn_max = max([float(c["f_n"]) for c in contacts] + [1e-300])
    segs, widths, colours = [], [], []
    for c in contacts:
        xi, yi = float(c["x_i"]), float(c["y_i"])
        if periodic:
            xi, yi = xi % L1, yi % L2
        segs.append([(xi, yi), (xi + float(c["lx"]), yi + float(c["ly"]))])
        widths.append(4.0 * float(c["f_n"]) / fn_max)
        colours.append("#e31a1c" if c["sliding"] == "1" else "black")
    ax.add_collection(LineCollection(segs, linewidths=widths, colors=colours, capstyle="round"))
    ax.plot([0, L1, L1, 0, 0], [0, 0, L2, L2, 0], "--", color="0.4", lw=0.6)
    ax.set_xlim(-1, L1 + 1)
    ax.set_ylim(-1, L2 + 1)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(title, fontsize=9)


def plot_rearrangements(d, info):
    for k in info.get("pictured_rearrangements", []):
        fig, axes = plt.subplots(1, 2, figsize=(11, 5.8))
        jump = info["rearrangement_jump_epsilon_2"][k]
        for ax, side, q in ((axes[0], "before", info["rearrangement_q_from"][k]),
                            (axes[1], "after", info["rearrangement_q_to"][k])):
            network_panel(ax, d, f"rearrangement_{k:03d}_{side}", f"{side}: q = {q:.5g}")
        fig.suptitle(f"rearrangement {k}: " + r"$\Delta\epsilon_2$" + f" = {jump:.3g}; "
                     "width of a contact line proportional to its F_N, red: sliding",
                     fontsize=9)
        fig.tight_layout()
        save(fig, d, f"rearrangement_{k:03d}")


def main(argv):
    if len(argv) not in (2, 3):
        sys.exit(__doc__)
    d = argv[1]
    with open(os.path.join(d, "sic.json")) as f:
        info = json.load(f)
    rows = equilibria(read_csv(os.path.join(d, "sic_curve.csv")))
    reference = None
    if len(argv) == 3:
        ref = argv[2]
        path = os.path.join(ref, "sic_curve.csv")
        reference = equilibria(read_csv(path if os.path.exists(path) else
                                        os.path.join(ref, "curve.csv")))
    plot_curve(d, info, rows, reference)
    plot_jumps(d, info)
    plot_rearrangements(d, info)


if __name__ == "__main__":
    main(sys.argv)
