#!/usr/bin/env bash
# Install the Debian 12 packages this project needs, only those that are missing.
# Runs apt-get as root (or through sudo). Safe to run repeatedly.
#   install-deps.sh [PKG...]        the serial build's packages, plus any extra Debian package names
#                                   (pipelines/impact/figures.mk: paraview python3-paraview xvfb xauth)
#   install-deps.sh --mpi [PKG...]  also OpenMPI and parallel HDF5 for the SUITE_MPI=ON build (build-mpi/);
#                                   libhdf5-openmpi-dev installs beside the serial libhdf5-dev (own include
#                                   and library directories), so the serial build is unchanged
set -euo pipefail
pkgs=(build-essential cmake pkg-config libeigen3-dev libhdf5-dev hdf5-tools libcli11-dev
      libspdlog-dev libtomlplusplus-dev libgtest-dev libgmock-dev libbenchmark-dev
      python3-numpy python3-h5py python3-matplotlib python3-scipy qemu-user)
if [ "${1:-}" = "--mpi" ]; then
  pkgs+=(libopenmpi-dev openmpi-bin libhdf5-openmpi-dev)
  shift
fi
for p in "$@"; do
  case "$p" in
    -*) echo "install-deps: unknown option '$p' (valid: --mpi, then package names)" >&2; exit 2 ;;
  esac
  pkgs+=("$p")
done
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#pkgs[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
