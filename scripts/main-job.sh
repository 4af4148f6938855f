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
