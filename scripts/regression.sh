#!/usr/bin/env bash
# Behaviour regression of the solver: runs the quick tier of every study in studies/ (and, with
# --long, the longer jobs of tests/regression/*.toml) through the runner into a fresh database and
# writes every job's physics metrics as CSV (study, job key, status, metric, value to 17 digits),
# sorted, without the cost metrics (wall and CPU times and their ratios vary from run to run).
#
#   scripts/regression.sh capture OUT.csv [--long]   # write the export
#   scripts/regression.sh compare BASE.csv [--long]  # run again and diff against BASE.csv
#
# A refactoring that must not change behaviour brings every baseline row back with the same value
# (exit 0; rows of metrics added since are listed, not failed); a changed or missing row is
# printed and fails (exit 1). The baselines are tests/regression/baseline_quick.csv
# and baseline_long.csv, captured on the code before the scheme-interface redesign (issue 14); the
# long_alsph rows at 94d3e27, the last commit before contact and alsph moved onto the shared loop.
# Needs a Release build in build/ (scripts/build.sh; RUNNER= another binary). STUDIES="a b" limits
# the run to those study files (studies/a.toml, or tests/regression/a.toml with --long; compare
# then checks only the baseline rows of the study names they define).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
RUNNER="${RUNNER:-$ROOT/build/runner}"
mode="${1:-}" file="${2:-}" long="${3:-}"
[[ "$mode" == capture || "$mode" == compare ]] && [[ -n "$file" ]] ||
  { echo "usage: $0 capture|compare FILE.csv [--long]" >&2; exit 2; }

TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
DB="$TMP/regression.sqlite"
export OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive

studies=()
if [[ "$long" == --long ]]; then
  files=("$ROOT"/tests/regression/*.toml)
  tier=()
else
  files=("$ROOT"/studies/*.toml)
  tier=(--tier quick)
fi
for s in "${files[@]}"; do
  if [[ -n "${STUDIES:-}" ]] && ! [[ " $STUDIES " == *" $(basename "$s" .toml) "* ]]; then
    continue
  fi
  [[ "$long" == --long ]] || grep -q '^\[tiers\.quick\]' "$s" && studies+=("$s")
done
for s in "${studies[@]}"; do
  echo "regression: $(basename "$s")" >&2
  "$RUNNER" "$s" "${tier[@]}" --db "$DB" -j "${JOBS:-2}" --progress plain --yes >"$TMP/run.log" 2>&1 ||
    { cat "$TMP/run.log" >&2; echo "regression: $s exited non-zero" >&2; exit 1; }
done

# Cost metrics: anything measured in seconds of a clock (wall, cpu, time per ...), their shares and
# ratios, the per-particle CPU costs, and the patch test's timer repeat count.
cost="(metric LIKE '%wall%' OR metric LIKE '%cpu%' OR metric LIKE 'time\_%' ESCAPE '\\' OR metric LIKE '%\_s' ESCAPE '\\'
       OR metric LIKE '%\_s\_per\_%' ESCAPE '\\' OR metric LIKE '%share%' OR metric LIKE '%over\_iteration%' ESCAPE '\\'
       OR metric LIKE '%\_us\_%' ESCAPE '\\' OR metric = 'laplacian_repeats')"
"$RUNNER" query --db "$DB" \
  "SELECT study, job, status, metric, printf('%.17g', value) AS value FROM job_metrics
   WHERE NOT $cost ORDER BY study, job, metric" >"$TMP/now.csv"

if [[ "$mode" == capture ]]; then
  cp "$TMP/now.csv" "$file"
  echo "regression: $(($(wc -l <"$file") - 1)) metric rows written to $file" >&2
else
  # Every baseline row must come back with the same value; rows of metrics the baseline does not
  # have (a metric added since) are listed but do not fail.
  awk -F, -v only=" ${STUDIES:-} " 'NR == FNR { if (FNR > 1 && (only == "  " || index(only, " " $1 " "))) base[$1 FS $2 FS $3 FS $4] = $5; next }
           FNR > 1 { k = $1 FS $2 FS $3 FS $4; if (k in base) { if (base[k] != $5) print "changed: " k ": " base[k] " -> " $5; delete base[k] } else print "added: " $0 }
           END { for (k in base) print "missing: " k "," base[k] }' "$file" "$TMP/now.csv" | sort >"$TMP/diff.txt"
  rows=$(($(wc -l <"$file") - 1))
  added=$(grep -c '^added: ' "$TMP/diff.txt" || true)
  bad=$(grep -c -v '^added: ' "$TMP/diff.txt" || true)
  { grep '^added: ' "$TMP/diff.txt" || true; } | sed 's/^/regression: /' | head -"${SHOW_ADDED:-20}"
  if ((bad == 0)); then
    echo "regression: identical to $file ($rows metric rows; $added rows of new metrics)"
  else
    grep -v '^added: ' "$TMP/diff.txt"
    echo "regression: DIFFERENT from $file ($bad of $rows rows changed or missing)" >&2
    exit 1
  fi
fi
