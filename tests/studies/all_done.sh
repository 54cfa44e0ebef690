#!/usr/bin/env bash
# Runs the quick tier of one study on a fresh database, fails unless every job ends `done` (a
# diverged quick job is a failure here), then renders `runner report`, which checks the study's
# [[figures]] against real jobs and their HDF5 outputs. Usage: all_done.sh RUNNER SOURCE_DIR STUDY
RUNNER="$1" SRC="$2"
source "$(dirname "$0")/lib.sh"

run_quick "$3"
bad=$(q "SELECT count(*) FROM jobs WHERE state <> 'done'")
if [ "$bad" != 0 ]; then
  q "SELECT key, state FROM jobs WHERE state <> 'done'"
  fail "$bad job(s) of $3 did not end done"
fi
# Value bands of this study's quick tier, when it has them (tests/studies/bands_<study>.sh).
if [ -f "$(dirname "$0")/bands_$3.sh" ]; then
  source "$(dirname "$0")/bands_$3.sh"
fi
render_reports "$3"
echo "$3 quick tier: OK"
