#!/usr/bin/env bash
# README command (a): install dependencies, build Release, run the default study
# (studies/visc_patch.toml) into results/results.sqlite and print its result tables.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$ROOT/scripts/install_deps.sh"
"$ROOT/scripts/build.sh"
cd "$ROOT"
./build/runner studies/visc_patch.toml
for lattice in uniform disordered; do
  echo
  echo "err (seed 001 eq. 21), ${lattice} lattice, mean over seeds: rows n_side, columns visc"
  ./build/runner table visc_patch --rows n_side --cols visc --value err --where "lattice=${lattice}"
done
