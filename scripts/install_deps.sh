#!/usr/bin/env bash
# Installs the build and run dependencies from Debian 12 packages (run as root, or with sudo).
# Idempotent: packages already present are skipped by apt.
set -euo pipefail
PACKAGES=(
  cmake ninja-build g++ pkg-config git
  libeigen3-dev libsuitesparse-dev libhdf5-dev libhypre-dev
  libsqlite3-dev sqlite3 libcli11-dev libtomlplusplus-dev nlohmann-json3-dev libssl-dev
  libgtest-dev
  gnuplot-nox chromium
  paraview python3-paraview xvfb xauth libgl1-mesa-dri python3-h5py # ParaView check of the snapshots
  slurm-wlm munge
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  SUDO=""
  [[ $(id -u) -ne 0 ]] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
