#!/usr/bin/env bash
# CI check of the ALSPH studies (seed 004, issue 4): the quick tiers of studies/alsph_dt.toml,
# alsph_iter.toml and alsph_re.toml run through the runner into a fresh database (seconds); the
# too-large time step of alsph_dt is recorded as 'diverged' with t_diverged while the sweep goes
# on (exit 0); the metrics the issue names are in job_metrics; the full alsph_dt grid expands to
# 36 jobs; the reports render. Usage: alsph.sh RUNNER SOURCE_DIR
RUNNER="$1" SRC="$2"
source "$(dirname "$0")/lib.sh"

expect_jobs alsph_dt "" 36
run_quick alsph_dt alsph_iter alsph_re
[ "$(q "SELECT count(*) FROM jobs WHERE state = 'done'")" = 7 ] || fail "expected 7 done jobs (2 + 3 + 2)"
[ "$(q "SELECT count(*) FROM job_metrics WHERE study = 'alsph_dt' AND status = 'diverged' AND metric = 't_diverged' AND value > 0")" = 2 ] ||
  fail "the two dt_star = 2 jobs must be diverged with t_diverged"
for m in cd_mean cl_rms st_cycles div_mean iterations_mean converged_fraction wall_s iteration_cpu_us_per_particle; do
  [ "$(q "SELECT count(*) FROM job_metrics WHERE status = 'done' AND metric = '$m'")" = 7 ] ||
    fail "metric $m missing from a done job"
done
# Value bands (issue 15, section 2): the values the quick tier measured (deterministic: one
# OpenMP thread) with tolerances for floating-point differences between builds that a defect
# exceeds: cd_mean 5 % (the short impulsive-start runs, t_end 0.3-0.5, end inside the start-up
# transient; the force integration, the penalty r_AL or the iteration count move it by more: 1.57 ->
# 2.94 with 2 instead of 5 updates), div_mean and cl_rms 10 %; t_diverged is the first step's time
# (dt_star = 2 diverges at once).
expect_band alsph_dt cd_mean "algorithm=1 dt_star=0.0254" 2.3856 0.12
expect_band alsph_dt div_mean "algorithm=1 dt_star=0.0254" 0.018242 0.0018
expect_band alsph_dt t_diverged "algorithm=1 dt_star=2.0" 0.333333333 1e-6
expect_band alsph_dt cd_mean "algorithm=2 dt_star=0.0254" 2.4073 0.12
expect_band alsph_dt div_mean "algorithm=2 dt_star=0.0254" 0.01822 0.0018
expect_band alsph_dt t_diverged "algorithm=2 dt_star=2.0" 0.333333333 1e-6
expect_band alsph_iter cd_mean "max_iterations=2" 2.9389 0.15
expect_band alsph_iter div_mean "max_iterations=2" 0.039741 0.004
expect_band alsph_iter cd_mean "max_iterations=5" 1.5717 0.079
expect_band alsph_iter div_mean "max_iterations=5" 0.023269 0.0023
expect_band alsph_iter cd_mean "max_iterations=20" 1.8194 0.091
expect_band alsph_iter div_mean "max_iterations=20" 0.013072 0.0013
expect_band alsph_re cd_mean "Re=100.0" 1.7646 0.088
expect_band alsph_re cl_rms "Re=100.0" 0.30701 0.031
expect_band alsph_re cd_mean "Re=300.0" 1.5054 0.075
expect_band alsph_re cl_rms "Re=300.0" 0.31525 0.032
render_reports alsph_dt alsph_iter alsph_re
echo "alsph quick tiers: OK"
