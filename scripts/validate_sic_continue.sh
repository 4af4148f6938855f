#!/usr/bin/env bash
# Continues an SIC test (SPEC §3.3) from a saved equilibrium state, one stress increment per
# `granstab perturb` run, until an increment finds no equilibrium (docs/validation.md, "SIC to
# failure"). Not part of ctest.
#
# Why perturb: `granstab biaxial` starts a new stage (reference lengths reset to the sample's,
# q restarted at 0), so it cannot resume a saved SIC state. `granstab perturb` keeps the sample's
# stage (reference lengths L_a0, hence comparable strains) and first brings the sample to
# equilibrium at sigma_1 = P, sigma_2 = P (1 + perturb.q): with f0 = 1e-12 and one draw that
# loaded-equilibrium is the SIC increment itself (the draw changes nothing measurable).
# Failure: no equilibrium within MAX_STEPS steps of one increment (perturb exits non-zero). The
# biaxial command's other guard (epsilon_2 > failure_epsilon_2) is not available here.
#
#   scripts/validate_sic_continue.sh START_STATE K_START OUTDIR
# START_STATE: an SIC equilibrium state (e.g. sic_q_1.000000.granstab from granstab biaxial
# with output.save_every); K_START: the first increment to run (q = K_START * DELTA_Q).
# Environment: DELTA_Q (0.01), K_MAX (300), MAX_STEPS (2000000), BUILD_DIR (build).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
start=$(realpath "$1")
k=$2
out=$(realpath -m "$3")
dq=${DELTA_Q:-0.01}
k_max=${K_MAX:-300}
max_steps=${MAX_STEPS:-2000000}
granstab="${BUILD_DIR:-$root/build}/drivers/granstab"
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}
python=/usr/bin/python3
mkdir -p "$out"
[ -x "$granstab" ] || { echo "no granstab binary at $granstab (set BUILD_DIR)" >&2; exit 1; }

cat > "$out/step.toml" <<TOML
[perturb]
f0 = 1e-12
repetitions = 1
release = false
[equilibrium]
max_steps = $max_steps
TOML

table="$out/sic_continue.dat"
[ -f "$table" ] || echo "# q steps wall_s epsilon_2 epsilon_v z x0 x_s sliding contacts max_net_force" > "$table"
state=$start
while [ "$k" -le "$k_max" ]; do
  q=$("$python" -c "print(f'{$k * $dq:.6f}')")
  next="$out/sic_q_$q.granstab"
  if ! "$granstab" perturb --quiet "$out/step.toml" --set input.sample="\"$state\"" \
      --set perturb.q="$q" --set output.csv="\"$out/step_$q.csv\"" \
      --set output.sample="\"$next\"" 2> "$out/step_$q.err"; then
    echo "# no equilibrium at q = $q within $max_steps steps: $(tail -1 "$out/step_$q.err")" | tee -a "$table"
    exit 0
  fi
  "$granstab" info --json "$next" > "$out/info_$q.json"
  "$python" - "$out/step_$q.json" "$out/info_$q.json" "$q" >> "$table" <<'PY'
import json, sys
run, info, q = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), sys.argv[3]
print(q, run["initial_equilibrium_steps"], f'{run["wall_seconds"]:.1f}', run["epsilon_2_final"],
      run["epsilon_v_final"], info["z"], info["x0"], info["x_s"], info["contacts_sliding"],
      info["contacts_carrying"], info["equilibrium"]["max_net_force"])
PY
  tail -1 "$table"
  state=$next
  k=$((k + 1))
done
