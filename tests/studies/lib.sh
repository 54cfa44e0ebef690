# Shared helpers of the quick-tier study checks (sourced by tests/studies/*.sh). Each check runs a
# study's quick tier through the runner into a fresh database and asserts on `job_metrics`.
# The sourcing script sets RUNNER and SRC (its two arguments) before sourcing this file.
set -euo pipefail
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
DB="$TMP/results.sqlite"
export OMP_NUM_THREADS=1

fail() { echo "FAIL: $*" >&2; exit 1; }

# q SQL: the query's result rows, without the CSV header.
q() { "$RUNNER" query --db "$DB" "$1" | tail -n +2; }

# expect_jobs STUDY TIER N: the study (tier "" for all of it) expands to N jobs.
expect_jobs() {
  local tier=() label="$1"
  if [ -n "$2" ]; then tier=(--tier "$2"); label="$1 [$2]"; fi
  "$RUNNER" "$SRC/studies/$1.toml" "${tier[@]}" --dry-run --db "$TMP/dry.sqlite" >"$TMP/dry.txt"
  head -1 "$TMP/dry.txt" | grep -qF "$label: $3 jobs" || fail "$label does not expand to $3 jobs"
}

# run_quick STUDY...: runs each study's quick tier; a non-zero exit fails with its log.
run_quick() {
  for s in "$@"; do
    "$RUNNER" "$SRC/studies/$s.toml" --tier quick --db "$DB" -j 2 --progress plain >"$TMP/$s.log" 2>&1 ||
      { cat "$TMP/$s.log"; fail "$s quick tier exited non-zero"; }
  done
}

# expect_metric_count STUDY METRIC N [STATUS]: N rows of METRIC for the study's jobs.
expect_metric_count() {
  local where="study = '$1' AND metric = '$2'"
  [ -n "${4:-}" ] && where="$where AND status = '$4'"
  [ "$(q "SELECT count(*) FROM job_metrics WHERE $where")" = "$3" ] ||
    fail "metric $2: expected $3 rows in $1"
}

# render_reports STUDY...: `runner report` of each study's quick tier succeeds.
render_reports() {
  for s in "$@"; do
    "$RUNNER" report "$SRC/studies/$s.toml" --db "$DB" --tier quick --out "$TMP/report_$s" >/dev/null ||
      fail "report of $s"
  done
}

# expect_band STUDY METRIC WHERE VALUE TOL: exactly one done-or-diverged row of METRIC in STUDY
# matches WHERE, and its value lies in VALUE +- TOL. WHERE is "-" (no filter) or space-separated
# key=value pairs on the job's parameters (json_extract(params, '$.key') = value; numbers compare as
# numbers, anything else as a string). A band is the value the quick tier measured with a
# tolerance a real defect exceeds; each call site says where its band comes from.
expect_band() {
  local study="$1" metric="$2" where="$3" value="$4" tol="$5" cond="" kv k v
  if [ "$where" != "-" ]; then
    for kv in $where; do
      k="${kv%%=*}" v="${kv#*=}"
      if [[ "$v" =~ ^-?[0-9.]+([eE][-+]?[0-9]+)?$ ]]; then
        cond="$cond AND json_extract(params, '\$.$k') = $v"
      else
        cond="$cond AND json_extract(params, '\$.$k') = '$v'"
      fi
    done
  fi
  local sel="FROM job_metrics WHERE study = '$study' AND metric = '$metric'$cond"
  local n
  n="$(q "SELECT count(*) $sel")"
  [ "$n" = 1 ] || fail "band $study/$metric [$where]: $n matching rows (expected 1)"
  local got
  got="$(q "SELECT value $sel")"
  awk -v g="$got" -v c="$value" -v t="$tol" 'BEGIN { d = g - c; if (d < 0) d = -d; exit !(d <= t) }' ||
    fail "band $study/$metric [$where]: $got outside $value +- $tol"
  echo "  band ok: $study/$metric [$where] = $got in $value +- $tol"
}
