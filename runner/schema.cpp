// The SQL schema of the job store. Documented in docs/runner.md; the view job_metrics is a stable
// interface that users' scripts rely on (its column names never change).
#include "schema.hpp"

namespace sph::runner {

namespace {

// Version 1: studies, jobs, study membership, attempts, metrics, the job_metrics view.
const char* schema_v1 = R"SQL(
CREATE TABLE studies (
  id                INTEGER PRIMARY KEY,
  name              TEXT NOT NULL UNIQUE,
  case_name         TEXT NOT NULL,
  description       TEXT NOT NULL DEFAULT '',
  file              TEXT NOT NULL,
  definition_sha256 TEXT NOT NULL,
  created_at        REAL NOT NULL,
  updated_at        REAL NOT NULL
);

CREATE TABLE jobs (
  id               INTEGER PRIMARY KEY,
  key              TEXT NOT NULL UNIQUE,
  case_name        TEXT NOT NULL,
  scheme           TEXT NOT NULL DEFAULT '',
  numerics_version INTEGER NOT NULL,
  params_json      TEXT NOT NULL,
  state            TEXT NOT NULL DEFAULT 'pending'
                   CHECK (state IN ('pending','submitted','running','done','failed','diverged','timeout')),
  attempts         INTEGER NOT NULL DEFAULT 0,
  created_at       REAL NOT NULL,
  updated_at       REAL NOT NULL,
  owner_host       TEXT,
  owner_pid        INTEGER,
  heartbeat_at     REAL,
  slurm_job_id     TEXT,
  progress         REAL,
  output_dir       TEXT
);
CREATE INDEX jobs_state ON jobs(state);

CREATE TABLE study_jobs (
  study_id INTEGER NOT NULL REFERENCES studies(id) ON DELETE CASCADE,
  job_id   INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
  tier     TEXT NOT NULL,
  ordinal  INTEGER NOT NULL,
  PRIMARY KEY (study_id, job_id, tier)
) WITHOUT ROWID;
CREATE INDEX study_jobs_job ON study_jobs(job_id);
CREATE INDEX study_jobs_order ON study_jobs(study_id, tier, ordinal);

CREATE TABLE attempts (
  id           INTEGER PRIMARY KEY,
  job_id       INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
  attempt      INTEGER NOT NULL,
  state        TEXT NOT NULL
               CHECK (state IN ('running','done','failed','diverged','timeout','interrupted','abandoned')),
  started_at   REAL NOT NULL,
  finished_at  REAL,
  wall_s       REAL,
  cpu_s        REAL,
  peak_rss_kb  INTEGER,
  host         TEXT NOT NULL,
  pid          INTEGER NOT NULL,
  child_pid    INTEGER,
  threads      INTEGER NOT NULL,
  code_version TEXT NOT NULL,
  compiler     TEXT NOT NULL,
  exit_code    INTEGER,
  signal       INTEGER,
  message      TEXT,
  error_text   TEXT,
  UNIQUE (job_id, attempt)
);
CREATE INDEX attempts_finished ON attempts(finished_at);

CREATE TABLE metrics (
  job_id  INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
  name    TEXT NOT NULL,
  value   REAL,
  attempt INTEGER NOT NULL,
  ordinal INTEGER NOT NULL,
  PRIMARY KEY (job_id, name)
) WITHOUT ROWID;
CREATE INDEX metrics_name ON metrics(name);

CREATE VIEW job_metrics AS
  SELECT s.name        AS study,
         j.key         AS job,
         j.state       AS status,
         j.params_json AS params,
         m.name        AS metric,
         m.value       AS value
  FROM studies s
  JOIN (SELECT DISTINCT study_id, job_id FROM study_jobs) sj ON sj.study_id = s.id
  JOIN jobs j ON j.id = sj.job_id
  JOIN metrics m ON m.job_id = j.id;
)SQL";

// Version 2:
// - attempts.failure_class: why an attempt did not finish (exit, signal, timeout, exception,
//   stale, interrupted, spawn, ingest); NULL for done and diverged attempts.
// - attempts.slurm_job_id: the Slurm job (array task) that ran the attempt.
// - study_jobs.current: 1 for jobs in the study's latest expansion; 0 for jobs an earlier version
//   of the study file had (kept, so their results stay queryable by study name).
// - job_params(job_id, name, value): the identity parameters of each job, one row each, indexed
//   by (name, value) so that filters on parameters are index look-ups, not JSON scans.
const char* schema_v2 = R"SQL(
ALTER TABLE attempts ADD COLUMN failure_class TEXT;
ALTER TABLE attempts ADD COLUMN slurm_job_id TEXT;
ALTER TABLE study_jobs ADD COLUMN current INTEGER NOT NULL DEFAULT 1;
UPDATE attempts SET failure_class = CASE
    WHEN state = 'timeout' THEN 'timeout'
    WHEN state = 'abandoned' THEN 'stale'
    WHEN state = 'interrupted' THEN 'interrupted'
    WHEN state = 'failed' AND signal IS NOT NULL THEN 'signal'
    WHEN state = 'failed' AND error_text LIKE 'exception:%' THEN 'exception'
    WHEN state = 'failed' THEN 'exit'
  END;

CREATE TABLE job_params (
  job_id INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
  name   TEXT NOT NULL,
  value,
  PRIMARY KEY (job_id, name)
) WITHOUT ROWID;
CREATE INDEX job_params_lookup ON job_params(name, value, job_id);
INSERT INTO job_params(job_id, name, value)
  SELECT j.id, p.key, p.value FROM jobs j, json_each(j.params_json) p;

CREATE TABLE slurm_submissions (
  id           INTEGER PRIMARY KEY,
  study_id     INTEGER NOT NULL REFERENCES studies(id) ON DELETE CASCADE,
  tier         TEXT NOT NULL,
  slurm_job_id TEXT,
  manifest     TEXT NOT NULL,
  dir          TEXT NOT NULL,
  n_jobs       INTEGER NOT NULL,
  n_tasks      INTEGER NOT NULL,
  submitted_at REAL NOT NULL
);
)SQL";

// Version 3: attempts indexed by state (then time), so that `runner status` finds the last
// failed attempts among 100,000 done ones without reading them all.
const char* schema_v3 = R"SQL(
CREATE INDEX attempts_state ON attempts(state, finished_at);
)SQL";

// Version 4: the database carries PRAGMA application_id 'SPHR' (set by Store::migrate), and
// attempts.solver_fingerprint records the solver code that ran each attempt (a hash of solver/
// at build time; NULL for attempts recorded before): a done job whose fingerprint differs from
// the running build's is stale (docs/runner.md, "Stale results").
const char* schema_v4 = R"SQL(
ALTER TABLE attempts ADD COLUMN solver_fingerprint TEXT;
)SQL";

// Version 5: attempts.predicted_cpu_s, the cost model's estimate of the attempt's CPU time when
// it was claimed (runner/cost.hpp), beside its measured cpu_s; NULL without an estimate.
const char* schema_v5 = R"SQL(
ALTER TABLE attempts ADD COLUMN predicted_cpu_s REAL;
)SQL";

// Version 6: attempt_metrics keeps the metrics of every finished attempt (metrics holds those of
// the job's result: a recomputation that fails or diverges leaves a done result in place), with
// the view job_attempt_metrics over it. Filled from metrics (earlier attempts' were not kept).
const char* schema_v6 = R"SQL(
CREATE TABLE attempt_metrics (
  job_id  INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
  attempt INTEGER NOT NULL,
  name    TEXT NOT NULL,
  value   REAL,
  ordinal INTEGER NOT NULL,
  PRIMARY KEY (job_id, attempt, name)
) WITHOUT ROWID;
INSERT OR IGNORE INTO attempt_metrics(job_id, attempt, name, value, ordinal)
  SELECT job_id, attempt, name, value, ordinal FROM metrics;

CREATE VIEW job_attempt_metrics AS
  SELECT s.name               AS study,
         j.key                AS job,
         a.attempt            AS attempt,
         a.state              AS attempt_state,
         a.solver_fingerprint AS solver_fingerprint,
         a.finished_at        AS finished_at,
         j.params_json        AS params,
         m.name               AS metric,
         m.value              AS value
  FROM studies s
  JOIN (SELECT DISTINCT study_id, job_id FROM study_jobs) sj ON sj.study_id = s.id
  JOIN jobs j ON j.id = sj.job_id
  JOIN attempt_metrics m ON m.job_id = j.id
  JOIN attempts a ON a.job_id = m.job_id AND a.attempt = m.attempt;
)SQL";

} // namespace

const std::vector<const char*>& migrations() {
  static const std::vector<const char*> m{schema_v1, schema_v2, schema_v3,
                                          schema_v4, schema_v5, schema_v6};
  return m;
}

} // namespace sph::runner
