#!/usr/bin/env bash
# Installs every Debian package the project needs (apt-get) and builds it in build/
# for this machine (ROVER_NATIVE=OFF for a portable build).
# Safe to run again: apt-get skips what is installed, CMake rebuilds what changed.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
native="${ROVER_NATIVE:-ON}"
case "$native" in
  ON|OFF|1|0) ;;
  *) echo "setup: ROVER_NATIVE must be ON or OFF (or 1 or 0), got '$native'" >&2; exit 1 ;;
esac

packages=(
  build-essential cmake pkg-config
  libeigen3-dev libboost-dev libnlopt-cxx-dev libnlopt-dev
  libopenmpi-dev openmpi-bin libhdf5-dev
  nlohmann-json3-dev libcli11-dev libgtest-dev libbenchmark-dev
  gnuplot-nox python3-h5py python3-numpy
  python3-openturns  # the documented OpenTURNS example and the surrogate comparison
  time bc  # /usr/bin/time and bc, for the timing scripts in bench/
)
# Optional: SUNDIALS for bench/sundials_bench, the comparison with CVODE and
# ARKODE. Debian's libsundials-dev pulls in PETSc and hypre (about 1 GB).
if [[ "${ROVER_WITH_SUNDIALS:-0}" == 1 ]]; then packages+=(libsundials-dev); fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=""
  if [[ $(id -u) -ne 0 ]]; then sudo_cmd="sudo"; fi
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# The build is for this machine (-march=native: AVX2/FMA where the CPU has
# them, about 15 % faster runs). Building on one machine to run on another (a
# cluster's login node for its compute nodes): ROVER_NATIVE=OFF.
build_type="${ROVER_BUILD_TYPE:-Release}"
cmake -S "$here" -B "$here/build" -DCMAKE_BUILD_TYPE="$build_type" -DROVER_NATIVE="$native" >/dev/null
# ROVER_BUILD_TARGET: one target (the main job builds only `rover`); default all.
target=()
if [[ -n "${ROVER_BUILD_TARGET:-}" ]]; then target=(--target "$ROVER_BUILD_TARGET"); fi
cmake --build "$here/build" --parallel "$(nproc)" "${target[@]}"
echo "setup: built in $here/build"
