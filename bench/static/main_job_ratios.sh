#!/usr/bin/env bash
# Issue #18 target 1: static_seconds / dynamic_seconds of the six `granstab compare` runs of
# scripts/main-job.sh (--quiet, one thread), for one or more granstab binaries run one after the
# other per run (interleaved, so that a slow spell of the VM hits them alike), ROUNDS times.
# Usage: bench/static/main_job_ratios.sh [--cpu N] [--rounds R] [--out DIR] GRANSTAB [GRANSTAB...]
# Prints one line per run, binary and round; DIR/<binary index>-<round>/<run>/ keeps the results
# (compare the curves of two binaries with cmp).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cpu="" rounds=2 out=$(mktemp -d)
while [ $# -gt 0 ]; do
  case $1 in
    --cpu) cpu=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    *) break ;;
  esac
done
[ $# -ge 1 ] || { sed -n 5p "$0"; exit 2; }
pin=()
[ -n "$cpu" ] && pin=(taskset -c "$cpu")
sample="$root/data/samples/periodic-n100-k1e4.granstab"
# The runs of scripts/main-job.sh, in its order (keep the two lists in step).
runs=("mu0.5-dq1e-3|--dq 0.001 --mu 0.5 --probe-states 4"
  "mu0.15-dq1e-3|--dq 0.001 --mu 0.15 --probe-states 4"
  "mu0.5-dq1e-2|--dq 0.01 --mu 0.5"
  "mu0.15-dq1e-2|--dq 0.01 --mu 0.15"
  "mu0.15-substeps|--dq 0.01 --mu 0.15 --dynamic-substeps 100 --static-substeps 10"
  "mu0.5-substeps|--dq 0.001 --mu 0.5 --static-substeps 10 --dynamic-substeps 10 --no-hill")
for round in $(seq "$rounds"); do
  for spec in "${runs[@]}"; do
    name=${spec%%|*}
    read -r -a args <<< "${spec#*|}"
    b=0
    for granstab in "$@"; do
      b=$((b + 1))
      dir="$out/$b-$round/$name"
      OMP_NUM_THREADS=1 "${pin[@]}" "$granstab" compare "$sample" "${args[@]}" --quiet \
        --out "$dir" > /dev/null
      python3 - "$dir/compare.json" "$name" "$b" "$round" << 'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
print("%-16s binary %s round %s: static %.3f s, dynamic %.2f s, ratio %.3f, attempts %d, q1 %.9f"
      % (sys.argv[2], sys.argv[3], sys.argv[4], d["static_seconds"], d["dynamic_seconds"],
         d["static_seconds"] / d["dynamic_seconds"], d["static_attempts"], d["q1"]))
EOF
    done
  done
done
echo "results in $out"
