#!/usr/bin/env bash
# Configures and builds granstab (Release, -Wall -Wextra) into ${BUILD_DIR:-build}.
# Extra CMake arguments are passed through, e.g. scripts/build.sh -DGRANSTAB_SANITIZE=ON.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DGRANSTAB_WERROR=ON "$@" >/dev/null
cmake --build "$build" -j "$(nproc)"
