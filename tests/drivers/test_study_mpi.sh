#!/usr/bin/env bash
# granstab study under `mpirun --oversubscribe -np 3` (issue #20 item 5): the ranks share a 2 x 2
# study out (4 trees over 3 ranks: 2, 1, 1) and end with the results of a run on one process.
# Usage: test_study_mpi.sh GRANSTAB MPIEXEC
set -euo pipefail
granstab=$1
mpiexec=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for d in local mpi; do
  mkdir -p "$work/$d"
  cat > "$work/$d/prepare.toml" <<'TOML'
[sample]
n = 40
boundary = "periodic"
seed = 7
[material]
kappa = 1e4
mu = 0.15
TOML
  cat > "$work/$d/study.toml" <<'TOML'
[study]
out = "out"
[grid]
n = [40, 60]
seed = [1, 2]
[[step]]
command = "prepare"
settings = "prepare.toml"
set = { "sample.n" = "{n}", "sample.seed" = "{seed}" }
[[step]]
command = "q1"
arguments = ["{prepare}/sample.granstab", "--mu", "0.5", "--no-hill", "--quiet"]
TOML
done
(cd "$work/local" && OMP_NUM_THREADS=1 "$granstab" study study.toml --jobs 1 --quiet)
# mpirun refuses root unless told (a CI container runs as root).
(cd "$work/mpi" && OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
  "$mpiexec" --oversubscribe -np 3 "$granstab" study study.toml 2> "$work/mpi.err") || {
  cat "$work/mpi.err"; exit 1; }
cat "$work/mpi.err"
for r in 0 1 2; do
  grep -q "study rank $r: " "$work/mpi.err" || { echo "rank $r ran no task"; exit 1; }
done
grep -q "study rank 0: 4 tasks" "$work/mpi.err" || { echo "rank 0 should hold two trees"; exit 1; }
n_done=$(find "$work/mpi/out" -name .done | wc -l)
[ "$n_done" = 8 ] || { echo "expected 8 done tasks, found $n_done"; exit 1; }
for f in $(cd "$work/local/out" && find . -name static_curve.csv -o -name sample.granstab); do
  cmp "$work/local/out/$f" "$work/mpi/out/$f" || { echo "$f differs from the local run"; exit 1; }
done
echo "MPI study: 8 tasks over 3 ranks, results identical to the local run"
