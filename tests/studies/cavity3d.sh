#!/usr/bin/env bash
# CI check of the 3D lid-driven cavity (seed 002 section 4.5, issue 14): the quick tier of
# studies/cavity3d.toml (a 10^3 cube for 0.3 time units, wcsph_tvf and isph through the same case
# and the shared time loop; seconds) runs into a fresh database; its metrics sit in value bands;
# the full study expands to its jobs; the report renders. Usage: cavity3d.sh RUNNER SRC
RUNNER="$1" SRC="$2"
source "$(dirname "$0")/lib.sh"

expect_jobs cavity3d "" 7
run_quick cavity3d
[ "$(q "SELECT count(*) FROM jobs WHERE state = 'done'")" = 2 ] || fail "expected 2 done jobs"
# band SCHEME METRIC VALUE TOL: the quick-tier job of SCHEME has METRIC within VALUE +- TOL.
# Values measured on this tier (2026-12-01); the tolerances are about 5 % of E_k and 0.01 U0 of
# the profile extrema: far above round-off and the spread of thread counts, far below what a
# wrong wall velocity, viscosity or lid direction gives (the lid's E_k input at t = 0.3 scales
# with nu and the wall treatment).
# (The tier's isph job is the one with the cubic spline, the wcsph_tvf job has Wendland C2.)
kernel_of() { [ "$1" = isph ] && echo cubic_spline || echo wendland_c2; }
value() {
  q "SELECT value FROM job_metrics WHERE study = 'cavity3d' AND metric = '$2' AND json_extract(params, '$.kernel') = '$(kernel_of "$1")'"
}
band() {
  local v
  v="$(value "$1" "$2")"
  awk -v v="$v" -v c="$3" -v t="$4" 'BEGIN { exit !(v != "" && v >= c - t && v <= c + t) }' ||
    fail "$1 $2 = '$v', expected $3 +- $4"
}
band wcsph_tvf ke 0.01405 0.0007
band wcsph_tvf ux_min -0.1132 0.01
band wcsph_tvf uz_min -0.0864 0.01
band isph ke 0.00474 0.00024
band isph ux_min -0.0613 0.01
band isph uz_min -0.0376 0.01
# The lid drags the fluid next to it in +x: u_x just below the lid is positive and the return
# flow below the centre negative, for both schemes.
for s in wcsph_tvf isph; do
  hi="$(value "$s" ux_at_z_0.9766)"
  awk -v v="$hi" 'BEGIN { exit !(v > 0.2) }' || fail "$s: u_x below the lid $hi"
done
render_reports cavity3d
echo "cavity3d quick tier: OK"
