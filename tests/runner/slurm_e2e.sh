#!/usr/bin/env bash
# End-to-end test of `runner submit --slurm` on a real single-node Slurm cluster started by
# scripts/slurm/start_local_cluster.sh: a small patch_test study runs as a job array, its results
# are ingested and must equal a local run of the same study; failed jobs are resubmitted alone;
# a cancelled array's unfinished jobs come back as pending and are resubmitted alone; a
# checkpointed job cancelled on Slurm resumes from its checkpoint and equals a local run.
# Usage: slurm_e2e.sh RUNNER_EXE SOURCE_DIR. Exit 77 (skipped) when not root or Slurm is missing.
set -euo pipefail
RUNNER=$1
SRC=$2
if [[ $(id -u) -ne 0 ]]; then
  echo "SKIPPED: the Slurm test starts a local cluster and must run as root"
  exit 77
fi
for b in sbatch squeue scancel slurmctld slurmd munged; do
  if ! command -v "$b" >/dev/null; then
    echo "SKIPPED: $b not found (scripts/install_deps.sh --with-slurm installs slurm-wlm and munge)"
    exit 77
  fi
done
# A cluster this test starts is stopped when it ends (pass or fail); one already running (started
# by hand with scripts/slurm/start_local_cluster.sh) is left as it was.
daemons_before=$(for d in slurmctld slurmd munged; do pgrep -x "$d" || true; done | wc -l)
DIR=$(mktemp -d /tmp/sph_slurm_e2e.XXXXXX)
cleanup() {
  rm -rf "$DIR"
  if [[ $daemons_before == 0 ]]; then "$SRC/scripts/slurm/start_local_cluster.sh" --stop; fi
}
trap cleanup EXIT
t0=$(date +%s)
"$SRC/scripts/slurm/start_local_cluster.sh"
echo "cluster ready in $(($(date +%s) - t0)) s"

cd "$DIR"
cat > s.toml <<'TOML'
[study]
name = "slurm_e2e"
case = "patch_test"
[sweep]
visc = ["visc01", "visc03"]
n_side = [8, 10, 12]
TOML
fail() { echo "FAIL: $*"; exit 1; }
q() { "$RUNNER" query --db "$1" "$2" | tail -n +2; }
# Every metric but the timings (laplacian_cpu_s, and laplacian_repeats, which the case picks to
# fill 50 ms of CPU time) must be equal.
metrics() {
  q "$1" "SELECT job, metric, value FROM job_metrics WHERE metric NOT IN ('laplacian_cpu_s', 'laplacian_repeats') ORDER BY job, metric"
}

# 1. The reference: a local run.
"$RUNNER" s.toml --db local/results.sqlite -j 2 >local.log 2>&1 || { cat local.log; fail "local run"; }

# 2. Through Slurm, with one job made to crash: 6 jobs, 2 per array task, at most 2 tasks at once.
SPH_RUNNER_FAULT=segv SPH_RUNNER_FAULT_MATCH=n_side=10 timeout 300 \
  "$RUNNER" submit s.toml --slurm --jobs-per-task 2 --array-limit 2 --wait \
  --db slurm/results.sqlite | tee submit1.log || true
grep -q "submitted 6 jobs as Slurm array" submit1.log || fail "first submission"
[[ $(q slurm/results.sqlite "SELECT count(*) FROM jobs WHERE state='done'") == 4 ]] || fail "4 done"
[[ $(q slurm/results.sqlite "SELECT count(*) FROM jobs WHERE state='failed'") == 2 ]] || fail "2 failed"
[[ $(q slurm/results.sqlite "SELECT count(*) FROM attempts WHERE failure_class='signal' AND error_text LIKE '%SIGSEGV%'") == 2 ]] \
  || fail "crash classified as signal"
# Every attempt records the Slurm array task that ran it, and the host.
[[ $(q slurm/results.sqlite "SELECT count(*) FROM attempts WHERE slurm_job_id GLOB '[0-9]*_[0-9]*' AND host != 'slurm'") == 6 ]] \
  || fail "slurm ids recorded"
"$RUNNER" status slurm_e2e --db slurm/results.sqlite

# 3. Resubmission of only the failed jobs.
timeout 300 "$RUNNER" submit s.toml --slurm --retry-failed --wait --db slurm/results.sqlite | tee submit2.log
grep -q "submitted 2 jobs" submit2.log || fail "only the 2 failed jobs are resubmitted"
[[ $(q slurm/results.sqlite "SELECT count(*) FROM jobs WHERE state='done'") == 6 ]] || fail "6 done"
[[ $(q slurm/results.sqlite "SELECT count(*) FROM attempts WHERE state='done'") == 6 ]] || fail "one done attempt per job"

# 4. The results equal the local run's, bit for bit (shortest round-trip reals).
diff <(metrics local/results.sqlite) <(metrics slurm/results.sqlite) || fail "Slurm metrics differ from the local run"
[[ $(metrics slurm/results.sqlite | grep -c ',err,') == 6 ]] || fail "no err metric"
echo "metrics of the Slurm run equal the local run's: $(metrics slurm/results.sqlite | wc -l) values"

# 5. A cancelled array: the jobs it did not finish go back to pending and only they are resubmitted.
sed -i 's/n_side = \[8, 10, 12\]/n_side = [8, 10, 12, 14]/' s.toml
SPH_RUNNER_FAULT=hang SPH_RUNNER_FAULT_MATCH=n_side=14 \
  "$RUNNER" submit s.toml --slurm --db slurm/results.sqlite | tee submit3.log
array=$(sed -n 's/.*as Slurm array \([0-9]*\).*/\1/p' submit3.log)
[[ -n "$array" ]] || fail "third submission"
[[ $(q slurm/results.sqlite "SELECT count(*) FROM jobs WHERE state='submitted'") == 2 ]] || fail "2 submitted"
"$RUNNER" status slurm_e2e --db slurm/results.sqlite | tee status.log
grep -q "submitted to Slurm" status.log || fail "status shows submitted jobs"
# Wait until both jobs are running (hanging), then cancel the array.
for _ in $(seq 100); do
  [[ $(squeue -h -r -j "$array" -t R | wc -l) -ge 1 ]] && break
  sleep 0.2
done
sleep 1
scancel "$array"
for _ in $(seq 100); do
  [[ -z "$(squeue -h -r -j "$array" 2>/dev/null)" ]] && break
  sleep 0.2
done
"$RUNNER" ingest --db slurm/results.sqlite | tee ingest.log
[[ $(q slurm/results.sqlite "SELECT count(*) FROM jobs WHERE state='pending'") == 2 ]] || fail "cancelled jobs pending again"
[[ $(q slurm/results.sqlite "SELECT count(*) FROM attempts WHERE failure_class='stale'") -ge 2 ]] || fail "lost attempts kept as stale"
timeout 300 "$RUNNER" submit s.toml --slurm --wait --db slurm/results.sqlite | tee submit4.log
grep -q "submitted 2 jobs" submit4.log || fail "only the 2 unfinished jobs are resubmitted"
[[ $(q slurm/results.sqlite "SELECT count(*) FROM jobs WHERE state='done'") == 8 ]] || fail "8 done"
[[ $(q slurm/results.sqlite "SELECT count(*) FROM attempts WHERE state='done'") == 8 ]] || fail "one done attempt per job"

# 6. A long job cancelled mid-way on Slurm resumes from its checkpoint (kept in the shared Slurm
#    directory) when resubmitted, and its result equals an uninterrupted local run's, bit for bit.
#    step_sleep_us (40 ms per step on Slurm) is not part of the job key: both runs are one job.
cat > ck.toml <<'TOML'
[study]
name = "slurm_ckpt"
case = "checkpoint_demo"
[params]
steps = 200
step_sleep_us = 20000
TOML
sed 's/step_sleep_us = 20000/step_sleep_us = 0/' ck.toml > ck_fast.toml
"$RUNNER" ck_fast.toml --db local/results.sqlite >>local.log 2>&1 || { cat local.log; fail "local checkpoint run"; }
"$RUNNER" submit ck.toml --slurm --checkpoint-every-steps 20 --db slurm/results.sqlite | tee submit5.log
array=$(sed -n 's/.*as Slurm array \([0-9]*\).*/\1/p' submit5.log)
[[ -n "$array" ]] || fail "checkpoint submission"
key=$(q slurm/results.sqlite "SELECT key FROM jobs WHERE case_name='checkpoint_demo'")
ckpt=slurm/slurm/outputs/slurm_ckpt/$key/checkpoint.h5
# Up to 60 s: on a loaded CI machine Slurm may start the task late.
for _ in $(seq 600); do [[ -f $ckpt ]] && break; sleep 0.1; done
[[ -f $ckpt ]] || fail "no checkpoint in the shared directory ($ckpt)"
scancel "$array"
for _ in $(seq 100); do
  [[ -z "$(squeue -h -r -j "$array" 2>/dev/null)" ]] && break
  sleep 0.2
done
"$RUNNER" ingest --db slurm/results.sqlite
[[ $(q slurm/results.sqlite "SELECT state FROM jobs WHERE key='$key'") == pending ]] || fail "cancelled job pending again"
timeout 300 "$RUNNER" submit ck.toml --slurm --checkpoint-every-steps 20 --wait --db slurm/results.sqlite | tee submit6.log
[[ $(q slurm/results.sqlite "SELECT count(*) FROM attempts a JOIN jobs j ON j.id=a.job_id WHERE j.key='$key' AND a.state='done' AND a.attempt=2 AND a.message LIKE 'resumed from step %'") == 1 ]] \
  || { q slurm/results.sqlite "SELECT attempt, state, message, error_text FROM attempts a JOIN jobs j ON j.id=a.job_id WHERE j.key='$key'"; fail "resumed from the checkpoint"; }
ckm() { q "$1" "SELECT metric, value FROM job_metrics WHERE study='slurm_ckpt' ORDER BY metric"; }
diff <(ckm local/results.sqlite) <(ckm slurm/results.sqlite) || fail "resumed Slurm job differs from the uninterrupted local run"
[[ $(ckm slurm/results.sqlite | wc -l) == 5 ]] || fail "checkpoint_demo metrics"
echo "checkpointed job cancelled on Slurm, resumed ($(q slurm/results.sqlite "SELECT message FROM attempts WHERE state='done' AND message LIKE 'resumed%'")): metrics equal the local run's"

[[ $(q slurm/results.sqlite "PRAGMA integrity_check") == ok ]] || fail "integrity"
echo "PASS: Slurm end to end in $(($(date +%s) - t0)) s"
