#!/usr/bin/env bash
# CI check of the transport-velocity cylinder (seed 002 section 4.4, issue 6): the quick tier of
# studies/tvf_cylinder.toml (D/dx = 5, 8 D/U, uniform and with the refinement band; seconds) runs
# into a fresh database and records the force metrics the issue names; the drag is positive with
# its viscous part a fraction of it; the refined box holds fewer particles;
# the full study expands to its 11 jobs; the report renders. Usage: tvf_cylinder.sh RUNNER SRC
RUNNER="$1" SRC="$2"
source "$(dirname "$0")/lib.sh"

expect_jobs tvf_cylinder "" 11
run_quick tvf_cylinder
[ "$(q "SELECT count(*) FROM jobs WHERE state = 'done'")" = 2 ] || fail "expected 2 done jobs"
for m in cd_mean cl_rms cd_viscous_mean cd_amplitude cl_amplitude tv_ratio_max; do
  expect_metric_count tvf_cylinder "$m" 2
done
# m METRIC BAND: the metric of the uniform (0) or the variable-resolution (2) job.
m() { q "SELECT value FROM job_metrics WHERE study = 'tvf_cylinder' AND metric = '$1' AND json_extract(params, '$.refinement_band') = $2"; }
for b in 0 2; do
  awk -v d="$(m cd_mean $b)" -v v="$(m cd_viscous_mean $b)" 'BEGIN { exit !(d > 0.5 && v > 0 && v < d) }' ||
    fail "refinement_band $b: cd_mean $(m cd_mean $b), cd_viscous_mean $(m cd_viscous_mean $b)"
done
# The refined box has fewer particles than the uniform one at the same D/dx.
awk -v a="$(m n_fluid 2)" -v b="$(m n_fluid 0)" 'BEGIN { exit !(a < 0.7 * b) }' ||
  fail "n_fluid: refined $(m n_fluid 2), uniform $(m n_fluid 0)"
render_reports tvf_cylinder
echo "tvf_cylinder quick tier: OK"
