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
render_reports alsph_dt alsph_iter alsph_re
echo "alsph quick tiers: OK"
