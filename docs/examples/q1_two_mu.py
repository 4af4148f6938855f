"""q1 of the shipped sample at two biaxial frictions, from Python (docs/python.md).

    PYTHONPATH=build/python /usr/bin/python3 docs/examples/q1_two_mu.py [OUT_DIR]

Loads data/samples/periodic-n100-k1e4.granstab, runs the static stepping to the loss of
stability at mu = 0.25 and 0.5 (K_T/K_N as in the file), and writes OUT_DIR/q1_two_mu.png: the
q - epsilon_2 curves up to q1 and the normal-force network of the start state.
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt
import numpy as np

import granstab

root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
sample = os.path.join(root, "data", "samples", "periodic-n100-k1e4.granstab")
out = sys.argv[1] if len(sys.argv) > 1 else "q1-two-mu"
os.makedirs(out, exist_ok=True)

c = granstab.Configuration.load(sample)
print(f"N = {c.n_disks}, Phi = {c.phi:.4f}, z = {c.z:.3f}, file mu = {c.mu}")

fig, (curves, network) = plt.subplots(1, 2, figsize=(11, 4.5))
for mu in (0.25, 0.5):
    # hill=False: the Hill indicator column is not needed for the curve (and costs most of the run)
    r = granstab.q1(sample, mu=mu, dq=1e-3, hill=False, out=os.path.join(out, f"mu{mu}"))
    print(f"mu = {mu}: q1 = {r.q1:.6f} ({r.criterion}), {r.n_sliding_at_q1} sliding contacts")
    curves.plot(r.curve["epsilon_2"], r.curve["q"], label=f"mu = {mu}: q1 = {r.q1:.3f}")
curves.set_xlabel("epsilon_2")
curves.set_ylabel("q")
curves.legend()
curves.set_title("static stepping to q1")

# The normal-force network of the start state: one segment per disk-disk contact, its width
# proportional to F_N = K_N h (the linear law, common/contact_law.hpp).
i, j = c.contact_i, c.contact_j
disk_disk = j >= 0
i, j = i[disk_disk], j[disk_disk]
L1, L2 = c.length
xi, yi = c.x[i], c.y[i]
xj = c.x[j] + c.contact_k1[disk_disk] * L1
yj = c.y[j] + c.contact_k2[disk_disk] * L2
overlap = c.radius[i] + c.radius[j] - np.hypot(xj - xi, yj - yi)
f_n = c.k_n * np.maximum(overlap, 0.0)
for a in range(len(i)):
    network.plot([xi[a], xj[a]], [yi[a], yj[a]], color="k", lw=4 * f_n[a] / f_n.max())
network.add_patch(plt.Rectangle((0, 0), L1, L2, fill=False, ls="--", color="grey"))
network.set_aspect("equal")
network.set_title("normal forces at the start (width ~ F_N)")
fig.tight_layout()
fig.savefig(os.path.join(out, "q1_two_mu.png"), dpi=120)
print("wrote", os.path.join(out, "q1_two_mu.png"))
