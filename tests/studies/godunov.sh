#!/usr/bin/env bash
# CI check of the contact-SPH studies (seed 003, issue 5): the quick tiers of
# studies/godunov_eta_num.toml, godunov_zeta.toml and godunov_cylinders.toml run through the
# runner into a fresh database (seconds); the metrics the issue names are recorded; the correction
# lowers profile_err (shear layer) and the drag K (cylinder array); the paper tiers expand to
# their job counts; the reports render. Usage: godunov.sh RUNNER SOURCE_DIR
RUNNER="$1" SRC="$2"
source "$(dirname "$0")/lib.sh"

expect_jobs godunov_eta_num paper 46
expect_jobs godunov_zeta paper 8
expect_jobs godunov_cylinders paper 14
run_quick godunov_eta_num godunov_zeta godunov_cylinders
[ "$(q "SELECT count(*) FROM jobs WHERE state = 'done'")" = 8 ] || fail "expected 8 done jobs (3 + 3 + 2)"
for m in eta_fit eta_fit_spread profile_err; do
  expect_metric_count godunov_eta_num "$m" 3
done
for m in K CD CD_eq39 CD_ratio U_drift drag_balance wall_s; do
  expect_metric_count godunov_cylinders "$m" 2
done
# The correction removes numerical viscosity: lower profile_err for lead, lower drag K.
lead() { q "SELECT value FROM job_metrics WHERE study = 'godunov_zeta' AND metric = 'profile_err' AND json_extract(params, '$.material_left') = '' AND json_extract(params, '$.zeta') = $1"; }
awk -v a="$(lead 1.0)" -v b="$(lead 0.0)" 'BEGIN { exit !(a < b) }' || fail "profile_err(zeta = 1) >= profile_err(zeta = 0)"
cyl() { q "SELECT value FROM job_metrics WHERE study = 'godunov_cylinders' AND metric = 'K' AND json_extract(params, '$.zeta') = $1"; }
awk -v a="$(cyl 1.0)" -v b="$(cyl 0.0)" 'BEGIN { exit !(a < b) }' || fail "K(zeta = 1) >= K(zeta = 0)"
render_reports godunov_eta_num godunov_zeta godunov_cylinders
echo "godunov quick tiers: OK"
