#!/usr/bin/env bash
# Hybrid SIC against pure dynamic SIC on one sample, in one run (issue #24 target: the hybrid at
# least 10x faster to epsilon_2 = 0.01 on the N = 1400 series B sample, same dq and tolerances).
#   bench/hybrid/run.sh [--build DIR] [--sample FILE] [--dq X] [--epsilon-2-end X] [--work DIR]
# Prints the wall seconds, MD steps and end of each run, and their ratio. One thread each.
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
build=$here/build
sample=$here/data/samples/series-b-n1400-k1e4-s1.granstab
dq=1e-2
end=0.01
work=/tmp/granstab-bench-hybrid
while [ $# -gt 0 ]; do
  case $1 in
    --build) build=$2; shift 2 ;;
    --sample) sample=$2; shift 2 ;;
    --dq) dq=$2; shift 2 ;;
    --epsilon-2-end) end=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
export OMP_NUM_THREADS=1
mkdir -p "$work"
# The series B SIC settings (data/configs/series-b-sic.toml): mu = 0.5, flow guard 0.05, the
# default SPEC 3.1 tolerances, 1e7 MD steps per increment.
common=(--dq "$dq" --mu 0.5 --epsilon-2-end "$end" --epsilon-2-max 0.05
        --max-steps-per-increment 10000000 --quiet)
echo "# $(date -u +%FT%TZ) $(uname -n) load: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# sample $sample dq $dq epsilon_2_end $end"
for method in hybrid dynamic; do
  flag=(); [ $method = hybrid ] && flag=(--hybrid)
  start=$(date +%s.%N)
  "$build/drivers/granstab" sic "$sample" "${common[@]}" "${flag[@]}" --out "$work/$method" > /dev/null
  stop=$(date +%s.%N)
  /usr/bin/python3 - "$work/$method/sic.json" "$stop" "$start" "$method" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"{sys.argv[4]:8s} wall {float(sys.argv[2]) - float(sys.argv[3]):8.1f} s  "
      f"static {s['static_seconds']:7.1f} s  MD {s['dynamic_seconds']:7.1f} s  "
      f"MD steps {s['md_steps']:>10d}  end {s['stop_reason']} at q {s['q_last']:.4g} "
      f"epsilon_2 {s['epsilon_2_last']:.4g}  rearrangements {s['rearrangements']}")
PY
done
/usr/bin/python3 - "$work" <<'PY'
import json, sys
h = json.load(open(sys.argv[1] + "/hybrid/sic.json"))
d = json.load(open(sys.argv[1] + "/dynamic/sic.json"))
th = h["static_seconds"] + h["dynamic_seconds"]
td = d["static_seconds"] + d["dynamic_seconds"]
print(f"dynamic / hybrid: {td / th:.2f}x in seconds, {d['md_steps'] / max(h['md_steps'], 1):.2f}x in MD steps")
PY
echo "# load after: $(cut -d' ' -f1-3 /proc/loadavg)"
