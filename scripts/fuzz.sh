#!/usr/bin/env bash
# Fuzzes the input readers (issue #8, docs/reliability.md) with libFuzzer + ASan + UBSan:
#   scripts/fuzz.sh [SECONDS [TARGET...]]     SECONDS per target (default 60);
#   targets: configuration (the .granstab reader), run_config (the TOML run settings) and
#   material_options (--mu / --kt-ratio / --set material.* of the static commands).
# Builds tests/fuzz with clang++ into ${FUZZ_BUILD_DIR:-build-fuzz}; the growing corpus is kept
# in <build>/corpus/TARGET, and every crash, hang (> 10 s on one input) or contract violation
# as <build>/artifacts/TARGET/crash-* (timeout-*, oom-*). Exits 1 if any target found something.
# A crash input goes to tests/fuzz/regressions/TARGET/ (tests/common/test_fuzz_regressions.cpp).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(configuration run_config material_options)
build=${FUZZ_BUILD_DIR:-$root/build-fuzz}

cmake -S "$root/tests/fuzz" -B "$build" -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" -j "$(nproc)"

# Seeds: the hand-written ones, the shipped samples, the documented example, shipped settings.
seeds=$build/seeds
rm -rf "$seeds"
mkdir -p "$seeds/configuration" "$seeds/run_config" "$seeds/material_options"
cp "$root"/tests/fuzz/seeds/material_options/* "$seeds/material_options/" 2>/dev/null || true
cp "$root"/tests/fuzz/seeds/configuration/* "$root"/tests/fuzz/regressions/configuration/* \
  "$seeds/configuration/" 2>/dev/null || true
cp "$root"/data/samples/*.granstab "$seeds/configuration/" 2>/dev/null || true
awk '/^## Example/{e=1} e && /^```$/{n++; next} e && n==1' "$root/docs/file-format.md" \
  >"$seeds/configuration/file-format-example.granstab"
cp "$root"/tests/fuzz/seeds/run_config/* "$root"/tests/fuzz/regressions/run_config/* \
  "$seeds/run_config/" 2>/dev/null || true
cp "$root"/data/configs/*.toml "$seeds/run_config/" 2>/dev/null || true

status=0
for target in "${targets[@]}"; do
  corpus=$build/corpus/$target
  artifacts=$build/artifacts/$target
  mkdir -p "$corpus" "$artifacts"
  echo "== fuzz_$target for $seconds s (corpus $corpus)" >&2
  # New inputs go to the first directory (the kept corpus); the seeds are read only.
  if ! "$build/fuzz_$target" "$corpus" "$seeds/$target" \
      -dict="$root/tests/fuzz/$target.dict" -max_total_time="$seconds" -timeout=10 \
      -max_len=16384 -rss_limit_mb=2048 -artifact_prefix="$artifacts/" -print_final_stats=1 \
      2>"$build/fuzz_$target.log"; then
    status=1
  fi
  grep -E "(DONE|stat::|==[0-9]+==ERROR|SUMMARY|contract violated)" \
    "$build/fuzz_$target.log" >&2 || true
  if compgen -G "$artifacts/*" >/dev/null; then
    status=1
    echo "fuzz_$target found inputs in $artifacts (log: $build/fuzz_$target.log):" >&2
    ls "$artifacts" >&2
  fi
done
exit $status
