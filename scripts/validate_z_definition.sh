#!/usr/bin/env bash
# Independent check of SPEC §2's z and x0 on a configuration file (docs/validation.md): finds every
# overlapping pair by brute force (minimum image, no contact list, no neighbour list), removes
# rattlers iteratively (fewer than 2 force-carrying contacts), and prints z = 2 N_c / N' and x0
# beside `granstab info`. Also z when only contacts with F_N above a threshold count, to show how
# much weak contacts matter. Periodic cells only. Not part of ctest.
#   scripts/validate_z_definition.sh SAMPLE.granstab...      (BUILD_DIR: build)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
granstab="${BUILD_DIR:-$root/build}/drivers/granstab"
for sample in "$@"; do
  echo "== $sample"
  /usr/bin/python3 - "$sample" <<'PY'
import sys
import numpy as np
lines = [l.split('#')[0].split() for l in open(sys.argv[1])]
lines = [l for l in lines if l]
header, i = {}, 1
while lines[i][0] != 'disks':
    header[lines[i][0]] = lines[i][1:]
    i += 1
if header['boundary'][0] != 'periodic':
    sys.exit('periodic cells only')
n = int(lines[i][1])
disks = np.array([[float(v) for v in l[:3]] for l in lines[i + 1:i + 1 + n]])
i += 1 + n
listed = {tuple(sorted((int(l[0]), int(l[1])))) for l in lines[i + 1:i + 1 + int(lines[i][1])]}
L = np.array([float(v) for v in header['cell.length']])
k_n = float(header['material.k_n'][0])
x, y, r = disks.T
dx = x[None, :] - x[:, None]
dy = y[None, :] - y[:, None]
dx -= L[0] * np.round(dx / L[0])
dy -= L[1] * np.round(dy / L[1])
h = (r[:, None] + r[None, :] - np.hypot(dx, dy))[np.triu_indices(n, 1)]
ij = np.array(np.triu_indices(n, 1)).T
touching = h > 0
pairs, f_n = ij[touching], k_n * h[touching]
found = {tuple(p) for p in pairs}
print(f"overlapping pairs {len(pairs)}; listed contacts {len(listed)}; "
      f"overlapping but not listed {len(found - listed)}; listed but not overlapping {len(listed - found)}")
for threshold in (0.0, 1e-3, 1e-2, 1e-1):
    kept = pairs[f_n > threshold]
    active = np.ones(n, bool)
    while True:
        both = kept[active[kept[:, 0]] & active[kept[:, 1]]]
        count = np.bincount(both.ravel(), minlength=n)
        drop = active & (count < 2)
        if not drop.any():
            break
        active &= ~drop
    print(f"F_N > {threshold:g}: z = {2 * len(both) / active.sum():.4f}, x0 = {1 - active.mean():.4f} "
          f"(N_c = {len(both)}, N' = {active.sum()})")
PY
  [ -x "$granstab" ] && "$granstab" info --json "$sample" | grep -E '"(z|x0)"' | tr -d ' ,\n' && echo " (granstab info)"
done
