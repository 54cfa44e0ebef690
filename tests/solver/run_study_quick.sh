#!/bin/sh
# Runs the quick tier of a study on a fresh database, fails unless every job ends `done` (a
# diverged quick job is a failure here), then renders `runner report`, which checks the study's
# [[figures]] against real jobs and their HDF5 outputs.
# usage: run_study_quick.sh RUNNER STUDY.toml WORK_DIR
set -eu
runner=$1 study=$2 dir=$3
rm -rf "$dir"
mkdir -p "$dir"
"$runner" run "$study" --tier quick --db "$dir/results.sqlite" -j 1 --threads-per-job 1 --progress plain
bad=$("$runner" query "SELECT count(*) FROM jobs WHERE state <> 'done'" --db "$dir/results.sqlite" | tail -n 1)
if [ "$bad" != 0 ]; then
  echo "$bad job(s) of $study did not end done:"
  "$runner" query "SELECT key, state FROM jobs WHERE state <> 'done'" --db "$dir/results.sqlite"
  exit 1
fi
"$runner" report "$study" --db "$dir/results.sqlite" --tier quick --out "$dir/report"
