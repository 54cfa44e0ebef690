#!/usr/bin/env bash
# CI check of the ALSPH studies (seed 004, issue 4): the quick tiers of studies/alsph_dt.toml,
# alsph_iter.toml and alsph_re.toml run through the runner into a fresh database (seconds); the
# too-large time step of alsph_dt is recorded as 'diverged' with t_diverged while the sweep goes
# on (exit 0); the metrics the issue names are in job_metrics; the full alsph_dt grid expands to
# 36 jobs; the reports render. Usage: alsph_quick.sh RUNNER SOURCE_DIR
set -euo pipefail
RUNNER="$1"
SRC="$2"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
DB="$TMP/alsph.sqlite"
export OMP_NUM_THREADS=1
fail() { echo "FAIL: $*" >&2; exit 1; }

"$RUNNER" "$SRC/studies/alsph_dt.toml" --dry-run --db "$TMP/dry.sqlite" | head -1 |
  grep -q "alsph_dt: 36 jobs" || fail "alsph_dt does not expand to 36 jobs"
for s in alsph_dt alsph_iter alsph_re; do
  "$RUNNER" "$SRC/studies/$s.toml" --tier quick --db "$DB" -j 2 --progress plain >"$TMP/$s.log" 2>&1 ||
    { cat "$TMP/$s.log"; fail "$s quick tier exited non-zero"; }
done
q() { "$RUNNER" query --db "$DB" "$1" | tail -n +2; }
[ "$(q "SELECT count(*) FROM jobs WHERE state = 'done'")" = 7 ] || fail "expected 7 done jobs (2 + 3 + 2)"
[ "$(q "SELECT count(*) FROM job_metrics WHERE study = 'alsph_dt' AND status = 'diverged' AND metric = 't_diverged' AND value > 0")" = 2 ] ||
  fail "the two dt_star = 2 jobs must be diverged with t_diverged"
for m in cd_mean cl_rms st_cycles div_mean iterations_mean converged_fraction wall_s iteration_cpu_us_per_particle; do
  [ "$(q "SELECT count(*) FROM job_metrics WHERE status = 'done' AND metric = '$m'")" = 7 ] ||
    fail "metric $m missing from a done job"
done
for s in alsph_dt alsph_iter alsph_re; do
  "$RUNNER" report "$SRC/studies/$s.toml" --db "$DB" --tier quick --out "$TMP/report_$s" >/dev/null ||
    fail "report of $s"
done
echo "alsph quick tiers: OK"
