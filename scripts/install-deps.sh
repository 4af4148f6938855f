#!/usr/bin/env bash
# Installs granstab's Debian dependencies (DEPS.md) when any is missing; a no-op run takes ~1 s.
set -euo pipefail
packages=(g++ cmake make ninja-build pkg-config libeigen3-dev libsuitesparse-dev coinor-libipopt-dev
  libspectra-dev libcli11-dev libtomlplusplus-dev libgtest-dev libgmock-dev libbenchmark-dev
  python3-matplotlib python3-munkres
  python3-dev pybind11-dev python3-numpy python3-pytest  # the Python module and its tests
  libopenmpi-dev openmpi-bin  # granstab study under mpirun
  # The serial OpenBLAS becomes the system's libblas.so.3 (Debian alternatives): it runs the dense
  # fronts of UMFPACK's LUs, 42 % of a q1 run at N = 5600 on the reference BLAS (docs/static.md).
  libopenblas0-serial)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
echo "granstab: installing ${missing[*]}" >&2
$SUDO apt-get update -qq
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
  -o DPkg::Lock::Timeout=300 "${missing[@]}" >/dev/null
