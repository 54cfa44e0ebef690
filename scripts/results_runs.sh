#!/usr/bin/env bash
# The runs behind the README's result tables (issue 15, section 4), in order of cost, each
# published into docs/results/<study>.csv when it has finished (`runner publish`). Resumable:
# run it again after an interruption and the runner continues where it stopped (finished jobs are
# kept, checkpointed ones resume). tests/docs/readme_results.py checks the README against the
# published files.
#
# Usage: scripts/results_runs.sh [RUNNER] [DB] [STEP...]
#   RUNNER  the runner binary (default build/runner); build it from a clean commit so that the
#           recorded code_version names a commit
#   DB      the database (default results/readme_runs.sqlite)
#   STEP    run only these steps (names below); default: all
# CPU times are those of this project's 2-core machine, one thread per job.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
RUNNER="$(realpath "${1:-$ROOT/build/runner}")"
DB="$(realpath -m "${2:-$ROOT/results/readme_runs.sqlite}")"
shift $(($# > 2 ? 2 : $#))
cd "$ROOT"
mkdir -p "$(dirname "$DB")" docs/results

step() { # NAME STUDY_FILE RUNNER_ARGS...
  local name=$1 file=$2
  shift 2
  if [ ${#STEPS[@]} -gt 0 ] && [[ ! " ${STEPS[*]} " =~ " $name " ]]; then return 0; fi
  echo "== $name: runner $file $*"
  nice -n 10 "$RUNNER" "$file" --db "$DB" --yes "$@"
  "$RUNNER" publish "$(sed -n 's/^name *= *"\(.*\)"/\1/p' "$file" | head -1)" --db "$DB"
}
STEPS=("$@")

step visc_patch studies/visc_patch.toml                            # 120 jobs, 20 s
step tvf_tgv studies/tvf_tgv.toml                                  # 21 jobs, ~20 min
step isph_re100 studies/isph_cavity_re100.toml                     # ~10 min
step alsph_re100 studies/alsph_re.toml --tier validate             # 1 job, ~20 min
step cavity3d_re100 studies/cavity3d.toml --tier re100             # 4 jobs, ~62 min
step cavity3d_re1000 studies/cavity3d.toml --tier machine --where Re=1000 # 2 jobs, ~15 min
step tvf_cylinder studies/tvf_cylinder.toml --where D_over_dx=20 --where domain_height=16 \
  --where refinement_band=0                                        # 1 job, ~42 min
step tvf_cavity_re100 studies/tvf_cavity.toml --tier re100             # 3 jobs, ~1.3 h (seed 002's own cavity)
# Contact SPH (seed 003): the README's table quotes these tiers (CPU times from docs/contact.md)
step contact_zeta studies/godunov_zeta.toml --tier paper           # 8 jobs, ~15 min
step contact_cylinders studies/godunov_cylinders.toml --tier smallest # 6 jobs, ~6 min
step contact_alpha2d studies/godunov_eta_num.toml --tier alpha2d   # 16 jobs, minutes
step contact_eta_num studies/godunov_eta_num.toml --tier paper     # 46 jobs, ~2-3 h (alpha = 1 3D: 28x a lead run)
step cantilever studies/cantilever.toml                            # 9 jobs, ~3 min (docs/solid.md)
step cantilever_fine studies/cantilever.toml --tier fine           # 1 more job, ~3 min
step fsi_beam studies/fsi_beam.toml                                # 2 jobs, ~25 min (docs/fsi.md)
step alsph_small studies/alsph_dt.toml --tier small                # 8 jobs, ~3 h
# ISPH at Re = 1000, the README's five rows: 7, 11, 11, 40 and 74 CPU-min (dx = 0.005: 5-6 h, not run)
for job in "visc04 0.025" "visc04 0.02" "visc03 0.02" "visc04 0.0125" "visc04 0.01"; do
  set -- $job
  step isph_re1000 studies/isph_cavity.toml --where visc=$1 --where dx=$2
done
