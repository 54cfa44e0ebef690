// The SQLite job store: opening and migrating, study/job registration, claims, finishes,
// heartbeats and stale-job recovery.
#include "store.hpp"

#include "schema.hpp"

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <sys/vfs.h>
#include <unistd.h>
#include <unordered_set>

namespace sph::runner {

namespace fs = std::filesystem;

double unix_now() {
  using namespace std::chrono;
  return duration<double>(system_clock::now().time_since_epoch()).count();
}

bool is_network_filesystem(const fs::path& dir, std::string* fs_name) {
  struct statfs st {};
  if (statfs(dir.c_str(), &st) != 0)
    return false;
  struct Known {
    unsigned long magic;
    const char* name;
  };
  static const Known known[] = {
      {0x6969, "NFS"},        {0x517B, "SMB"},       {0xFF534D42, "CIFS"},   {0xFE534D42, "SMB2"},
      {0x0BD00BD0, "Lustre"}, {0x47504653, "GPFS"},  {0x19830326, "BeeGFS"}, {0x00C36400, "Ceph"},
      {0x65735546, "FUSE"},   {0x013111A8, "IBRIX"}, {0x5346414F, "AFS"},
  };
  for (const auto& k : known)
    if (static_cast<unsigned long>(st.f_type) == k.magic) {
      if (fs_name)
        *fs_name = k.name;
      return true;
    }
  return false;
}

namespace {

void configure(Db& db) {
  sqlite3_busy_timeout(db.handle(), 15000);
  db.exec("PRAGMA foreign_keys=ON");
}

int user_version(Db& db) {
  return static_cast<int>(db.scalar_int("PRAGMA user_version"));
}

// The names of the tables, views and indexes a runner database of schema version v (1 to 3,
// written before databases carried the application id) must have.
std::vector<std::string> legacy_objects(int v) {
  std::vector<std::string> o = {
      "table studies",           "table jobs",           "table study_jobs",
      "table attempts",          "table metrics",        "view job_metrics",
      "index jobs_state",        "index study_jobs_job", "index study_jobs_order",
      "index attempts_finished", "index metrics_name"};
  if (v >= 2)
    o.insert(o.end(), {"table job_params", "table slurm_submissions", "index job_params_lookup"});
  if (v >= 3)
    o.push_back("index attempts_state");
  return o;
}

bool has_column(Db& db, const std::string& table, const std::string& column) {
  Stmt q = db.prepare("SELECT 1 FROM pragma_table_info(?) WHERE name=?");
  q.bind(1, table).bind(2, column);
  return q.step();
}

// Positive identification, before anything (even the journal mode) changes a byte: a runner
// database carries application_id 'SPHR' (since schema version 4); an older one (versions 1-3)
// must have every table, view and index of its version and the key columns of `jobs`. An empty
// file (no schema at all) is a new database. Anything else is someone else's file: refused.
void identify(Db& db, const fs::path& path) {
  const auto app = db.scalar_int("PRAGMA application_id");
  const int v = user_version(db);
  const auto objects = db.scalar_int("SELECT count(*) FROM sqlite_master");
  if (app == Store::application_id) {
    if (v > Store::schema_version)
      throw std::runtime_error("database '" + path.string() + "' has schema version " +
                               std::to_string(v) + ", newer than this runner supports (" +
                               std::to_string(Store::schema_version) +
                               "); use a newer runner build");
    return;
  }
  const std::string not_ours =
      "'" + path.string() + "' is an SQLite database but not a runner " + "database";
  const std::string untouched = "; refusing to modify it (nothing was changed). Use another --db";
  if (app != 0) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "0x%08llx", static_cast<unsigned long long>(app) & 0xffffffffu);
    throw std::runtime_error(not_ours + " (its application_id is " + buf +
                             ", a runner database has 0x53504852 'SPHR')" + untouched);
  }
  if (v == 0 && objects == 0)
    return; // empty: a new database
  if (v > Store::schema_version)
    throw std::runtime_error("database '" + path.string() + "' has schema version " +
                             std::to_string(v) + ", newer than this runner supports (" +
                             std::to_string(Store::schema_version) +
                             "), and no runner application id: it is " + "not a runner database" +
                             ", or one written by a newer runner build; nothing was changed");
  if (v < 1 || v > 3)
    throw std::runtime_error(not_ours + " (user_version " + std::to_string(v) +
                             ", no runner application id)" + untouched);
  std::string missing;
  for (const auto& o : legacy_objects(v)) {
    auto sp = o.find(' ');
    Stmt q = db.prepare("SELECT 1 FROM sqlite_master WHERE type=? AND name=?");
    q.bind(1, o.substr(0, sp)).bind(2, o.substr(sp + 1));
    if (!q.step())
      missing += (missing.empty() ? "" : ", ") + o;
  }
  if (missing.empty())
    for (const char* c : {"key", "params_json", "numerics_version", "state", "owner_pid"})
      if (!has_column(db, "jobs", c))
        missing += std::string(missing.empty() ? "" : ", ") + "column jobs." + c;
  if (!missing.empty())
    throw std::runtime_error(not_ours + " (user_version " + std::to_string(v) +
                             " but no runner application id, and it lacks " + missing + ")" +
                             untouched);
}

} // namespace

std::string damaged_message(const fs::path& path, const std::string& what, bool at_open) {
  return "database '" + path.string() + "' is damaged (" + what + "); " +
         (at_open ? "nothing was written to it"
                  : "the command stopped, its transaction rolled back") +
         ". Restore it from a backup, or salvage what SQLite can read: sqlite3 '" + path.string() +
         "' .recover | sqlite3 recovered.sqlite";
}

namespace {
// configure() and check_version() on a just-opened database, with SQLite's errors turned into the
// runner's messages: a damaged file says so (and how to salvage it); anything else names the file
// and ends with `advice`.
void configure_checked(Db& db, const fs::path& path, const std::string& advice) {
  try {
    configure(db);
    identify(db, path);
  } catch (const SqliteError& e) {
    int primary = e.code() & 0xff;
    if (primary == SQLITE_CORRUPT || primary == SQLITE_NOTADB)
      throw std::runtime_error(damaged_message(path, e.what()));
    throw std::runtime_error("database '" + path.string() + "': " + e.what() + advice);
  }
}
} // namespace

Store Store::open_write(const fs::path& path, bool allow_network_fs) {
  if (std::error_code ec; fs::is_directory(path, ec))
    throw std::runtime_error("database path '" + path.string() + "' is a directory; --db takes a " +
                             "database file, e.g. " + (path / "results.sqlite").string());
  fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec)
    throw std::runtime_error("cannot create directory '" + dir.string() + "': " + ec.message());
  std::string fs_name;
  bool network = is_network_filesystem(dir, &fs_name);
  if (network && !allow_network_fs)
    throw std::runtime_error(
        "database '" + path.string() + "' is on a network file system (" + fs_name +
        "); SQLite locking and WAL are not safe there. Put the database on a local disk (--db), "
        "or pass --allow-network-fs to use it anyway with a rollback journal and a single runner");
  // A new database appears whole: its schema is written to a private file that is then linked
  // into place (link fails if another runner created it meanwhile, and that one is used), so a
  // reader (`status`, `query`) never finds a runner database without its schema.
  if (!fs::exists(path)) {
    fs::path tmp = path;
    tmp += ".new." + std::to_string(::getpid());
    {
      Db fresh(tmp.string(), SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
      configure(fresh);
      fresh.exec(network ? "PRAGMA journal_mode=DELETE" : "PRAGMA journal_mode=WAL");
      Store(std::move(fresh), tmp).migrate();
    }
    if (::link(tmp.c_str(), path.c_str()) != 0 && errno != EEXIST) {
      int err = errno;
      fs::remove(tmp, ec);
      throw std::runtime_error("cannot create database '" + path.string() +
                               "': " + std::strerror(err));
    }
    fs::remove(tmp, ec);
  }
  Db db(path.string(), SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  configure_checked(db, path, " (not touched; restore it from a backup or use another --db)");
  // A damaged file is refused before anything is written to it. quick_check reads every page
  // (0.3 to 1 s for a 100,000-job, 110 MB database): it runs at every start for databases up to
  // 256 MB, and for larger ones when a -wal file is present at open (another runner is using it,
  // or the last one did not close: kill -9, power loss).
  std::error_code size_ec;
  const auto db_bytes = fs::file_size(path, size_ec);
  const bool wal_present = fs::exists(path.string() + "-wal", size_ec);
  if (!size_ec && (db_bytes <= (256u << 20) || wal_present)) {
    try {
      Stmt q = db.prepare("PRAGMA quick_check(5)");
      std::string problems;
      while (q.step())
        if (q.text(0) != "ok")
          problems += (problems.empty() ? "" : "; ") + q.text(0);
      if (!problems.empty())
        throw SqliteError("PRAGMA quick_check: " + problems, SQLITE_CORRUPT);
    } catch (const SqliteError& e) {
      throw std::runtime_error(damaged_message(path, e.what()));
    }
  }
  // configure_checked() identified the file (someone else's is refused before anything, even
  // the journal mode, changes its bytes).
  if (network)
    db.exec("PRAGMA journal_mode=DELETE");
  else {
    Stmt s = db.prepare("PRAGMA journal_mode=WAL");
    if (!s.step() || s.text(0) != "wal")
      throw std::runtime_error("cannot switch database '" + path.string() + "' to WAL mode");
  }
  db.exec("PRAGMA synchronous=NORMAL");
  // A small -wal file: checkpoints every 250 pages (1 MB) instead of 1000, and a -wal file
  // larger than 1 MB is cut back to that after a checkpoint (a full disk must not come from it).
  db.exec("PRAGMA wal_autocheckpoint=250");
  db.exec("PRAGMA journal_size_limit=1048576");
  // A page cache of up to 128 MB (allocated as used): registering 100,000 jobs in one
  // transaction touches tens of MB of index pages, which the default 2 MB cache spills to the
  // -wal file again and again.
  db.exec("PRAGMA cache_size=-131072");
  Store store(std::move(db), path);
  store.migrate();
  return store;
}

Store Store::open_read(const fs::path& path) {
  if (!fs::exists(path))
    throw std::runtime_error("no database at '" + path.string() +
                             "' (run a study first, or pass --db)");
  Db db = Db::reader(path.string());
  configure_checked(db, path, "");
  if (user_version(db) == 0)
    throw std::runtime_error("'" + path.string() + "' is not a runner database (no schema)");
  // A runner database of an older schema is read as it is; the columns added since are filled by
  // the next runner that opens it for writing.
  return Store(std::move(db), path);
}

void Store::migrate() {
  if (user_version(db_) == schema_version)
    return;
  WriteTx tx(db_);
  int v = user_version(db_); // re-read under the write lock: another runner may have migrated
  if (v == 0 && db_.scalar_int("SELECT count(*) FROM sqlite_master WHERE type='table'") > 0)
    throw std::runtime_error("'" + path_.string() +
                             "' is an SQLite database but not a runner database; refusing to "
                             "modify it");
  const auto& m = migrations();
  for (; v < schema_version; ++v)
    db_.exec(m[static_cast<std::size_t>(v)]);
  db_.exec("PRAGMA application_id=" + std::to_string(application_id));
  db_.exec("PRAGMA user_version=" + std::to_string(schema_version));
  tx.commit();
}

std::string stale_sql(Db& db, const std::string& job, const std::string& state,
                      const std::string& fp) {
  Stmt c = db.prepare("SELECT 1 FROM pragma_table_info('attempts') WHERE "
                      "name='solver_fingerprint'");
  const std::string fingerprint =
      c.step() ? "(SELECT a.solver_fingerprint FROM attempts a WHERE a.job_id=" + job +
                     " AND a.state=" + state + " ORDER BY a.attempt DESC LIMIT 1)"
               : std::string("NULL");
  return "(" + state + " IN ('done','diverged') AND " + fingerprint + " IS NOT " + fp + ")";
}

SyncReport Store::register_expansion(const Study& study, const Expansion& ex, bool retry_failed,
                                     int max_attempts, bool rerun_stale,
                                     const std::string& fingerprint) {
  StudyRecord rec{study.name, study.case_name, study.description,
                  fs::absolute(study.file).lexically_normal().string(), study.definition_sha256};
  SyncReport sync =
      sync_study(rec, ex.tier, ex.jobs, retry_failed, max_attempts, unix_now(),
                 rerun_stale ? std::optional<std::string>(fingerprint) : std::nullopt);
  if (!rerun_stale)
    sync.stale_kept = stale_count(sync.study_id, ex.tier, fingerprint);
  return sync;
}

std::size_t Store::stale_count(std::int64_t study_id, const std::string& tier,
                               const std::string& fingerprint) {
  Stmt q = db_.prepare("SELECT count(*) FROM jobs j WHERE j.id IN (SELECT job_id FROM study_jobs "
                       "WHERE study_id=?1 AND tier=?2 AND current) AND " +
                       stale_sql(db_, "j.id", "j.state", "?3"));
  q.bind(1, study_id).bind(2, tier).bind(3, fingerprint);
  return q.step() ? static_cast<std::size_t>(q.integer(0)) : 0;
}

void Store::checkpoint_wal(bool truncate) {
  sqlite3_wal_checkpoint_v2(db_.handle(), nullptr,
                            truncate ? SQLITE_CHECKPOINT_TRUNCATE : SQLITE_CHECKPOINT_PASSIVE,
                            nullptr, nullptr);
}

SyncReport Store::sync_study(const StudyRecord& study, const std::string& tier,
                             const std::vector<JobSpec>& jobs, bool retry_failed, int max_attempts,
                             double now, const std::optional<std::string>& rerun_stale_of) {
  SyncReport r;
  WriteTx tx(db_);
  {
    Stmt q = db_.prepare("SELECT id, definition_sha256 FROM studies WHERE name=?");
    q.bind(1, study.name);
    if (q.step()) {
      r.study_id = q.integer(0);
      r.definition_changed = q.text(1) != study.definition_sha256;
      Stmt u = db_.prepare("UPDATE studies SET case_name=?, description=?, file=?, "
                           "definition_sha256=?, updated_at=? WHERE id=?");
      u.bind(1, study.case_name).bind(2, study.description).bind(3, study.file);
      u.bind(4, study.definition_sha256).bind(5, now).bind(6, r.study_id).run();
    } else {
      Stmt i = db_.prepare("INSERT INTO studies(name, case_name, description, file, "
                           "definition_sha256, created_at, updated_at) VALUES(?,?,?,?,?,?,?)");
      i.bind(1, study.name).bind(2, study.case_name).bind(3, study.description);
      i.bind(4, study.file).bind(5, study.definition_sha256).bind(6, now).bind(7, now).run();
      r.study_id = sqlite3_last_insert_rowid(db_.handle());
      r.study_is_new = true;
    }
  }
  std::unordered_set<std::int64_t> before;
  {
    Stmt q = db_.prepare("SELECT job_id FROM study_jobs WHERE study_id=? AND tier=? AND current");
    q.bind(1, r.study_id).bind(2, tier);
    while (q.step())
      before.insert(q.integer(0));
    // Jobs of an earlier version of the study stay members (current=0): still queryable.
    Stmt d = db_.prepare("UPDATE study_jobs SET current=0 WHERE study_id=? AND tier=?");
    d.bind(1, r.study_id).bind(2, tier).run();
  }
  Stmt ins = db_.prepare(
      "INSERT INTO jobs(key, case_name, scheme, numerics_version, params_json, state, attempts, "
      "created_at, updated_at) VALUES(?,?,?,?,?,'pending',0,?,?) ON CONFLICT(key) DO NOTHING");
  Stmt find = db_.prepare("SELECT id FROM jobs WHERE key=?");
  Stmt member = db_.prepare(
      "INSERT INTO study_jobs(study_id, job_id, tier, ordinal, current) VALUES(?,?,?,?,1) "
      "ON CONFLICT(study_id, job_id, tier) DO UPDATE SET ordinal=excluded.ordinal, current=1");
  // Many new jobs at once: after the first 20,000 new ones, the (name, value, job_id) index is
  // dropped and rebuilt once at the end (a sort) instead of taking ten random inserts per job.
  // Inside the transaction: readers never see the table without it.
  bool bulk = false;
  Stmt params = db_.prepare("INSERT OR IGNORE INTO job_params(job_id, name, value) SELECT ?1, "
                            "p.key, p.value FROM json_each(?2) p");
  std::size_t kept = 0;
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const JobSpec& j = jobs[i];
    ins.bind(1, j.key).bind(2, j.case_name).bind(3, j.scheme).bind(4, numerics_version);
    ins.bind(5, j.params_json).bind(6, now).bind(7, now).run();
    std::int64_t id;
    if (db_.changes() == 1) {
      id = sqlite3_last_insert_rowid(db_.handle());
      if (++r.inserted == 20000 && jobs.size() - i > 20000) {
        db_.exec("DROP INDEX IF EXISTS job_params_lookup");
        bulk = true;
      }
      params.bind(1, id).bind(2, j.params_json).run();
    } else {
      find.bind(1, j.key);
      find.step();
      id = find.integer(0);
      find.reset();
    }
    if (before.count(id))
      ++kept;
    member.bind(1, r.study_id).bind(2, id).bind(3, tier).bind(4, static_cast<std::int64_t>(i));
    member.run();
  }
  r.removed = before.size() - kept;
  if (bulk)
    db_.exec("CREATE INDEX IF NOT EXISTS job_params_lookup ON job_params(name, value, job_id)");

  const char* failing = "('failed','diverged','timeout')";
  std::string failed_attempts = std::string("(SELECT count(*) FROM attempts a WHERE a.job_id = "
                                            "jobs.id AND a.state IN ") +
                                failing + ")";
  std::string in_study =
      "id IN (SELECT job_id FROM study_jobs WHERE study_id=?1 AND tier=?2 AND current)";
  if (retry_failed) {
    Stmt u = db_.prepare("UPDATE jobs SET state='pending', updated_at=?3 WHERE state IN " +
                         std::string(failing) + " AND " + in_study + " AND " + failed_attempts +
                         " < ?4");
    u.bind(1, r.study_id).bind(2, tier).bind(3, now).bind(4, max_attempts).run();
    r.requeued = static_cast<std::size_t>(db_.changes());
    Stmt c = db_.prepare("SELECT count(*) FROM jobs WHERE state IN " + std::string(failing) +
                         " AND " + in_study);
    c.bind(1, r.study_id).bind(2, tier);
    c.step();
    r.exhausted = static_cast<std::size_t>(c.integer(0));
  }
  if (rerun_stale_of) {
    Stmt u = db_.prepare("UPDATE jobs SET state='pending', updated_at=?3 WHERE " + in_study +
                         " AND " + stale_sql(db_, "jobs.id", "jobs.state", "?4"));
    u.bind(1, r.study_id).bind(2, tier).bind(3, now).bind(4, *rerun_stale_of).run();
    r.stale_requeued = static_cast<std::size_t>(db_.changes());
  }
  {
    Stmt q =
        db_.prepare("SELECT j.id, sj.ordinal, j.state, j.attempts FROM study_jobs sj JOIN "
                    "jobs j ON j.id = sj.job_id WHERE sj.study_id=? AND sj.tier=? AND sj.current "
                    "ORDER BY sj.ordinal");
    q.bind(1, r.study_id).bind(2, tier);
    while (q.step())
      r.jobs.push_back({q.integer(0), static_cast<std::size_t>(q.integer(1)), q.text(2),
                        static_cast<int>(q.integer(3))});
  }
  tx.commit();
  return r;
}

std::vector<StaleJob> Store::reset_stale(const std::string& host, int self_pid, double now,
                                         double stale_after_s,
                                         const std::function<bool(int)>& pid_alive) {
  std::vector<StaleJob> out;
  WriteTx tx(db_);
  struct Row {
    std::int64_t id;
    std::string key, reason;
  };
  std::vector<Row> stale;
  {
    Stmt q = db_.prepare("SELECT id, key, owner_host, owner_pid, heartbeat_at FROM jobs WHERE "
                         "state='running'");
    while (q.step()) {
      std::string owner = q.text(2);
      int pid = static_cast<int>(q.integer(3));
      std::string who = "host " + owner + ", pid " + std::to_string(pid);
      if (owner == host) {
        // On this host the owner's pid decides, never its heartbeat: a runner stopped for a
        // while (Ctrl-Z, kill -STOP, a suspended laptop) still owns its jobs and their folders.
        if (pid == self_pid || !pid_alive(pid))
          stale.push_back({q.integer(0), q.text(1), "abandoned: owner process gone (" + who + ")"});
      } else if (q.is_null(4) || now - q.real(4) > stale_after_s) {
        double age = q.is_null(4) ? -1 : now - q.real(4);
        stale.push_back({q.integer(0), q.text(1),
                         "abandoned: owner heartbeat stale" +
                             (age >= 0 ? " for " + std::to_string(static_cast<long>(age)) + " s"
                                       : std::string()) +
                             " (" + who + ")"});
      }
    }
  }
  Stmt uj = db_.prepare("UPDATE jobs SET state='pending', owner_host=NULL, owner_pid=NULL, "
                        "heartbeat_at=NULL, updated_at=? WHERE id=? AND state='running'");
  Stmt ua =
      db_.prepare("UPDATE attempts SET state='abandoned', failure_class='stale', finished_at=?, "
                  "error_text=? "
                  "WHERE job_id=? AND state='running'");
  for (const auto& s : stale) {
    uj.bind(1, now).bind(2, s.id).run();
    ua.bind(1, now).bind(2, s.reason).bind(3, s.id).run();
    out.push_back({s.key, s.reason});
  }
  tx.commit();
  return out;
}

std::optional<int> Store::claim(std::int64_t job_id, const AttemptStart& a) {
  WriteTx tx(db_);
  Stmt u = db_.prepare("UPDATE jobs SET state='running', owner_host=?, owner_pid=?, "
                       "attempts=attempts+1, heartbeat_at=?, updated_at=?, progress=NULL "
                       "WHERE id=? AND state='pending' RETURNING attempts");
  u.bind(1, a.host).bind(2, a.pid).bind(3, a.started_at).bind(4, a.started_at).bind(5, job_id);
  if (!u.step())
    return std::nullopt;
  int attempt = static_cast<int>(u.integer(0));
  u.reset();
  Stmt i = db_.prepare("INSERT INTO attempts(job_id, attempt, state, started_at, host, pid, "
                       "threads, code_version, compiler, solver_fingerprint) "
                       "VALUES(?,?,'running',?,?,?,?,?,?,?)");
  i.bind(1, job_id).bind(2, attempt).bind(3, a.started_at).bind(4, a.host).bind(5, a.pid);
  i.bind(6, a.threads).bind(7, a.code_version).bind(8, a.compiler);
  i.bind(9, a.solver_fingerprint).run();
  tx.commit();
  return attempt;
}

bool Store::finish(std::int64_t job_id, int attempt, const std::string& host, int pid,
                   const Finish& f) {
  WriteTx tx(db_);
  Stmt u = db_.prepare(
      "UPDATE jobs SET state=?1, owner_host=NULL, owner_pid=NULL, heartbeat_at=NULL, "
      "updated_at=?2, progress=CASE WHEN ?1='done' THEN 1.0 ELSE progress END, "
      "output_dir=COALESCE(?3, output_dir) "
      "WHERE id=?4 AND state='running' AND owner_host=?5 AND owner_pid=?6 AND attempts=?7");
  u.bind(1, f.state).bind(2, f.finished_at).bind(3, f.output_dir).bind(4, job_id);
  u.bind(5, host).bind(6, pid).bind(7, attempt).run();
  if (db_.changes() != 1)
    return false; // no longer ours: the transaction rolls back
  record_attempt(job_id, attempt, f);
  tx.commit();
  return true;
}

bool Store::finish_submitted(std::int64_t job_id, int attempt, const std::string& host,
                             const std::string& slurm_job_id, const Finish& f) {
  WriteTx tx(db_);
  Stmt u = db_.prepare(
      "UPDATE jobs SET state=?1, owner_host=NULL, owner_pid=NULL, heartbeat_at=NULL, "
      "updated_at=?2, progress=CASE WHEN ?1='done' THEN 1.0 ELSE progress END, "
      "output_dir=COALESCE(?3, output_dir) WHERE id=?4 AND state='submitted' AND attempts=?5");
  u.bind(1, f.state).bind(2, f.finished_at).bind(3, f.output_dir).bind(4, job_id);
  u.bind(5, attempt).run();
  if (db_.changes() != 1)
    return false;
  record_attempt(job_id, attempt, f);
  Stmt a = db_.prepare("UPDATE attempts SET host=?, slurm_job_id=? WHERE job_id=? AND attempt=?");
  a.bind(1, host).bind(2, slurm_job_id).bind(3, job_id).bind(4, attempt).run();
  tx.commit();
  return true;
}

void Store::record_attempt(std::int64_t job_id, int attempt, const Finish& f) {
  Stmt a = db_.prepare("UPDATE attempts SET state=?, finished_at=?, wall_s=?, cpu_s=?, "
                       "peak_rss_kb=?, child_pid=?, exit_code=?, signal=?, message=?, "
                       "error_text=?, failure_class=? WHERE job_id=? AND attempt=?");
  a.bind(1, f.state).bind(2, f.finished_at).bind(3, f.wall_s).bind(4, f.cpu_s);
  a.bind(5, f.peak_rss_kb).bind(6, f.child_pid).bind(7, f.exit_code).bind(8, f.signal);
  if (f.message.empty())
    a.bind_null(9);
  else
    a.bind(9, f.message);
  if (f.error_text.empty())
    a.bind_null(10);
  else
    a.bind(10, f.error_text);
  if (f.failure_class.empty())
    a.bind_null(11);
  else
    a.bind(11, f.failure_class);
  a.bind(12, job_id).bind(13, attempt).run();
  Stmt d = db_.prepare("DELETE FROM metrics WHERE job_id=?");
  d.bind(1, job_id).run();
  Stmt m = db_.prepare("INSERT OR REPLACE INTO metrics(job_id, name, value, attempt, ordinal) "
                       "VALUES(?,?,?,?,?)");
  for (std::size_t k = 0; k < f.metrics.size(); ++k) {
    // SQLite stores NaN as NULL; infinities are kept.
    m.bind(1, job_id).bind(2, f.metrics[k].first).bind(3, f.metrics[k].second);
    m.bind(4, attempt).bind(5, static_cast<std::int64_t>(k)).run();
  }
}

void Store::release(std::int64_t job_id, int attempt, const std::string& host, int pid,
                    const std::string& reason, double now) {
  WriteTx tx(db_);
  Stmt u = db_.prepare("UPDATE jobs SET state='pending', owner_host=NULL, owner_pid=NULL, "
                       "heartbeat_at=NULL, updated_at=? WHERE id=? AND state='running' AND "
                       "owner_host=? AND owner_pid=? AND attempts=?");
  u.bind(1, now).bind(2, job_id).bind(3, host).bind(4, pid).bind(5, attempt).run();
  if (db_.changes() != 1)
    return;
  Stmt a = db_.prepare("UPDATE attempts SET state='interrupted', failure_class='interrupted', "
                       "finished_at=?, error_text=? "
                       "WHERE job_id=? AND attempt=?");
  a.bind(1, now).bind(2, reason).bind(3, job_id).bind(4, attempt).run();
  tx.commit();
}

void Store::heartbeat(const std::vector<std::pair<std::int64_t, std::optional<double>>>& jobs,
                      const std::string& host, int pid, double now) {
  if (jobs.empty())
    return;
  WriteTx tx(db_);
  Stmt u = db_.prepare("UPDATE jobs SET heartbeat_at=?, progress=COALESCE(?, progress) "
                       "WHERE id=? AND state='running' AND owner_host=? AND owner_pid=?");
  for (const auto& [id, progress] : jobs) {
    u.bind(1, now).bind(2, progress).bind(3, id).bind(4, host).bind(5, pid).run();
  }
  tx.commit();
}

std::map<std::string, std::size_t> Store::state_counts(std::int64_t study_id,
                                                       const std::string& tier) {
  std::map<std::string, std::size_t> out;
  Stmt q =
      db_.prepare("SELECT j.state, count(*) FROM study_jobs sj JOIN jobs j ON j.id = "
                  "sj.job_id WHERE sj.study_id=? AND sj.tier=? AND sj.current GROUP BY j.state");
  q.bind(1, study_id).bind(2, tier);
  while (q.step())
    out[q.text(0)] = static_cast<std::size_t>(q.integer(1));
  return out;
}

std::map<std::string, std::string> Store::states_of(const std::vector<std::string>& keys) {
  std::map<std::string, std::string> out;
  Stmt q = db_.prepare("SELECT state FROM jobs WHERE key=?");
  for (const auto& k : keys) {
    q.bind(1, k);
    if (q.step())
      out[k] = q.text(0);
    q.reset();
  }
  return out;
}

} // namespace sph::runner
