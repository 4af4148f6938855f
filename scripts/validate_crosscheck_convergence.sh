#!/usr/bin/env bash
# Where the static/dynamic differences of the cross-check come from (issue #6,
# docs/crosscheck.md, item 7). Not part of ctest.
# The script varies each of the three sources of difference alone, on the shipped N = 100 sample:
#   - the static step: granstab q1 with steps 1e-3, 1e-4 and 1e-5;
#   - the dynamic tolerances and the dynamic stress step: granstab compare with all three
#     tolerances at T and with --dynamic-substeps.
# It then prints each dynamic curve minus the finest static curve.
#   scripts/validate_crosscheck_convergence.sh [OUTDIR]     (defaults: /tmp/crosscheck-convergence)
# Knobs:
#   MU (0.5), DQ (0.001), Q_MAX (empty: up to q1), BUILD_DIR (build),
#   FINEST_STATIC_STEP (1e-5; about 9 min wall on one idle core for mu 0.5).
# All runs use OMP_NUM_THREADS=1. The whole set takes about 15 min of CPU at mu = 0.5.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
granstab="${BUILD_DIR:-$root/build}/drivers/granstab"
sample="$root/data/samples/periodic-n100-k1e4.granstab"
out=${1:-/tmp/crosscheck-convergence}
mu=${MU:-0.5}
dq=${DQ:-0.001}
finest=${FINEST_STATIC_STEP:-1e-5}
export OMP_NUM_THREADS=1
mkdir -p "$out"
stop=()
[ -n "${Q_MAX:-}" ] && stop=(--stop "$Q_MAX")
qmax=()
[ -n "${Q_MAX:-}" ] && qmax=(--q-max "$Q_MAX")

# granstab q1 takes the friction from the sample: a copy with material.mu set to MU. Its static
# path is compare's static half, to the bit.
grep -q '^material.mu ' "$sample" || { echo "no material.mu line in $sample" >&2; exit 1; }
sed "s/^material.mu .*/material.mu $mu/" "$sample" > "$out/sample-mu$mu.granstab"
for step in "$dq" "$(/usr/bin/python3 -c "print($dq / 10)")" "$finest"; do
  echo "== static step $step"
  /usr/bin/time -f "   %U s user, %e s wall" "$granstab" q1 "$out/sample-mu$mu.granstab" \
    --dq "$step" --no-hill "${stop[@]}" --out "$out/static-$step" | tail -n 1
done

# name, tolerance, dynamic substeps
runs=("tol1e-4-steps1 1e-4 1" "tol1e-5-steps1 1e-5 1" "tol1e-6-steps1 1e-6 1"
  "tol1e-4-steps10 1e-4 10" "tol1e-6-steps10 1e-6 10")
for run in "${runs[@]}"; do
  read -r name tol sub <<< "$run"
  echo "== compare $name"
  /usr/bin/time -f "   %U s user, %e s wall" "$granstab" compare "$sample" --mu "$mu" --dq "$dq" \
    --no-hill --force-tolerance "$tol" --torque-tolerance "$tol" --stress-tolerance "$tol" \
    --dynamic-substeps "$sub" "${qmax[@]}" --out "$out/compare-$name" | grep -E "^q1|max \|d eps2\|"
done

/usr/bin/python3 "$root/scripts/crosscheck_convergence_table.py" "$out" "$dq" "$finest"
