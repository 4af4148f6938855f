#!/usr/bin/env bash
# Configures and builds granstab (Release, -Wall -Wextra) into ${BUILD_DIR:-build}.
# Extra CMake arguments are passed through, e.g. scripts/build.sh -DGRANSTAB_SANITIZE=ON.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
# Ninja when it is installed (install-deps.sh installs it): it schedules across targets, so two
# cores stay busy, and it spends less CPU than make on dependency scanning. A build directory
# configured before keeps its generator (CMake refuses to change it).
generator=()
if [ -z "${CMAKE_GENERATOR:-}" ] && [ ! -f "$build/CMakeCache.txt" ] && command -v ninja >/dev/null; then
  generator=(-G Ninja)
fi
cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DGRANSTAB_WERROR=ON "$@" >/dev/null
cmake --build "$build" -j "$(nproc)"
