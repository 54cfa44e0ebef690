#!/usr/bin/env bash
# CI check of the transport-velocity study (seed 002, issue 6): the quick tier of
# studies/tvf_tgv.toml runs through the runner into a fresh database (seconds); the metrics the
# issue names are recorded for the four TVF variants and lie in value bands (issue 15; the
# limited correction's transport velocity below that of Adami's background pressure follows); the
# full study expands to its 21 jobs; the report renders. Usage: tvf.sh RUNNER SOURCE_DIR
RUNNER="$1" SRC="$2"
source "$(dirname "$0")/lib.sh"

expect_jobs tvf_tgv "" 21
run_quick tvf_tgv
[ "$(q "SELECT count(*) FROM jobs WHERE state = 'done'")" = 4 ] || fail "expected 4 done jobs"
for m in ke_rate_rel_err ke_rel_err_end umax_rel_err_end tv_ratio_max sumW_spread_end sumW_rms_end; do
  expect_metric_count tvf_tgv "$m" 4
done
# Value bands (issue 15, section 2). The quick tier is deterministic (one OpenMP thread, fixed
# lattice seed): the values below are what it measured, and each tolerance only has to absorb
# floating-point differences between compilers and libraries (a 63-step run, not chaotic at
# Re = 100) while staying well inside what a defect moves: 2 mu -> mu in the viscous force takes the
# limited variant's ke_rate_rel_err from 0.17 to 0.34 (issue 15), a 10 % viscosity error moves
# ke_rate by 0.16 (the exact rate is -16 pi^2 / Re = -1.579). Tolerances: 3 % of ke_rate, 0.03 on
# ke_rate_rel_err (0.05 for the two variants whose error is ~0.46), 0.01 on umax_rel_err_end (0.2
# for original, 1.73), 8 % of tv_ratio_max (exactly 0 without a correction).
expect_band tvf_tgv ke_rate "tvf=limited" -1.8483 0.055
expect_band tvf_tgv ke_rate_rel_err "tvf=limited" 0.17045 0.03
expect_band tvf_tgv umax_rel_err_end "tvf=limited" 0.020843 0.01
expect_band tvf_tgv tv_ratio_max "tvf=limited" 0.6447 0.052
expect_band tvf_tgv ke_rate "tvf=smoothing_length" -1.7858 0.054
expect_band tvf_tgv ke_rate_rel_err "tvf=smoothing_length" 0.13085 0.03
expect_band tvf_tgv umax_rel_err_end "tvf=smoothing_length" 0.037256 0.01
expect_band tvf_tgv tv_ratio_max "tvf=smoothing_length" 0.60437 0.048
expect_band tvf_tgv ke_rate "tvf=none" -2.3057 0.069
expect_band tvf_tgv ke_rate_rel_err "tvf=none" 0.46009 0.05
expect_band tvf_tgv umax_rel_err_end "tvf=none" 0.16976 0.01
expect_band tvf_tgv tv_ratio_max "tvf=none" 0.0 0.0
expect_band tvf_tgv ke_rate "tvf=original" -0.83662 0.025
expect_band tvf_tgv ke_rate_rel_err "tvf=original" 0.4702 0.05
expect_band tvf_tgv umax_rel_err_end "tvf=original" 1.73 0.2
expect_band tvf_tgv tv_ratio_max "tvf=original" 4.3903 0.35
# The ordering the study is about, now implied by the bands: the limited correction's transport
# velocity stays below that of Adami's background pressure (0.64 vs 4.39).
render_reports tvf_tgv
echo "tvf quick tier: OK"
