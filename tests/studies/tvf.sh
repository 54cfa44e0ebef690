#!/usr/bin/env bash
# CI check of the transport-velocity study (seed 002, issue 6): the quick tier of
# studies/tvf_tgv.toml runs through the runner into a fresh database (seconds); the metrics the
# issue names are recorded for the four TVF variants; the limited correction's transport velocity
# stays below that of Adami's background pressure in dual-criteria stepping (tvf = original); the
# full study expands to its 17 jobs; the report renders. Usage: tvf.sh RUNNER SOURCE_DIR
RUNNER="$1" SRC="$2"
source "$(dirname "$0")/lib.sh"

expect_jobs tvf_tgv "" 21
run_quick tvf_tgv
[ "$(q "SELECT count(*) FROM jobs WHERE state = 'done'")" = 4 ] || fail "expected 4 done jobs"
for m in ke_rate_rel_err ke_rel_err_end umax_rel_err_end tv_ratio_max sumW_spread_end sumW_rms_end; do
  expect_metric_count tvf_tgv "$m" 4
done
tv() { q "SELECT value FROM job_metrics WHERE study = 'tvf_tgv' AND metric = 'tv_ratio_max' AND json_extract(params, '$.tvf') = '$1'"; }
awk -v a="$(tv limited)" -v b="$(tv original)" 'BEGIN { exit !(a < b) }' ||
  fail "tv_ratio_max(limited) >= tv_ratio_max(original)"
[ "$(tv none)" = 0.0 ] || [ "$(tv none)" = 0 ] || fail "tv_ratio_max(none) is not 0"
render_reports tvf_tgv
echo "tvf quick tier: OK"
