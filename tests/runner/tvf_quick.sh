#!/usr/bin/env bash
# CI check of the transport-velocity study (seed 002, issue 6): the quick tier of
# studies/tvf_tgv.toml runs through the runner into a fresh database (seconds); the metrics the
# issue names are recorded for the four TVF variants; the limited correction's transport velocity
# stays below that of Adami's background pressure in dual-criteria stepping (tvf = original); the full study expands to its 17 jobs; the report renders.
# Usage: tvf_quick.sh RUNNER SOURCE_DIR
set -euo pipefail
RUNNER="$1"
SRC="$2"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
DB="$TMP/tvf.sqlite"
export OMP_NUM_THREADS=1
fail() { echo "FAIL: $*" >&2; exit 1; }

"$RUNNER" "$SRC/studies/tvf_tgv.toml" --dry-run --db "$TMP/dry.sqlite" >"$TMP/dry.txt"
head -1 "$TMP/dry.txt" | grep -q "tvf_tgv: 17 jobs" || fail "tvf_tgv does not expand to 17 jobs"
"$RUNNER" "$SRC/studies/tvf_tgv.toml" --tier quick --db "$DB" -j 2 --progress plain >"$TMP/run.log" 2>&1 ||
  { cat "$TMP/run.log"; fail "tvf_tgv quick tier exited non-zero"; }
q() { "$RUNNER" query --db "$DB" "$1" | tail -n +2; }
[ "$(q "SELECT count(*) FROM jobs WHERE state = 'done'")" = 4 ] || fail "expected 4 done jobs"
for m in ke_rate_rel_err ke_rel_err_end umax_rel_err_end tv_ratio_max sumW_spread_end sumW_rms_end; do
  [ "$(q "SELECT count(*) FROM job_metrics WHERE study = 'tvf_tgv' AND metric = '$m'")" = 4 ] ||
    fail "metric $m missing from a tvf_tgv job"
done
tv() { q "SELECT value FROM job_metrics WHERE study = 'tvf_tgv' AND metric = 'tv_ratio_max' AND json_extract(params, '$.tvf') = '$1'"; }
awk -v a="$(tv limited)" -v b="$(tv original)" 'BEGIN { exit !(a < b) }' ||
  fail "tv_ratio_max(limited) >= tv_ratio_max(original)"
[ "$(tv none)" = 0.0 ] || [ "$(tv none)" = 0 ] || fail "tv_ratio_max(none) is not 0"
"$RUNNER" report "$SRC/studies/tvf_tgv.toml" --db "$DB" --tier quick --out "$TMP/report" >/dev/null ||
  fail "report of tvf_tgv"
echo "tvf quick tier: OK"
