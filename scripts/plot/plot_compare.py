#!/usr/bin/python3
"""Pictures of a `granstab compare` output directory (SPEC §5), PNG and SVG.

Usage: MPLBACKEND=Agg /usr/bin/python3 scripts/plot/plot_compare.py DIR
(or `granstab plot DIR`). Reads DIR/compare.json, static_curve.csv, dynamic_curve.csv,
matched.csv, disks_at_q1.csv, network_at_q1.csv, mode.csv and writes
  DIR/curves.{png,svg}      q and epsilon_v against epsilon_2, both methods, q1 marked, insets
                            blown up on the strictly quasistatic range q <= q1;
  DIR/difference.{png,svg}  |dynamic - static| in epsilon_2 and epsilon_v at the same q, with the
                            bound the SPEC §3.1 tolerances allow;
  DIR/sample_at_q1.{png,svg} the static network at q1: disks, contact forces as segments of
                            width proportional to F_N (force chains), sliding contacts, and the
                            unstable mode as arrows.
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection, PatchCollection  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

STATIC_COLOUR = "#1f4e9c"
DYNAMIC_COLOUR = "#d9531e"
Q1_COLOUR = "#2a7f3f"
# Set in main(): "loss of stability" only when the static run found one.
Q1_LABEL = [r"loss of stability $q_1$ (static)"]


def read_csv(path):
    """Rows of a CSV file as dicts of strings, skipping '#' comment lines."""
    with open(path, newline="") as f:
        lines = [line for line in f if not line.startswith("#")]
    return list(csv.DictReader(lines))


def column(rows, name, cast=float):
    return [cast(r[name]) for r in rows]


def save(fig, directory, name):
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(directory, f"{name}.{ext}"), dpi=150, bbox_inches="tight")
    plt.close(fig)


def curve_panel(ax, xs, ys, xd, yd, n_below, ylabel, q1_x, q1_y, inset_box):
    """One panel: static line, dynamic markers (the first n_below at q <= q1), q1 marked; an
    inset on the quasistatic range."""
    # Dense runs (small delta q): every k-th dynamic marker below q1, the static line on top;
    # every dynamic state beyond q1 is drawn (filled), since that is where the curves part.
    every = max(1, n_below // 45)
    ax.plot(xs, ys, "-", color=STATIC_COLOUR, lw=1.6, zorder=3,
            label="static (contact network, §4)")
    ax.plot(xd[:n_below], yd[:n_below], "o", color=DYNAMIC_COLOUR, ms=3.5, mfc="none", mew=1.0,
            markevery=every,
            label="dynamic SIC (MD, §3.3)" + (f", every {every}th state" if every > 1 else ""))
    if n_below < len(xd):
        ax.plot(xd[n_below:], yd[n_below:], "o", color=DYNAMIC_COLOUR, ms=4, zorder=4,
                label=r"dynamic SIC beyond $q_1$")
    ax.plot([q1_x], [q1_y], "*", color=Q1_COLOUR, ms=13, mec="black", mew=0.5, zorder=5,
            label=Q1_LABEL[0])
    ax.set_xlabel(r"axial strain $\varepsilon_2$")
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.ticklabel_format(axis="x", style="sci", scilimits=(-3, 3))
    if inset_box is None:
        return
    xmax, ylo, yhi, title = inset_box
    ins = ax.inset_axes([0.57, 0.1, 0.38, 0.38])
    inside = [i for i, x in enumerate(xd) if x <= xmax]
    ins.plot(xs, ys, "-", color=STATIC_COLOUR, lw=1.4, zorder=3)
    ins.plot([xd[i] for i in inside], [yd[i] for i in inside], "o", color=DYNAMIC_COLOUR, ms=3,
             mfc="none", mew=0.9, markevery=max(1, len(inside) // 30))
    ins.plot([q1_x], [q1_y], "*", color=Q1_COLOUR, ms=10, mec="black", mew=0.5, zorder=5)
    ins.set_xlim(0.0, xmax)
    ins.set_ylim(ylo, yhi)
    ins.set_title(title, fontsize=7)
    ins.tick_params(labelsize=6)
    ins.ticklabel_format(axis="both", style="sci", scilimits=(-3, 3))
    ins.xaxis.get_offset_text().set_fontsize(6)
    ins.yaxis.get_offset_text().set_fontsize(6)
    ins.grid(alpha=0.3)
    ax.indicate_inset_zoom(ins, edgecolor="0.4")


def plot_curves(d, info, static, dynamic):
    q1 = info["q1"]
    xs, qs, vs = column(static, "epsilon_2"), column(static, "load"), column(static, "epsilon_v")
    ok = [r for r in dynamic if r["reached"] == "1"]
    xd, qd, vd = column(ok, "epsilon_2"), column(ok, "q_target"), column(ok, "epsilon_v")
    # State at q1: the last static state.
    x1, v1 = xs[-1], vs[-1]
    below = [i for i, q in enumerate(qd) if q <= q1 * (1 + 1e-12)]
    x_in = max([x1] + [xd[i] for i in below]) * 1.08
    q_lo, q_hi = min(qs + [qd[i] for i in below]), max(qs + [qd[i] for i in below])
    v_vals = vs + [vd[i] for i in below]
    v_pad = 0.08 * (max(v_vals) - min(v_vals) or 1e-12)
    q_pad = 0.08 * (q_hi - q_lo or 1e-12)
    # Inset on the strictly quasistatic range q <= q1 when the dynamic run went far beyond it;
    # otherwise the whole plot is that range and the inset blows up its first fifth.
    zoom = max(xd + xs) > 2.0 * x_in
    title = r"strictly quasistatic range $q \leq q_1$"
    q_cap = q1 if zoom else q1 / 5.0
    if not zoom:
        title = rf"start of the quasistatic range, $q \leq {q_cap:.3g}$"
        first = [i for i, q in enumerate(qs) if q <= q_cap * (1 + 1e-9)]
        firstd = [i for i, q in enumerate(qd) if q <= q_cap * (1 + 1e-9)]
        x_in = max([xs[i] for i in first] + [xd[i] for i in firstd]) * 1.08
        v_first = [vs[i] for i in first] + [vd[i] for i in firstd]
        v_pad = 0.08 * (max(v_first) - min(v_first) or 1e-12)
        v_vals = v_first
        q_lo, q_hi = 0.0, q_cap
        q_pad = 0.08 * q_cap
    fig, axes = plt.subplots(1, 2, figsize=(11.5, 4.6))
    n_below = len(below)
    curve_panel(axes[0], xs, qs, xd, qd, n_below,
                r"deviator ratio $q = (\sigma_2 - \sigma_1)/\sigma_1$", x1, q1,
                (x_in, q_lo - q_pad, q_hi + q_pad, title))
    axes[0].axhline(q1, color=Q1_COLOUR, ls="--", lw=0.9)
    q1_text = rf"$q_1 = {q1:.4g}$" if info["criterion"] != "none" else f"stable up to q = {q1:.4g}"
    axes[0].annotate(q1_text, xy=(1.0, q1), xycoords=("axes fraction", "data"),
                     xytext=(-4, 4), textcoords="offset points", ha="right", va="bottom",
                     color=Q1_COLOUR, fontsize=9)
    qr = info.get("q_max_rigid")
    if qr is not None and qr < 1.5 * max(qd + qs):
        axes[0].axhline(qr, color="0.35", ls=":", lw=0.9)
        axes[0].annotate(rf"rigid limit $q_{{max}} = {qr:.4g}$ (§4.5)", xy=(1.0, qr),
                         xycoords=("axes fraction", "data"), xytext=(-4, 4),
                         textcoords="offset points", ha="right", va="bottom", color="0.35",
                         fontsize=8)
    curve_panel(axes[1], xs, vs, xd, vd, n_below,
                r"volumetric strain $\varepsilon_v$ (contraction > 0)", x1, v1,
                (x_in, min(v_vals) - v_pad, max(v_vals) + v_pad, title))
    fig.suptitle(
        f"{os.path.basename(info['sample'])}: N = {info['n_disks']}, "
        rf"$\kappa$ = {info['kappa']:.3g}, $\mu$ = {info['mu']:g}, $\Delta q$ = {info['dq']:g}"
        + (f"  ({info['criterion']} at $q_1$)" if info["criterion"] != "none"
           else "  (static run stopped while stable)"), fontsize=11)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), fontsize=8.5)
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    save(fig, d, "curves")


def plot_difference(d, info, matched):
    if not matched:
        return
    q = column(matched, "q")
    d2 = [abs(a - b) for a, b in zip(column(matched, "epsilon_2_dynamic"),
                                     column(matched, "epsilon_2_static"))]
    dv = [abs(a - b) for a, b in zip(column(matched, "epsilon_v_dynamic"),
                                     column(matched, "epsilon_v_static"))]
    e2 = [abs(x) for x in column(matched, "epsilon_2_static")]
    bound = column(matched, "bound_epsilon_2")
    dense = len(q) > 60  # small delta q: lines only
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.semilogy(q, e2, "-", color="0.6", lw=1.2, label=r"$|\varepsilon_2|$ (static), for scale")
    ax.semilogy(q, d2, "-" if dense else "o-", color=DYNAMIC_COLOUR, ms=3.5,
                label=r"$|\varepsilon_2^{dyn} - \varepsilon_2^{stat}|$")
    ax.semilogy(q, dv, "-" if dense else "s-", color=STATIC_COLOUR, ms=3, mfc="none",
                label=r"$|\varepsilon_v^{dyn} - \varepsilon_v^{stat}|$")
    ax.semilogy(q, bound, "--", color="black", lw=1.0,
                label=r"bound on $\varepsilon_2$ from the §3.1 tolerances")
    ax.axvline(info["q1"], color=Q1_COLOUR, ls="--", lw=0.9)
    ax.set_xlabel(r"deviator ratio $q$")
    ax.set_ylabel("strain difference at the same q")
    tol = info["equilibrium_tolerances"]
    ax.set_title(f"static vs dynamic below $q_1$ (dynamic tolerances: force {tol['force']:g}, "
                 f"stress {tol['stress']:g})", fontsize=9)
    ax.grid(alpha=0.3, which="both")
    qs = info.get("q_first_static_sliding")
    if qs is not None:
        ax.axvline(qs, color="0.5", ls=":", lw=0.9)
        ax.annotate("first sliding contact (static)", xy=(qs, 0.02),
                    xycoords=("data", "axes fraction"),
                    xytext=(3, 0), textcoords="offset points", fontsize=7, color="0.35",
                    rotation=90, va="bottom")
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=2)
    fig.tight_layout()
    save(fig, d, "difference")


def plot_sample(d, info):
    with open(os.path.join(d, "disks_at_q1.csv")) as f:
        head = f.readline().split()
    lengths = (float(head[2]), float(head[4]))
    periodic = head[6] == "periodic"
    disks = read_csv(os.path.join(d, "disks_at_q1.csv"))
    contacts = read_csv(os.path.join(d, "network_at_q1.csv"))
    mode = [r for r in read_csv(os.path.join(d, "mode.csv")) if r["disk"] not in ("e1", "e2")]
    L1, L2 = lengths

    def wrap(x, L):
        return x % L if periodic else x

    fig, ax = plt.subplots(figsize=(7.5, 7.5 * L2 / L1 + 0.6))
    circles, colours = [], []
    for r in disks:
        x, y, rad = wrap(float(r["x"]), L1), wrap(float(r["y"]), L2), float(r["radius"])
        # Periodic images of disks that cross the cell edges, so the picture tiles.
        shifts = [(0, 0)]
        if periodic:
            sx = [0] + ([-L1] if x + rad > L1 else []) + ([L1] if x - rad < 0 else [])
            sy = [0] + ([-L2] if y + rad > L2 else []) + ([L2] if y - rad < 0 else [])
            shifts = [(a, b) for a in sx for b in sy]
        for a, b in shifts:
            circles.append(Circle((x + a, y + b), rad))
            colours.append("#d9d9d9" if r["rattler"] == "1" else "#f4f1e8")
    ax.add_collection(PatchCollection(circles, facecolors=colours, edgecolors="0.45",
                                      linewidths=0.5))
    fn_max = max([float(c["f_n"]) for c in contacts] + [1e-300])
    segs, widths, slide_segs = [], [], []
    n_sliding = sum(c["sliding"] == "1" for c in contacts)
    for c in contacts:
        xi, yi = wrap(float(c["x_i"]), L1), wrap(float(c["y_i"]), L2)
        xj, yj = xi + float(c["lx"]), yi + float(c["ly"])
        seg = [(xi, yi), (xj, yj)]
        w = 6.0 * float(c["f_n"]) / fn_max
        segs.append(seg)
        widths.append(w)
        if c["sliding"] == "1":
            slide_segs.append(seg)
        # A chain that leaves the cell re-enters on the other side.
        if periodic and not (0 <= xj <= L1 and 0 <= yj <= L2):
            a = -L1 if xj > L1 else (L1 if xj < 0 else 0)
            b = -L2 if yj > L2 else (L2 if yj < 0 else 0)
            segs.append([(xi + a, yi + b), (xj + a, yj + b)])
            widths.append(w)
            if c["sliding"] == "1":
                slide_segs.append(segs[-1])
    ax.add_collection(LineCollection(segs, linewidths=widths, colors="black",
                                     capstyle="round", label=r"contact force, width $\propto F_N$"))
    if slide_segs:
        ax.add_collection(LineCollection(slide_segs, linewidths=2.2, colors="#e31a1c", alpha=0.8,
                                         label=f"sliding contact ({n_sliding})"))
    if mode:
        rattler = {r["disk"]: r["rattler"] == "1" for r in disks}
        ux, uy = column(mode, "ux"), column(mode, "uy")
        # A uniform translation is a zero mode of a periodic cell (the solver pins it on one
        # disk): draw the mode relative to the mean displacement of the disks that carry its
        # degrees of freedom (the 'active' column; older files: the non-rattlers). Rattlers, also
        # those made by the statuses at q1, have none: no arrow.
        if "active" in mode[0]:
            moving = [i for i, r in enumerate(mode) if r["active"] == "1"]
        else:
            moving = [i for i, r in enumerate(mode) if not rattler.get(r["disk"], False)]
        if periodic and moving:
            mx = sum(ux[i] for i in moving) / len(moving)
            my = sum(uy[i] for i in moving) / len(moving)
            ux = [u - mx for u in ux]
            uy = [u - my for u in uy]
        still = set(range(len(mode))) - set(moving)
        ux = [0.0 if i in still else u for i, u in enumerate(ux)]
        uy = [0.0 if i in still else u for i, u in enumerate(uy)]
        umax = max(max(abs(u) for u in ux), max(abs(u) for u in uy), 1e-300)
        scale = 0.9 / umax  # the largest arrow is 0.9 a long
        xs = [wrap(float(r["x"]), L1) for r in mode]
        ys = [wrap(float(r["y"]), L2) for r in mode]
        keep = [i for i in range(len(mode)) if abs(ux[i]) + abs(uy[i]) > 1e-3 * umax]
        ax.quiver([xs[i] for i in keep], [ys[i] for i in keep],
                  [scale * ux[i] for i in keep], [scale * uy[i] for i in keep],
                  angles="xy", scale_units="xy", scale=1.0, color="#1f78b4", width=0.004,
                  zorder=4, label="unstable mode at $q_1$ (displacements, mean removed)")
    if periodic:
        ax.plot([0, L1, L1, 0, 0], [0, 0, L2, L2, 0], "--", color="0.3", lw=0.8)
    ax.set_xlim(-0.6, L1 + 0.6)
    ax.set_ylim(-0.6, L2 + 0.6)
    ax.set_aspect("equal")
    ax.set_xlabel(r"$x_1$ ($a$)")
    ax.set_ylabel(r"$x_2$ ($a$, axial direction)")
    if info["criterion"] == "none":
        where = f"static network at q = {info['q1']:.4g} (still stable: no unstable mode)"
    else:
        where = f"static network at $q_1$ = {info['q1']:.4g} ({info['criterion']})"
    ax.set_title(where + "; grey disks: rattlers", fontsize=10)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.08), ncol=2, fontsize=8)
    fig.tight_layout()
    save(fig, d, "sample_at_q1")


def main(argv):
    if len(argv) != 2:
        sys.exit("usage: plot_compare.py DIR")
    d = argv[1]
    with open(os.path.join(d, "compare.json")) as f:
        info = json.load(f)
    static = read_csv(os.path.join(d, "static_curve.csv"))
    dynamic = read_csv(os.path.join(d, "dynamic_curve.csv"))
    matched = read_csv(os.path.join(d, "matched.csv"))
    if info["criterion"] == "none":
        Q1_LABEL[0] = "last static state (still stable)"
    plot_curves(d, info, static, dynamic)
    plot_difference(d, info, matched)
    plot_sample(d, info)
    for name in ("curves", "difference", "sample_at_q1"):
        print(os.path.join(d, name + ".png"))


if __name__ == "__main__":
    main(sys.argv)
