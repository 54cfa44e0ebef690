#!/usr/bin/env bash
# Mutation harness (issue 15, section 3): proves the test suite fails when the numerics are wrong.
#
# For each mutation of scripts/mutations.txt (one per line: ID @@ FILE @@ SEARCH @@ REPLACE, SEARCH
# an exact string that must occur exactly once in FILE; lines starting with # are comments), on a
# scratch copy of the repository: apply it, rebuild incrementally, run ctest, restore the file.
# A mutation is
#   caught          some test failed (the first failing test is printed),
#   MISSED          the build succeeded and every test passed,
#   not applicable  SEARCH does not occur exactly once in FILE (the code moved or changed: update
#                   the list; never counted as caught),
#   build error     the mutated code does not compile (not counted as caught: fix the mutation).
# The unmutated baseline must build and pass first.
#
# Usage: scripts/mutate.sh [-R CTEST_REGEX] [-E CTEST_EXCLUDE] [-m ID_REGEX] [-j JOBS] [-S]
#                          [-d SCRATCH_DIR] [-l LIST] [-o RESULT_TABLE]
#   -R / -E   ctest -R / -E subset of the suite (default: the whole suite)
#   -m        only the mutations whose ID matches this extended regex
#   -j        build and ctest parallelism (default 2)
#   -d        scratch directory (default /tmp/sph-mutate); reused, so reruns build incrementally
#   -o        Markdown result table (default SCRATCH_DIR/result.md)
#   -B        skip the baseline ctest run (only right after a run on the same tree passed it)
#   -S        build only the runner and the tests/solver executables (with -E excluding the
#             runner's own tests, which then are not rebuilt: faster)
# It takes long (one incremental build and one suite run per mutation): run it outside CI, e.g.
#   nohup scripts/mutate.sh > /tmp/mutate.log 2>&1 &
set -uo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SKIP_BASELINE=0 SOLVER_ONLY=0 REGEX="" EXCLUDE="" ONLY="" JOBS=2 SCRATCH=/tmp/sph-mutate LIST="$ROOT/scripts/mutations.txt" OUT=""
while getopts "R:E:m:j:d:l:o:SB" opt; do
  case $opt in
  R) REGEX="$OPTARG" ;;
  E) EXCLUDE="$OPTARG" ;;
  m) ONLY="$OPTARG" ;;
  j) JOBS="$OPTARG" ;;
  d) SCRATCH="$OPTARG" ;;
  l) LIST="$OPTARG" ;;
  o) OUT="$OPTARG" ;;
  S) SOLVER_ONLY=1 ;;
  B) SKIP_BASELINE=1 ;;
  *) sed -n '2,25p' "$0"; exit 2 ;;
  esac
done
OUT="${OUT:-$SCRATCH/result.md}"
SRC="$SCRATCH/src" BUILD="$SCRATCH/src/build"
mkdir -p "$SRC"
# Copy the working tree (not .git, not build dirs) into the scratch copy, writing only the files
# that differ so the scratch build stays incremental (scripts/sync_tree.py).
python3 "$ROOT/scripts/sync_tree.py" "$ROOT" "$SRC" || exit 1

CTEST_ARGS=(--timeout 600 -j"$JOBS" --stop-on-failure)

TARGETS=()
if [ "$SOLVER_ONLY" = 1 ]; then
  # The runner's test executables are not built: leave out ctest's placeholders for them.
  EXCLUDE="${EXCLUDE:+$EXCLUDE|}_NOT_BUILT\$"
  TARGETS=(--target runner $(sed -n 's/^sph_unit_test(\([A-Za-z0-9_]*\).*/\1/p' "$SRC/tests/solver/CMakeLists.txt"))
fi
build() { cmake --build "$BUILD" -j"$JOBS" "${TARGETS[@]}" >"$SCRATCH/build.log" 2>&1; }
# Without -R, two phases: everything but the study scripts first (seconds), then the study quick
# tiers; ctest stops at the first failure, so a caught mutation usually costs only the first phase.
run_tests() {
  local ex="${EXCLUDE:+$EXCLUDE|}^study_"
  if [ -n "$REGEX" ]; then
    (cd "$BUILD" && ctest "${CTEST_ARGS[@]}" -R "$REGEX" ${EXCLUDE:+-E "$EXCLUDE"} >"$SCRATCH/ctest.log" 2>&1)
  else
    (cd "$BUILD" && ctest "${CTEST_ARGS[@]}" -E "$ex" >"$SCRATCH/ctest.log" 2>&1) &&
      (cd "$BUILD" && ctest "${CTEST_ARGS[@]}" -R '^study_' >"$SCRATCH/ctest.log" 2>&1)
  fi
}
first_failure() {
  # ctest prints "The following tests FAILED:" then "  <n> - <name> (Failed)"
  sed -n '/The following tests FAILED/,$p' "$SCRATCH/ctest.log" | sed -n '2p' |
    sed -E 's/^[[:space:]]*[0-9]+ - ([^ ]+).*/\1/'
}

echo "== baseline: configure, build and test the unmutated copy in $SRC"
cmake -S "$SRC" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release >"$SCRATCH/configure.log" 2>&1 ||
  { cat "$SCRATCH/configure.log"; exit 1; }
build || { tail -30 "$SCRATCH/build.log"; echo "baseline build failed"; exit 1; }
if [ "$SKIP_BASELINE" = 1 ]; then
  echo "baseline tests skipped (-B)"
else
  run_tests || { tail -30 "$SCRATCH/ctest.log"; echo "baseline tests fail: fix them first"; exit 1; }
  echo "baseline passes"
fi

{
  echo "| mutation | file | result | caught by (first failing test) |"
  echo "|---|---|---|---|"
} >"$OUT"
n_caught=0 n_missed=0 n_na=0 n_err=0
while IFS= read -r line || [ -n "$line" ]; do
  [[ -z "${line// /}" || "$line" =~ ^[[:space:]]*# ]] && continue
  id="$(awk -F ' @@ ' '{print $1}' <<<"$line")"
  file="$(awk -F ' @@ ' '{print $2}' <<<"$line")"
  [ -n "$ONLY" ] && ! [[ "$id" =~ $ONLY ]] && continue
  t0=$(date +%s)
  cp "$SRC/$file" "$SCRATCH/orig" 2>/dev/null || { echo "?" >"$SCRATCH/orig"; }
  status=$(MUT_LINE="$line" MUT_FILE="$SRC/$file" python3 - <<'PY'
import os, sys
parts = os.environ["MUT_LINE"].split(" @@ ")
if len(parts) != 4:
    print("bad line"); sys.exit()
_, _, search, replace = parts
path = os.environ["MUT_FILE"]
try:
    text = open(path).read()
except OSError:
    print("not applicable (no file)"); sys.exit()
n = text.count(search)
if n != 1:
    print(f"not applicable (found {n} times)"); sys.exit()
open(path, "w").write(text.replace(search, replace))
print("applied")
PY
)
  who=""
  if [ "$status" = applied ]; then
    if ! build; then
      result="build error"; n_err=$((n_err + 1))
    elif run_tests; then
      result="MISSED"; n_missed=$((n_missed + 1))
    else
      result="caught"; who="$(first_failure)"; n_caught=$((n_caught + 1))
    fi
    cp "$SCRATCH/orig" "$SRC/$file"
  else
    result="$status"; n_na=$((n_na + 1))
  fi
  printf '%-34s %-16s %s (%ds)\n' "$id" "$result" "$who" $(($(date +%s) - t0))
  echo "| $id | $file | $result | $who |" >>"$OUT"
done <"$LIST"
build >/dev/null 2>&1 # leave the scratch build unmutated
echo "== caught $n_caught, missed $n_missed, not applicable $n_na, build errors $n_err"
echo "result table: $OUT"
[ $n_missed -eq 0 ] && [ $n_na -eq 0 ] && [ $n_err -eq 0 ]
