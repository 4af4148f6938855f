#!/usr/bin/env bash
# The README's test command: install what is missing, configure, build, run ctest; then, once
# that passes, the same under AddressSanitizer + UndefinedBehaviorSanitizer in build-asan/
# (docs/reliability.md). GRANSTAB_SANITIZERS=0 skips the sanitizer half.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
(cd "${BUILD_DIR:-$root/build}" && ctest --output-on-failure -j "$(nproc)")

[ "${GRANSTAB_SANITIZERS:-1}" = 0 ] && exit 0
asan=${ASAN_BUILD_DIR:-$root/build-asan}
# RelWithDebInfo at -O1 -g1: line tables are all the sanitizers' reports need for file:line, and
# both cut the compile time, which is most of CI (the tests run in ~2.5 min under ASan). The
# benchmarks are not run by ctest, so they are not built here.
BUILD_DIR=$asan "$root/scripts/build.sh" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" -DGRANSTAB_SANITIZE=ON \
  -DGRANSTAB_BUILD_BENCH=OFF
cd "$asan"
# Tests labelled sanitizer_skip are too slow under ASan; they ran in the Release build above.
ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1:check_initialization_order=1} \
UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1} \
  ctest --output-on-failure -j "$(nproc)" -LE sanitizer_skip
