#!/usr/bin/env bash
# Installs dependencies from Debian 12 packages (as root, or a user with sudo). Idempotent:
# packages already installed are skipped, and apt-get is not called at all when nothing is missing
# (so a user without root can run it once an administrator has installed the packages).
#
# Usage: install_deps.sh [--with-paraview] [--with-browser] [--with-slurm] [--tests] [--all] [--list]
#   (no flag)        what building the runner and running a study needs, and gnuplot for the
#                    figures of `runner report`
#   --with-paraview  ParaView and pvpython, a virtual X server and h5py (opening particle fields;
#                    the test study_paraview_fields)
#   --with-browser   Chromium (the headless check of report pages; screenshots)
#   --with-slurm     Slurm and munge (`runner submit --slurm` on a local cluster; the Slurm test)
#   --tests          GoogleTest and Python 3 (building and running the test suite), LAMMPS and
#                    PySPH (the checks of bench/lammps_ab.sh and bench/pysph_tgv.py)
#   --all            all of the above (scripts/test.sh: the whole suite, nothing skipped)
#   --list           print the selected packages, one a line, and install nothing
set -euo pipefail
CORE=(
  cmake ninja-build g++ pkg-config git
  libeigen3-dev libsuitesparse-dev libhdf5-dev libhypre-dev
  libsqlite3-dev sqlite3 libcli11-dev libtomlplusplus-dev nlohmann-json3-dev libssl-dev
  gnuplot-nox
)
PARAVIEW=(paraview python3-paraview xvfb xauth libgl1-mesa-dri python3-h5py)
BROWSER=(chromium)
SLURM=(slurm-wlm munge)
TESTS=(libgtest-dev python3 lammps python3-pysph)

PACKAGES=("${CORE[@]}")
list=0
for arg in "$@"; do
  case "$arg" in
    --with-paraview) PACKAGES+=("${PARAVIEW[@]}") ;;
    --with-browser) PACKAGES+=("${BROWSER[@]}") ;;
    --with-slurm) PACKAGES+=("${SLURM[@]}") ;;
    --tests) PACKAGES+=("${TESTS[@]}") ;;
    --all) PACKAGES+=("${TESTS[@]}" "${PARAVIEW[@]}" "${BROWSER[@]}" "${SLURM[@]}") ;;
    --list) list=1 ;;
    -h | --help) sed -n '2,16p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "install_deps.sh: unknown option '$arg' (--help lists them)" >&2; exit 2 ;;
  esac
done
mapfile -t PACKAGES < <(printf '%s\n' "${PACKAGES[@]}" | awk '!seen[$0]++')

if ((list)); then
  printf '%s\n' "${PACKAGES[@]}"
  exit 0
fi
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  SUDO=""
  if [[ $(id -u) -ne 0 ]]; then
    if ! command -v sudo >/dev/null; then
      echo "install_deps.sh: missing Debian packages: ${missing[*]}" >&2
      echo "  install them as root (apt-get install ${missing[*]}), then run this again" >&2
      exit 1
    fi
    SUDO="sudo"
  fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
