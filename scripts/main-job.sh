#!/usr/bin/env bash
# The README's main-job command: install, build, then run granstab on a shipped sample.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
granstab="${BUILD_DIR:-$root/build}/drivers/granstab"
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2}
"$granstab" version
"$granstab" info "$root/data/samples/tiny-triangular-periodic.granstab"
# The cross-check of SPEC §5 (docs/user-guide.md): static stepping and dynamic SIC from the shipped
# N = 100 equilibrium sample with the same delta q, at the SPEC §3.2 series B biaxial friction
# mu = 0.5 and at the sample's preparation friction mu_prep = 0.15; pictures drawn with matplotlib.
sample="$root/data/samples/periodic-n100-k1e4.granstab"
results="${RESULTS_DIR:-$root/results}/periodic-n100-k1e4"
for mu in 0.5 0.15; do
  out="$results/mu$mu"
  "$granstab" compare "$sample" --dq 0.01 --mu "$mu" --out "$out"
  "$granstab" plot "$out"
done
echo "main job done: results and pictures (curves, difference, sample_at_q1 .png/.svg) in $results/mu0.5 and $results/mu0.15"
