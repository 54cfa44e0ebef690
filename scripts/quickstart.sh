#!/usr/bin/env bash
# README command (a): install dependencies, build Release, run the default study
# (studies/visc_patch.toml) into results/results.sqlite and print its result tables.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$ROOT/scripts/install_deps.sh"
"$ROOT/scripts/build.sh"
cd "$ROOT"
./build/runner studies/visc_patch.toml
echo
echo "err (seed 001 eq. 21), uniform lattice: rows n_side, columns visc"
./build/runner table visc_patch --rows n_side --cols visc --value err --where "lattice=uniform"
# The disordered lattice over five seeds: the median beside the mean (one outlier seed can carry a
# mean: VISC-04 at n = 20 has a mean of 7.38 because one seed gave 19.03).
for agg in median mean; do
  echo
  echo "err (seed 001 eq. 21), disordered lattice, ${agg} over 5 seeds: rows n_side, columns visc"
  ./build/runner table visc_patch --rows n_side --cols visc --value err --where "lattice=disordered" \
    --agg "${agg}"
done
