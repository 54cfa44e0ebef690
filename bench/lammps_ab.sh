#!/usr/bin/env bash
# Our pair engine against LAMMPS on the same machine at the same time (issue 21, part 3): Debian's
# `lammps` (binary lmp; its build has no SPH package, so `pair_style lj/smooth/linear` is the pair
# loop of reference) and build/sph_bench, run alternately A B A B, one thread each, then the ratios.
#
# The same set-up on both sides: N particles on the 2D square lattice of spacing dx in a periodic
# box, every coordinate shifted by a uniform random amount in [-0.1, 0.1] dx, pair cutoff = our
# kernel support 2.6 dx (Wendland C2, h = 1.3 dx: 20 neighbours within it), and the same Verlet
# skin (SKIN x cutoff, default 0.25, the wcsph_tvf default). LAMMPS: `neighbor` skin `bin`,
# `neigh_modify every 1 delay 0 check yes` (rebuilt when an atom has moved more than skin/2, checked
# every step), a weak potential and a temperature so that the atoms drift and the list is rebuilt
# every few steps; its timing breakdown gives
#   neighbour build, ns/particle = Neigh time / (list builds x N)   (per build; Neigh time /
#                                  (steps x N), printed too, is its cost per step amortised over
#                                  the steps between builds, 1 build in ~15 steps here)
#   pair loop, ns/particle-step  = Pair time / (steps x N)   (its half list: each pair once, both
#                                  forces from it; the list holds the skin's pairs too)
# and ours (sph_bench --n N --dim 2 --threads 1 --csv --skin SKIN):
#   neighbour build, ns/particle = "verlet list build" (sort by cell + candidates within cutoff +
#                                  skin; the sort reorders every particle field, LAMMPS sorts atoms
#                                  every 1000 steps apart from its builds)
#   pair loop, ns/particle-step  = "pair geometry (verlet list)" (r_ij, r, W, dW of the pairs within
#                                  the support, every step) + a pressure-gradient loop over them
#                                  (full list, gather), from "pressure grad (nbr list)" pairs/s.
# Ratios are ours / LAMMPS (below 1: we are faster), per alternated pair of runs, and their medians.
#   bench/lammps_ab.sh [N] [REPEATS]      environment: SKIN, STEPS (LAMMPS run length), LMP, BENCH
# Tiny size (seconds; the test bench_lammps_ab): STEPS=50 bench/lammps_ab.sh 400 1
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
N="${1:-40000}" REPEATS="${2:-3}"
SKIN="${SKIN:-0.25}" STEPS="${STEPS:-400}"
LMP="${LMP:-lmp}" BENCH="${BENCH:-$ROOT/build/sph_bench}"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
export OMP_NUM_THREADS=1
command -v "$LMP" >/dev/null ||
  { echo "lammps_ab.sh: LAMMPS ($LMP) not found (Debian package lammps)" >&2; exit 1; }

side=$(awk -v n="$N" 'BEGIN { printf "%d", int(sqrt(n) + 0.5) }')
rc=2.6
skin=$(awk -v s="$SKIN" -v rc="$rc" 'BEGIN { printf "%.6g", s * rc }')
cat >"$TMP/in.pairs" <<LMP
# $((side * side)) atoms, 2D square lattice (spacing 1), disorder +-0.1, cutoff $rc, skin $skin
units lj
dimension 2
boundary p p p
atom_style atomic
lattice sq 1.0
region box block 0 $side 0 $side -0.5 0.5
create_box 1 box
create_atoms 1 box
mass 1 1.0
displace_atoms all random 0.1 0.1 0.0 4711 units box
pair_style lj/smooth/linear $rc
pair_coeff 1 1 0.001 0.89
velocity all create 1.0 4712 dist gaussian
neighbor $skin bin
neigh_modify every 1 delay 0 check yes
fix 1 all nve
fix 2 all enforce2d
timestep 0.005
thermo $STEPS
run $STEPS
LMP

run_lammps() {
  (cd "$TMP" && "$LMP" -in in.pairs -log "$TMP/log.lammps" -screen none) ||
    { cat "$TMP/log.lammps" >&2; echo "lammps_ab.sh: $LMP failed (log above)" >&2; exit 1; }
  awk -v N="$((side * side))" -v steps="$STEPS" '
    /^Pair  *\|/ { pair = $5 }                 # avg column
    /^Neigh  *\|/ { neigh = $5 }
    /^Neighbor list builds/ { builds = $5 }
    /^Total # of neighbors/ { half = $6 }
    /% CPU use/ { cpu = $1 }                    # below ~95 %: the machine was loaded
    END { if (!builds) exit 1
          printf "%.6g %.6g %.6g %.6g %s %.4g\n", 1e9 * neigh / (builds * N),
                 1e9 * pair / (steps * N), 2 * half / N, builds, cpu, 1e9 * neigh / (steps * N) }' \
    "$TMP/log.lammps"
}

run_ours() {
  "$BENCH" --n "$N" --dim 2 --threads 1 --csv --skin "$SKIN" >"$TMP/ours.csv"
  awk -F, '
    $5 == "verlet list build" { build = $6 }
    $5 == "pair geometry (verlet list)" { geo = $6 }
    $5 == "pressure grad (nbr list)" { pps = $6; nb = $3 }
    $5 == "verlet candidates" { cand = $6 }
    END { printf "%.6g %.6g %.6g %.6g %.6g\n", build, geo + 1e9 * nb / pps, nb, cand, pps }' \
    "$TMP/ours.csv"
}

echo "run,side,build_ns_per_particle,pair_ns_per_particle_step,list_entries_per_particle,extra"
for r in $(seq "$REPEATS"); do
  read -r l_build l_pair l_list l_builds l_cpu l_step < <(run_lammps)
  echo "$r,LAMMPS,$l_build,$l_pair,$l_list,builds=$l_builds neigh_ns_per_particle_step=$l_step cpu_use=$l_cpu"
  read -r o_build o_pair o_nb o_cand o_pps < <(run_ours)
  echo "$r,ours,$o_build,$o_pair,$o_cand,within_support=$o_nb pressure_pairs_per_s=$o_pps"
  echo "$r,ratio,$(awk -v a="$o_build" -v b="$l_build" 'BEGIN { printf "%.3g", a / b }'),$(
    awk -v a="$o_pair" -v b="$l_pair" 'BEGIN { printf "%.3g", a / b }'),,"
done | tee "$TMP/all.csv"
awk -F, '$2 == "ratio" { b[++n] = $3; p[n] = $4 }
  function med(a, n,   i, j, t) { for (i = 1; i <= n; ++i) for (j = i + 1; j <= n; ++j) if (a[j] < a[i]) { t = a[i]; a[i] = a[j]; a[j] = t }
                                  return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2 }
  END { printf "median ratios ours / LAMMPS over %d alternated pairs: neighbour build %.3g, pair loop per particle-step %.3g\n",
               n, med(b, n), med(p, n) }' "$TMP/all.csv"
