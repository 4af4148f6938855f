#!/usr/bin/env bash
# Validation of the dynamic protocols against SPEC §6 (issue #4, docs/validation.md); not part
# of ctest. Prepares series B samples (periodic, mu_prep = 0.15 or MU_PREP, K_T/K_N = 1,
# zeta = 1, N = 1400) at each kappa and seed, tabulates Phi, z, x0 (mean ± standard deviation over
# seeds) beside SPEC Table 1, then runs an SRC test (kappa = 1e4, gamma = 1e-4, to
# epsilon_2 = 0.02) and an SIC test (delta q = 0.01, to failure) on the first kappa = 1e4 sample,
# mu = 0.5.
# Compaction schedule: the recommended one (data/configs/series-b-n1400-k1e4-sr.toml: strain rate
# 0.01 until the mean stress reaches P, then stress control); STRAIN_RATE=0 gives the literal
# stress-control schedule of the shipped sample (series-b-n1400-k1e4.toml).
#
#   scripts/validate_series_b.sh [OUTDIR]            (default OUTDIR: validation-out)
# Environment: KAPPAS (default "1e3 1e4 1e5"), SEEDS ("1 2 3"), N (1400), GAMMA (1e-4),
#   EPS2_MAX (0.02), DELTA_Q (0.01), SKIP_BIAXIAL=1 to stop after Table 1, STRAIN_RATE (0.01;
#   compaction.strain_rate, 0 = stress control from the gas), MU_PREP (0.15, SPEC §3.2; 0.125
#   reproduces Phi, z and x0 of Table 1 at the three kappa, docs/validation.md "What moves z" (k)),
#   BUILD_DIR (build), OMP_NUM_THREADS (1: one thread is the fastest on a loaded 2-core box).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=$(realpath -m "${1:-validation-out}")
granstab="${BUILD_DIR:-$root/build}/drivers/granstab"
kappas=${KAPPAS:-"1e3 1e4 1e5"}
seeds=${SEEDS:-"1 2 3"}
n=${N:-1400}
strain_rate=${STRAIN_RATE:-0.01}
config="$root/data/configs/series-b-n1400-k1e4-sr.toml"
mu_prep=${MU_PREP:-0.15}
tag="-sr$strain_rate"
[ "$strain_rate" = 0 ] && tag=""
[ "$mu_prep" = 0.15 ] || tag="$tag-mu$mu_prep"
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}
python=/usr/bin/python3
mkdir -p "$out"
[ -x "$granstab" ] || { echo "no granstab binary at $granstab (set BUILD_DIR)" >&2; exit 1; }

json_field() { "$python" -c 'import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])' "$1" "$2"; }

echo "# series B preparation, N = $n, compaction.strain_rate = $strain_rate, mu_prep = $mu_prep" |
  tee "$out/table1.txt"
for kappa in $kappas; do
  for seed in $seeds; do
    name="b-n$n-k$kappa-s$seed$tag"
    if [ ! -f "$out/$name.json" ]; then
      "$granstab" prepare --quiet "$config" --set compaction.strain_rate="$strain_rate" \
        --set material.mu="$mu_prep" \
        --set sample.n="$n" --set material.kappa="$kappa" --set sample.seed="$seed" \
        --set output.sample="\"$out/$name.granstab\"" --set output.summary="\"$out/$name.json\""
    fi
    echo "$kappa $seed $(json_field "$out/$name.json" phi) $(json_field "$out/$name.json" z)" \
         "$(json_field "$out/$name.json" x0) $(json_field "$out/$name.json" steps)" \
         "$(json_field "$out/$name.json" wall_seconds)" >> "$out/prepare$tag.dat"
  done
done
"$python" - "$out/prepare$tag.dat" <<'PY' | tee -a "$out/table1.txt"
import statistics as st, sys
ref = {"1e5": ("0.8226 ± 0.0008", "3.59 ± 0.02", "10.0 ± 0.5"),
       "1e4": ("0.8230 ± 0.0008", "3.64 ± 0.02", "9.0 ± 0.6"),
       "1e3": ("0.8258 ± 0.0009", "3.77 ± 0.008", "6.7 ± 0.3")}
rows = {}
for line in open(sys.argv[1]):
    k, seed, phi, z, x0, steps, wall = line.split()
    rows.setdefault(k, {})[seed] = (float(phi), float(z), 100 * float(x0), int(steps), float(wall))
def ms(v):
    return f"{st.mean(v):.4f} ± {st.stdev(v):.4f}" if len(v) > 1 else f"{v[0]:.4f}"
print("| kappa | seeds | Phi | z | x0 (%) | steps (mean) | wall s (mean) | SPEC Phi | SPEC z | SPEC x0 (%) |")
print("|---|---|---|---|---|---|---|---|---|---|")
for k, by_seed in rows.items():
    v = list(by_seed.values())
    r = ref.get(k, ("?", "?", "?"))
    print(f"| {k} | {len(v)} | {ms([x[0] for x in v])} | {ms([x[1] for x in v])} | "
          f"{ms([x[2] for x in v])} | {st.mean([x[3] for x in v]):.0f} | "
          f"{st.mean([x[4] for x in v]):.0f} | {r[0]} | {r[1]} | {r[2]} |")
PY

[ "${SKIP_BIAXIAL:-0}" = 1 ] && exit 0
first_seed=${seeds%% *}
sample="$out/b-n$n-k1e4-s$first_seed$tag.granstab"
[ -f "$sample" ] || "$granstab" prepare --quiet "$config" --set compaction.strain_rate="$strain_rate" \
  --set material.mu="$mu_prep" --set sample.n="$n" --set sample.seed="$first_seed" \
  --set output.sample="\"$sample\"" --set output.summary="\"${sample%.granstab}.json\""
cat > "$out/src.toml" <<TOML
[input]
sample = "$sample"
[material]
mu = 0.5
[biaxial]
control = "strain-rate"
gamma = ${GAMMA:-1e-4}
epsilon_2_max = ${EPS2_MAX:-0.02}
record_interval = 1e-4
[output]
csv = "$out/src.csv"
TOML
cat > "$out/sic.toml" <<TOML
[input]
sample = "$sample"
[material]
mu = 0.5
[biaxial]
control = "stress-steps"
delta_q = ${DELTA_Q:-0.01}
q_max = 2.0
failure_epsilon_2 = 0.05
[output]
csv = "$out/sic.csv"
TOML
"$granstab" biaxial "$out/src.toml"
"$granstab" biaxial "$out/sic.toml"
for run in src sic; do
  echo "$run: steps $(json_field "$out/$run.json" steps), wall $(json_field "$out/$run.json" wall_seconds) s," \
       "stop: $(json_field "$out/$run.json" stop_reason)"
done
