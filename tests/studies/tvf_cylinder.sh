#!/usr/bin/env bash
# CI check of the transport-velocity cylinder (seed 002 section 4.4, issue 6): the quick tier of
# studies/tvf_cylinder.toml (D/dx = 5, 8 D/U; seconds) runs into a fresh database and records the
# force metrics the issue names; the drag is positive with its viscous part a fraction of it;
# the full study expands to its 5 jobs; the report renders. Usage: tvf_cylinder.sh RUNNER SRC
RUNNER="$1" SRC="$2"
source "$(dirname "$0")/lib.sh"

expect_jobs tvf_cylinder "" 5
run_quick tvf_cylinder
[ "$(q "SELECT count(*) FROM jobs WHERE state = 'done'")" = 1 ] || fail "expected 1 done job"
for m in cd_mean cl_rms cd_viscous_mean cd_amplitude cl_amplitude tv_ratio_max; do
  expect_metric_count tvf_cylinder "$m" 1
done
m() { q "SELECT value FROM job_metrics WHERE study = 'tvf_cylinder' AND metric = '$1'"; }
awk -v d="$(m cd_mean)" -v v="$(m cd_viscous_mean)" 'BEGIN { exit !(d > 0.5 && v > 0 && v < d) }' ||
  fail "cd_mean $(m cd_mean), cd_viscous_mean $(m cd_viscous_mean)"
render_reports tvf_cylinder
echo "tvf_cylinder quick tier: OK"
