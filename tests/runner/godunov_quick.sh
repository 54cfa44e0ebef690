#!/usr/bin/env bash
# CI check of the contact-SPH studies (seed 003, issue 5): the quick tiers of
# studies/godunov_eta_num.toml, godunov_zeta.toml and godunov_cylinders.toml run through the
# runner into a fresh database (seconds); the metrics the issue names are recorded; the correction
# lowers profile_err (shear layer) and the drag K (cylinder array); the paper tiers expand to
# their job counts; the reports render. Usage: godunov_quick.sh RUNNER SOURCE_DIR
set -euo pipefail
RUNNER="$1"
SRC="$2"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
DB="$TMP/godunov.sqlite"
export OMP_NUM_THREADS=1
fail() { echo "FAIL: $*" >&2; exit 1; }

for spec in "godunov_eta_num 46" "godunov_zeta 8" "godunov_cylinders 14"; do
  set -- $spec
  "$RUNNER" "$SRC/studies/$1.toml" --tier paper --dry-run --db "$TMP/dry.sqlite" >"$TMP/dry.txt"
  head -1 "$TMP/dry.txt" | grep -q "$1 \[paper\]: $2 jobs" || fail "$1 paper tier does not expand to $2 jobs"
done
for s in godunov_eta_num godunov_zeta godunov_cylinders; do
  "$RUNNER" "$SRC/studies/$s.toml" --tier quick --db "$DB" -j 2 --progress plain >"$TMP/$s.log" 2>&1 ||
    { cat "$TMP/$s.log"; fail "$s quick tier exited non-zero"; }
done
q() { "$RUNNER" query --db "$DB" "$1" | tail -n +2; }
[ "$(q "SELECT count(*) FROM jobs WHERE state = 'done'")" = 8 ] || fail "expected 8 done jobs (3 + 3 + 2)"
for m in eta_fit eta_fit_spread profile_err; do
  [ "$(q "SELECT count(*) FROM job_metrics WHERE study = 'godunov_eta_num' AND metric = '$m'")" = 3 ] ||
    fail "metric $m missing from a godunov_eta_num job"
done
for m in K CD CD_eq39 CD_ratio U_drift drag_balance wall_s; do
  [ "$(q "SELECT count(*) FROM job_metrics WHERE study = 'godunov_cylinders' AND metric = '$m'")" = 2 ] ||
    fail "metric $m missing from a godunov_cylinders job"
done
# The correction removes numerical viscosity: lower profile_err for lead, lower drag K.
lead() { q "SELECT value FROM job_metrics WHERE study = 'godunov_zeta' AND metric = 'profile_err' AND json_extract(params, '$.material_left') = '' AND json_extract(params, '$.zeta') = $1"; }
awk -v a="$(lead 1.0)" -v b="$(lead 0.0)" 'BEGIN { exit !(a < b) }' || fail "profile_err(zeta = 1) >= profile_err(zeta = 0)"
cyl() { q "SELECT value FROM job_metrics WHERE study = 'godunov_cylinders' AND metric = 'K' AND json_extract(params, '$.zeta') = $1"; }
awk -v a="$(cyl 1.0)" -v b="$(cyl 0.0)" 'BEGIN { exit !(a < b) }' || fail "K(zeta = 1) >= K(zeta = 0)"
for s in godunov_eta_num godunov_zeta godunov_cylinders; do
  "$RUNNER" report "$SRC/studies/$s.toml" --db "$DB" --tier quick --out "$TMP/report_$s" >/dev/null ||
    fail "report of $s"
done
echo "godunov quick tiers: OK"
