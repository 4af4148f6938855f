#!/usr/bin/env bash
# Issue #7: granstab against LAMMPS on the same workload. See README.md beside this file for the
# conversions and the convention differences that remain; results in bench/README.md.
#
#   bench/compare_lammps/run.sh [--build DIR] [--work DIR] [--sizes "1400 5600 22400"]
#                               [--repeats 3] [--particle-steps 2.24e7] [--quick] [--pin CPU]
#
# For each N: one packing (make_packing), then per repeat, interleaved: LAMMPS on 1 process,
# granstab on 1 thread, LAMMPS on 2 MPI processes, granstab on 2 OpenMP threads, each running
# the same strain-rate test for the same number of steps (particle-steps / N). Prints the
# particle-steps per second (medians over the repeats), the ratios, and checks the two codes'
# stress curves (compare.py), with the cache-line hand-over between CPU 0 and 1 measured before
# the runs and after each repeat-size group (handover.cpp). --quick divides the particle-steps
# by 8 and uses 3 repeats.
# --pin CPU runs both one-process runs on that CPU (taskset): on a VM whose CPUs run at unequal
# speeds, the one-thread ratio then compares the codes, not the CPUs they landed on.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
build="$repo/build"
work="${TMPDIR:-/tmp}/granstab-compare-lammps"
sizes="1400 5600 22400"
repeats=3
particle_steps=2.24e7
pin=()
lmp_skin=${LMP_SKIN:-0.05}  # neighbour settings, see README.md ("Neighbour settings")
gs_skin=${GS_SKIN:-0.1}
while [[ $# -gt 0 ]]; do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --sizes) sizes="$2"; shift 2 ;;
    --repeats) repeats="$2"; shift 2 ;;
    --particle-steps) particle_steps="$2"; shift 2 ;;
    --quick) particle_steps=2.8e6; shift ;;
    --pin) pin=(taskset -c "$2"); shift 2 ;;
    *) echo "run.sh: unknown option $1" >&2; exit 2 ;;
  esac
done

# LAMMPS from Debian (binary lmp; GRANULAR package, OpenMPI build, no OPENMP package).
if ! command -v lmp > /dev/null; then
  apt-get update
  DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
    -o DPkg::Lock::Timeout=300 lammps
fi
lmp_help="$(lmp -h)"
grep -q "gran/hooke/history" <<< "$lmp_help" || { echo "run.sh: lmp lacks gran/hooke/history" >&2; exit 1; }
# Ranks yield while waiting (the counterpart of OMP_WAIT_POLICY=passive for granstab's threads):
# on a shared machine busy-polling ranks burn the time slices of the one that has work.
mpirun=(mpirun -np 2 --bind-to none --mca mpi_yield_when_idle 1)
[[ $(id -u) -eq 0 ]] && mpirun+=(--allow-run-as-root)

build="$(realpath -m "$build")"  # the runs below cd into the work directory
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release > /dev/null
fi
cmake --build "$build" -j2 --target make_packing run_granstab handover > /dev/null
make_packing="$build/bench/compare_lammps/make_packing"
run_granstab="$build/bench/compare_lammps/run_granstab"
handover="$build/bench/compare_lammps/handover"

mkdir -p "$work"
cd "$work"
echo "# machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) CPUs; LAMMPS $(grep -m1 'Large-scale' <<< "$lmp_help" | sed 's/.*Simulator - //')"
echo "# work directory: $work; load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
[[ ${#pin[@]} -gt 0 ]] && echo "# one-process runs: ${pin[*]}"
export OMP_WAIT_POLICY=passive
for n in $sizes; do
  if [[ ! -f "p$n.env" ]]; then
    OMP_NUM_THREADS=1 "$make_packing" "$n" 2026 "p$n"
  fi
done

lammps() {  # lammps N STEPS EVERY OUT [mpirun...]
  local n=$1 steps=$2 every=$3 out=$4; shift 4
  # shellcheck disable=SC1090
  source "p$n.env"
  OMP_NUM_THREADS=1 "$@" lmp -in "$here/in.biaxial" -log none -nocite -var data "p$n.data" \
    -var steps "$steps" -var every "$every" -var dt "$DT" -var kn "$KN" -var kt "$KT" \
    -var gamma_n "$GAMMA_N" -var mu "$MU" -var erate "$ERATE" -var skin "$lmp_skin" > "$out"
}

# The one-way cache-line hand-over between CPU 0 and 1 (handover.cpp), before the runs and after
# each (repeat, N) group: on a VM it changes by 4x within minutes, and both codes' two-process
# speed-ups follow it. compare.py prints the list.
measure_handover() {  # measure_handover LABEL
  local ns
  ns=$("$handover" | awk '{print $2}')
  echo "$1 $ns" >> handover.txt
  echo "# cache-line hand-over, CPU 0 <-> 1, $1: $ns ns"
}
rm -f handover.txt
measure_handover start

for r in $(seq 1 "$repeats"); do
  for n in $sizes; do
    steps=$(awk -v p="$particle_steps" -v n="$n" 'BEGIN { s = int(p / n / 100) * 100; print (s < 200 ? 200 : s) }')
    every=$((steps / 20))
    lammps "$n" "$steps" "$every" "lammps_${n}_1_$r.out" "${pin[@]}"
    OMP_NUM_THREADS=1 "${pin[@]}" "$run_granstab" "p$n.granstab" "$steps" "$every" 1 "$gs_skin" \
      > "granstab_${n}_1_$r.out"
    lammps "$n" "$steps" "$every" "lammps_${n}_2_$r.out" "${mpirun[@]}"
    OMP_NUM_THREADS=2 "$run_granstab" "p$n.granstab" "$steps" "$every" 2 "$gs_skin" > "granstab_${n}_2_$r.out"
    echo "# repeat $r, N = $n, $steps steps done; load average $(cut -d' ' -f1-3 /proc/loadavg)"
    measure_handover "r$r-N$n"
  done
done

/usr/bin/python3 "$here/compare.py" --work "$work" --sizes "$sizes" --repeats "$repeats"
