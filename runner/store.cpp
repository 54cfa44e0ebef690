// The SQLite job store: opening and migrating, study/job registration, claims, finishes,
// heartbeats and stale-job recovery.
#include "store.hpp"

#include "schema.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <set>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

namespace sph::runner {

namespace fs = std::filesystem;

double unix_now() {
  using namespace std::chrono;
  return duration<double>(system_clock::now().time_since_epoch()).count();
}

namespace {
struct StateName {
  JobState state;
  const char* word;
};
// The database words: never change one (existing databases and users' SQL use them).
constexpr StateName state_names[] = {
    {JobState::pending, "pending"}, {JobState::submitted, "submitted"},
    {JobState::running, "running"}, {JobState::done, "done"},
    {JobState::failed, "failed"},   {JobState::diverged, "diverged"},
    {JobState::timeout, "timeout"},
};

// "('failed','diverged','timeout')": an SQL list of state words.
std::string sql_states(std::initializer_list<JobState> states) {
  std::string s = "(";
  for (JobState st : states)
    s += (s.size() > 1 ? ",'" : "'") + std::string(to_string(st)) + "'";
  return s + ")";
}
} // namespace

const char* to_string(JobState s) {
  for (const auto& n : state_names)
    if (n.state == s)
      return n.word;
  return "?";
}

std::optional<JobState> parse_job_state(std::string_view s) {
  for (const auto& n : state_names)
    if (s == n.word)
      return n.state;
  return std::nullopt;
}

JobState job_state_from(std::string_view s) {
  if (auto st = parse_job_state(s))
    return *st;
  std::string words;
  for (const auto& n : state_names)
    words += (words.empty() ? "" : ", ") + std::string(n.word);
  throw std::runtime_error("unknown job state '" + std::string(s) + "' (a job state is one of " +
                           words + ")");
}

const std::vector<JobState>& all_job_states() {
  static const std::vector<JobState> all = [] {
    std::vector<JobState> v;
    for (const auto& n : state_names)
      v.push_back(n.state);
    return v;
  }();
  return all;
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
  const int v = user_version(db);
  if (v == 0)
    throw std::runtime_error("'" + path.string() + "' is not a runner database (no schema)");
  if (v < schema_version) {
    // A runner database of an older schema lacks columns and tables the read commands use: it
    // is upgraded first, as the next run would (identified, quick-checked, migrated).
    db = Db();
    try {
      Store::open_write(path);
    } catch (const std::exception& e) {
      throw std::runtime_error("database '" + path.string() + "' has schema version " +
                               std::to_string(v) + ", older than this runner's " +
                               std::to_string(schema_version) +
                               ", and could not be upgraded: " + e.what());
    }
    db = Db::reader(path.string());
    configure_checked(db, path, "");
  }
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
  for (; v < schema_version; ++v) {
    // Version 5 adds one column; a file that already has it (written by this runner, then
    // relabelled as older) keeps it: ADD COLUMN has no IF NOT EXISTS.
    if (v == 4 && has_column(db_, "attempts", "predicted_cpu_s"))
      continue;
    db_.exec(m[static_cast<std::size_t>(v)]);
  }
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

SyncReport Store::register_expansion(const Study& study, const std::string& tier, JobStream& jobs,
                                     bool retry_failed, int max_attempts, bool rerun_stale,
                                     const std::string& fingerprint) {
  StudyRecord rec{study.name, study.case_name, study.description,
                  study.file.empty() ? std::string()
                                     : fs::absolute(study.file).lexically_normal().string(),
                  study.definition_sha256};
  JobSpec job;
  SyncReport sync = sync_study(
      rec, tier, [&]() -> const JobSpec* { return jobs.next(job) ? &job : nullptr; }, retry_failed,
      max_attempts, unix_now(),
      rerun_stale ? std::optional<std::string>(fingerprint) : std::nullopt, study.accumulate);
  if (!rerun_stale)
    sync.stale_kept = stale_count(sync.study_id, tier, fingerprint);
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

std::string Store::wal_files_changed() {
  for (const char* suffix : {"-wal", "-shm"}) {
    const std::string f = path_.string() + suffix;
    struct stat st {};
    const bool exists = ::stat(f.c_str(), &st) == 0;
    auto seen = wal_files_.find(suffix);
    if (seen == wal_files_.end()) {
      if (exists)
        wal_files_[suffix] = {static_cast<std::uint64_t>(st.st_dev),
                              static_cast<std::uint64_t>(st.st_ino)};
      continue;
    }
    if (!exists)
      return "'" + f + "' was deleted";
    if (seen->second != std::pair<std::uint64_t, std::uint64_t>(st.st_dev, st.st_ino))
      return "'" + f + "' was replaced by another file";
  }
  return "";
}

void Store::checkpoint_wal(bool truncate) {
  sqlite3_wal_checkpoint_v2(db_.handle(), nullptr,
                            truncate ? SQLITE_CHECKPOINT_TRUNCATE : SQLITE_CHECKPOINT_PASSIVE,
                            nullptr, nullptr);
}

SyncReport Store::sync_study(const StudyRecord& study, const std::string& tier,
                             const std::vector<JobSpec>& jobs, bool retry_failed, int max_attempts,
                             double now, const std::optional<std::string>& rerun_stale_of,
                             bool accumulate) {
  std::size_t i = 0;
  return sync_study(
      study, tier, [&]() { return i < jobs.size() ? &jobs[i++] : nullptr; }, retry_failed,
      max_attempts, now, rerun_stale_of, accumulate);
}

SyncReport Store::sync_study(const StudyRecord& study, const std::string& tier,
                             const JobSource& jobs, bool retry_failed, int max_attempts, double now,
                             const std::optional<std::string>& rerun_stale_of, bool accumulate) {
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
  std::vector<std::int64_t> before; // sorted (8 bytes a job: a study of a million jobs again)
  {
    Stmt q = db_.prepare("SELECT job_id FROM study_jobs WHERE study_id=? AND tier=? AND current "
                         "ORDER BY job_id");
    q.bind(1, r.study_id).bind(2, tier);
    while (q.step())
      before.push_back(q.integer(0));
    // Jobs of an earlier version of the study stay members (current=0): still queryable.
    if (!accumulate) {
      Stmt d = db_.prepare("UPDATE study_jobs SET current=0 WHERE study_id=? AND tier=?");
      d.bind(1, r.study_id).bind(2, tier).run();
    }
  }
  Stmt ins = db_.prepare(
      "INSERT INTO jobs(key, case_name, scheme, numerics_version, params_json, state, attempts, "
      "created_at, updated_at) VALUES(?,?,?,?,?,'pending',0,?,?) ON CONFLICT(key) DO NOTHING");
  Stmt find = db_.prepare("SELECT id FROM jobs WHERE key=?");
  Stmt member = db_.prepare(
      "INSERT INTO study_jobs(study_id, job_id, tier, ordinal, current) VALUES(?,?,?,?,1) "
      "ON CONFLICT(study_id, job_id, tier) DO UPDATE SET ordinal=excluded.ordinal, current=1");
  // The parameters of the new jobs go to job_params after the loop, in one statement. (One
  // statement per job, inserting its rows from json_each, wrote each page it changed, changed
  // before in the transaction, to a statement journal first, as a statement of several rows that
  // may fail half-way on a foreign key must: 18 pages of 4 kB a job, 1.1 GB for 20,000 jobs, most
  // of the time registering a million new jobs took.)
  const std::int64_t last_id_before = db_.scalar_int("SELECT coalesce(max(id), 0) FROM jobs");
  std::size_t kept = 0;
  std::int64_t first_ordinal = 0; // accumulate: the jobs go after the study's others
  if (accumulate) {
    Stmt m = db_.prepare(
        "SELECT coalesce(max(ordinal) + 1, 0) FROM study_jobs WHERE study_id=? AND tier=?");
    m.bind(1, r.study_id).bind(2, tier);
    m.step();
    first_ordinal = m.integer(0);
  }
  std::vector<std::int64_t> given; // accumulate: the ids of the given jobs
  std::size_t i = 0;
  for (const JobSpec* next = jobs(); next; next = jobs(), ++i) {
    const JobSpec& j = *next;
    ins.bind(1, j.key).bind(2, j.case_name).bind(3, j.scheme).bind(4, numerics_version);
    ins.bind(5, j.params_json).bind(6, now).bind(7, now).run();
    std::int64_t id;
    if (db_.changes() == 1) {
      id = sqlite3_last_insert_rowid(db_.handle());
      ++r.inserted;
    } else {
      find.bind(1, j.key);
      find.step();
      id = find.integer(0);
      find.reset();
    }
    if (std::binary_search(before.begin(), before.end(), id))
      ++kept;
    member.bind(1, r.study_id).bind(2, id).bind(3, tier);
    member.bind(4, first_ordinal + static_cast<std::int64_t>(i));
    member.run();
    if (accumulate)
      given.push_back(id);
  }
  r.removed = accumulate ? 0 : before.size() - kept;
  {
    // Many new jobs (at least 20,000, and as many as there were before): the (name, value, job_id)
    // index is dropped and rebuilt once (a sort) instead of taking ten inserts per job. Inside
    // the transaction: readers never see the table without it.
    const bool bulk = r.inserted >= 20000 && static_cast<std::int64_t>(r.inserted) >=
                                                 db_.scalar_int("SELECT count(*) FROM jobs") / 2;
    if (bulk)
      db_.exec("DROP INDEX IF EXISTS job_params_lookup");
    Stmt params =
        db_.prepare("INSERT OR IGNORE INTO job_params(job_id, name, value) SELECT j.id, "
                    "p.key, p.value FROM jobs j, json_each(j.params_json) p WHERE j.id > ?");
    params.bind(1, last_id_before).run();
    if (bulk)
      db_.exec("CREATE INDEX IF NOT EXISTS job_params_lookup ON job_params(name, value, job_id)");
  }

  const std::string failing = sql_states({JobState::failed, JobState::diverged, JobState::timeout});
  // With to_pending(): ?1 is the time, the study and tier are ?2 and ?3.
  const std::string in_study =
      "id IN (SELECT job_id FROM study_jobs WHERE study_id=?2 AND tier=?3 AND current)";
  if (retry_failed) {
    Stmt u = to_pending("state IN " + failing + " AND " + in_study +
                        " AND (SELECT count(*) FROM attempts a WHERE a.job_id = jobs.id AND "
                        "a.state IN " +
                        failing + ") < ?4");
    u.bind(1, now).bind(2, r.study_id).bind(3, tier).bind(4, max_attempts).run();
    r.requeued = static_cast<std::size_t>(db_.changes());
    Stmt c =
        db_.prepare("SELECT count(*) FROM jobs WHERE state IN " + failing + " AND " + in_study);
    c.bind(2, r.study_id).bind(3, tier);
    c.step();
    r.exhausted = static_cast<std::size_t>(c.integer(0));
  }
  if (rerun_stale_of) {
    Stmt u = to_pending(in_study + " AND " + stale_sql(db_, "jobs.id", "jobs.state", "?4"));
    u.bind(1, now).bind(2, r.study_id).bind(3, tier).bind(4, *rerun_stale_of).run();
    r.stale_requeued = static_cast<std::size_t>(db_.changes());
  }
  {
    Stmt q =
        db_.prepare("SELECT j.id, sj.ordinal, j.state, j.attempts FROM study_jobs sj JOIN "
                    "jobs j ON j.id = sj.job_id WHERE sj.study_id=? AND sj.tier=? AND sj.current "
                    "ORDER BY sj.ordinal");
    q.bind(1, r.study_id).bind(2, tier);
    Stmt one = db_.prepare("SELECT state, attempts FROM jobs WHERE id=?");
    for (std::size_t k = 0; k < given.size(); ++k) {
      // Only the given jobs (at their index among them), not every member.
      one.bind(1, given[k]);
      if (one.step())
        r.jobs.push_back(
            {given[k], k, job_state_from(one.text(0)), static_cast<int>(one.integer(1))});
      one.reset();
    }
    while (!accumulate && q.step())
      r.jobs.push_back({q.integer(0), static_cast<std::size_t>(q.integer(1)),
                        job_state_from(q.text(2)), static_cast<int>(q.integer(3))});
  }
  tx.commit();
  return r;
}

std::vector<StaleJob> Store::reset_stale(const std::string& host, int self_pid, double now,
                                         double stale_after_s,
                                         const std::function<bool(int, double)>& owner_alive) {
  std::vector<StaleJob> out;
  WriteTx tx(db_);
  struct Row {
    std::int64_t id;
    std::string key, reason;
  };
  std::vector<Row> stale;
  {
    Stmt q = db_.prepare(
        "SELECT id, key, owner_host, owner_pid, heartbeat_at, (SELECT max(a.started_at) FROM "
        "attempts a WHERE a.job_id = jobs.id AND a.state = 'running') FROM jobs WHERE "
        "state='running'");
    while (q.step()) {
      std::string owner = q.text(2);
      int pid = static_cast<int>(q.integer(3));
      std::string who = "host " + owner + ", pid " + std::to_string(pid);
      if (owner == host) {
        // On this host the owner's pid decides, never its heartbeat: a runner stopped for a
        // while (Ctrl-Z, kill -STOP, a suspended laptop) still owns its jobs and their folders.
        const double claimed_at = q.is_null(5) ? now : q.real(5);
        if (pid == self_pid || !owner_alive(pid, claimed_at))
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
  Stmt uj = to_pending("id=?2 AND state='running'");
  Stmt ua = end_attempt("job_id=?5 AND state='running'");
  for (const auto& s : stale) {
    uj.bind(1, now).bind(2, s.id).run();
    ua.bind(1, "abandoned").bind(2, "stale").bind(3, now).bind(4, s.reason).bind(5, s.id).run();
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
                       "threads, code_version, compiler, solver_fingerprint, predicted_cpu_s) "
                       "VALUES(?,?,'running',?,?,?,?,?,?,?,?)");
  i.bind(1, job_id).bind(2, attempt).bind(3, a.started_at).bind(4, a.host).bind(5, a.pid);
  i.bind(6, a.threads).bind(7, a.code_version).bind(8, a.compiler);
  i.bind(9, a.solver_fingerprint).bind(10, a.predicted_cpu_s).run();
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
  u.bind(1, to_string(f.state)).bind(2, f.finished_at).bind(3, f.output_dir).bind(4, job_id);
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
  u.bind(1, to_string(f.state)).bind(2, f.finished_at).bind(3, f.output_dir).bind(4, job_id);
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
  a.bind(1, to_string(f.state)).bind(2, f.finished_at).bind(3, f.wall_s).bind(4, f.cpu_s);
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
  auto insert_metrics = [&](const std::string& table) {
    Stmt m = db_.prepare("INSERT OR REPLACE INTO " + table +
                         "(job_id, name, value, attempt, ordinal) VALUES(?,?,?,?,?)");
    for (std::size_t k = 0; k < f.metrics.size(); ++k) {
      // SQLite stores NaN as NULL; infinities are kept.
      m.bind(1, job_id).bind(2, f.metrics[k].first).bind(3, f.metrics[k].second);
      m.bind(4, attempt).bind(5, static_cast<std::int64_t>(k)).run();
    }
  };
  insert_metrics("attempt_metrics");
  // The result the job holds: the attempt whose metrics are in `metrics`, if done or diverged.
  std::optional<JobState> held;
  {
    Stmt q = db_.prepare("SELECT a.state FROM attempts a WHERE a.job_id=?1 AND a.attempt<>?2 AND "
                         "a.attempt=(SELECT max(m.attempt) FROM metrics m WHERE m.job_id=?1)");
    q.bind(1, job_id).bind(2, attempt);
    if (q.step())
      if (auto st = parse_job_state(q.text(0)); st && holds_result(*st))
        held = *st;
  }
  const bool takes_over = !held || f.state == JobState::done ||
                          (f.state == JobState::diverged && *held != JobState::done);
  if (takes_over) {
    Stmt d = db_.prepare("DELETE FROM metrics WHERE job_id=?");
    d.bind(1, job_id).run();
    insert_metrics("metrics");
  } else {
    Stmt u = db_.prepare("UPDATE jobs SET state=? WHERE id=?");
    u.bind(1, to_string(*held)).bind(2, job_id).run();
  }
}

void Store::release(std::int64_t job_id, int attempt, const std::string& host, int pid,
                    const std::string& reason, double now) {
  WriteTx tx(db_);
  Stmt u = to_pending("id=?2 AND state='running' AND owner_host=?3 AND owner_pid=?4 AND "
                      "attempts=?5");
  u.bind(1, now).bind(2, job_id).bind(3, host).bind(4, pid).bind(5, attempt).run();
  if (db_.changes() != 1)
    return;
  Stmt a = end_attempt("job_id=?5 AND attempt=?6");
  a.bind(1, "interrupted").bind(2, "interrupted").bind(3, now).bind(4, reason);
  a.bind(5, job_id).bind(6, attempt).run();
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

std::map<JobState, std::size_t> Store::state_counts(std::int64_t study_id,
                                                    const std::string& tier) {
  std::map<JobState, std::size_t> out;
  Stmt q =
      db_.prepare("SELECT j.state, count(*) FROM study_jobs sj JOIN jobs j ON j.id = "
                  "sj.job_id WHERE sj.study_id=? AND sj.tier=? AND sj.current GROUP BY j.state");
  q.bind(1, study_id).bind(2, tier);
  while (q.step())
    out[job_state_from(q.text(0))] = static_cast<std::size_t>(q.integer(1));
  return out;
}

std::map<std::string, JobState> Store::states_of(const std::vector<std::string>& keys) {
  std::map<std::string, JobState> out;
  Stmt q = db_.prepare("SELECT state FROM jobs WHERE key=?");
  for (const auto& k : keys) {
    q.bind(1, k);
    if (q.step())
      out[k] = job_state_from(q.text(0));
    q.reset();
  }
  return out;
}

Stmt Store::to_pending(const std::string& cond) {
  return db_.prepare("UPDATE jobs SET state='pending', owner_host=NULL, owner_pid=NULL, "
                     "heartbeat_at=NULL, updated_at=?1 WHERE " +
                     cond);
}

Stmt Store::end_attempt(const std::string& cond) {
  return db_.prepare(
      "UPDATE attempts SET state=?1, failure_class=?2, finished_at=?3, error_text=?4 WHERE " +
      cond);
}

std::optional<Store::JobSummary> Store::job_summary(const std::string& key) {
  Stmt q = db_.prepare("SELECT id, state, attempts, output_dir FROM jobs WHERE key=?");
  q.bind(1, key);
  if (!q.step())
    return std::nullopt;
  JobSummary j;
  j.id = q.integer(0);
  j.state = job_state_from(q.text(1));
  j.attempts = static_cast<int>(q.integer(2));
  j.output_dir = q.is_null(3) ? "" : q.text(3);
  Stmt m = db_.prepare("SELECT name, value FROM metrics WHERE job_id=? ORDER BY ordinal");
  m.bind(1, j.id);
  while (m.step())
    j.metrics.emplace_back(m.text(0), m.opt_real(1));
  return j;
}

std::map<std::string, std::vector<CostSample>>
Store::cost_samples(const std::vector<std::string>& schemes, std::size_t limit) {
  std::map<std::string, std::vector<CostSample>> out;
  auto metric = [](const char* name) {
    return std::string("(SELECT value FROM metrics m WHERE m.job_id=j.id AND m.name='") + name +
           "')";
  };
  Stmt q = db_.prepare("SELECT a.cpu_s, " + metric("n_particles") + ", " + metric("steps") +
                       ", j.params_json, j.case_name, coalesce(" + metric("work_steps") + ", " +
                       metric("acoustic_steps") + "), " + metric("dimension") + ", " +
                       metric("predicted_work") +
                       " FROM jobs j JOIN attempts a ON a.job_id=j.id AND a.attempt=j.attempts "
                       "AND a.state='done' WHERE j.scheme=? AND j.state='done' AND a.cpu_s IS NOT "
                       "NULL ORDER BY a.finished_at DESC LIMIT ?");
  for (const auto& sch : schemes) {
    q.bind(1, sch).bind(2, static_cast<std::int64_t>(limit));
    while (q.step()) {
      CostSample c{q.real(0), q.opt_real(1), q.opt_real(2), q.text(3), q.opt_real(5),
                   {},        q.opt_real(7)};
      if (auto d = q.opt_real(6))
        c.dim = static_cast<int>(*d);
      out[q.text(4) + "/" + (sch.empty() ? "-" : sch)].push_back(std::move(c));
    }
    q.reset();
  }
  return out;
}

std::size_t Store::count_in_state(JobState s) {
  Stmt q = db_.prepare("SELECT count(*) FROM jobs WHERE state=?");
  q.bind(1, to_string(s));
  return q.step() ? static_cast<std::size_t>(q.integer(0)) : 0;
}

std::string Store::quick_check() {
  Stmt q = db_.prepare("PRAGMA quick_check");
  return q.step() ? q.text(0) : std::string("ok");
}

std::optional<double> Store::mean_wall_s(std::int64_t study_id, const std::string& tier) {
  Stmt q =
      db_.prepare("SELECT avg(a.wall_s) FROM attempts a WHERE a.state IN ('done','diverged') AND "
                  "a.wall_s IS NOT NULL AND a.job_id IN (SELECT job_id FROM study_jobs WHERE "
                  "study_id=? AND tier=?)");
  q.bind(1, study_id).bind(2, tier);
  if (q.step() && !q.is_null(0))
    return q.real(0);
  return std::nullopt;
}

std::optional<StudyInfo> Store::find_study(const std::string& name) {
  Stmt q = db_.prepare(
      "SELECT id, file, definition_sha256, description, case_name FROM studies WHERE name=?");
  q.bind(1, name);
  if (!q.step())
    return std::nullopt;
  return StudyInfo{q.integer(0), q.text(1), q.text(2), q.text(3), q.text(4)};
}

std::vector<std::string> Store::study_names() {
  std::vector<std::string> names;
  Stmt all = db_.prepare("SELECT name FROM studies ORDER BY name");
  while (all.step())
    names.push_back(all.text(0));
  return names;
}

std::vector<StateCount>
Store::state_table(std::optional<std::int64_t> study_id,
                   const std::function<std::string(const std::string&)>& fingerprint_of_case) {
  std::vector<StateCount> out;
  // This build's fingerprint of each study's case (they differ by case: core/fingerprint.hpp).
  std::vector<std::string> cases;
  for (Stmt c = db_.prepare("SELECT DISTINCT case_name FROM studies"); c.step();)
    cases.push_back(c.text(0));
  std::string fp = "(CASE s.case_name";
  for (std::size_t k = 0; k < cases.size(); ++k)
    fp += " WHEN ?" + std::to_string(2 + 2 * k) + " THEN ?" + std::to_string(3 + 2 * k);
  fp += " END)";
  Stmt q = db_.prepare("SELECT s.name, sj.tier, j.state, count(*), sum(" +
                       stale_sql(db_, "j.id", "j.state", fp) +
                       ") FROM studies s JOIN study_jobs "
                       "sj ON sj.study_id=s.id AND sj.current JOIN jobs j ON j.id=sj.job_id" +
                       (study_id ? " WHERE s.id=?1" : " WHERE ?1 IS NULL") +
                       " GROUP BY s.name, sj.tier, j.state ORDER BY s.name, sj.tier");
  if (study_id)
    q.bind(1, *study_id);
  for (std::size_t k = 0; k < cases.size(); ++k)
    q.bind(static_cast<int>(2 + 2 * k), cases[k])
        .bind(static_cast<int>(3 + 2 * k), fingerprint_of_case(cases[k]));
  while (q.step())
    out.push_back({q.text(0), q.text(1), job_state_from(q.text(2)), q.integer(3), q.integer(4)});
  return out;
}

namespace {
// Per-job test (study_jobs_job index), so that the few running or failed jobs drive the
// queries rather than the list of all the study's jobs; binds ?1.
std::string job_of_study(std::optional<std::int64_t> sid) {
  return sid ? " AND EXISTS (SELECT 1 FROM study_jobs sj WHERE sj.job_id=j.id AND "
               "sj.study_id=?1)"
             : "";
}
} // namespace

std::vector<RunningJob> Store::running_jobs(std::optional<std::int64_t> study_id) {
  std::vector<RunningJob> out;
  Stmt r = db_.prepare("SELECT j.key, j.owner_host, j.owner_pid, j.heartbeat_at, j.progress, "
                       "j.params_json FROM jobs j WHERE j.state='running'" +
                       job_of_study(study_id) + " ORDER BY j.heartbeat_at");
  if (study_id)
    r.bind(1, *study_id);
  while (r.step())
    out.push_back({r.text(0), r.text(1), r.text(5), r.integer(2), r.opt_real(3), r.opt_real(4)});
  return out;
}

std::vector<SubmittedArray> Store::submitted_arrays(std::optional<std::int64_t> study_id) {
  std::vector<SubmittedArray> out;
  Stmt sb = db_.prepare("SELECT substr(j.slurm_job_id, 1, instr(j.slurm_job_id, '_') - 1), "
                        "count(*), min(j.updated_at) FROM jobs j WHERE j.state='submitted'" +
                        job_of_study(study_id) + " GROUP BY 1 ORDER BY 3");
  if (study_id)
    sb.bind(1, *study_id);
  while (sb.step())
    out.push_back({sb.text(0), sb.integer(1), sb.real(2)});
  return out;
}

std::vector<AttemptError> Store::last_errors(std::optional<std::int64_t> study_id, int limit) {
  std::vector<AttemptError> out;
  Stmt e = db_.prepare("SELECT j.key, a.attempt, a.state, a.finished_at, a.error_text, "
                       "coalesce(a.failure_class, a.state), j.state FROM "
                       "attempts a JOIN jobs j ON j.id=a.job_id WHERE a.state IN "
                       "('failed','timeout','abandoned','interrupted') AND a.error_text IS NOT "
                       "NULL" +
                       job_of_study(study_id) + " ORDER BY a.finished_at DESC LIMIT ?2");
  if (study_id)
    e.bind(1, *study_id);
  e.bind(2, limit);
  while (e.step()) {
    AttemptError a;
    a.key = e.text(0);
    a.attempt = e.integer(1);
    a.attempt_state = e.text(2);
    a.finished_at = e.real(3);
    a.error_text = e.text(4);
    a.failure_class = e.text(5);
    a.job_state = job_state_from(e.text(6));
    out.push_back(std::move(a));
  }
  return out;
}

std::vector<StudyJob> Store::study_jobs(std::int64_t study_id,
                                        const std::optional<std::string>& tier, bool current_only,
                                        const std::string& fingerprint) {
  std::vector<StudyJob> out;
  const std::string member =
      std::string(current_only ? " AND current" : "") + (tier ? " AND tier=?3" : "");
  Stmt q = db_.prepare(
      "SELECT j.id, j.key, j.state, j.scheme, j.params_json, j.output_dir, " +
      stale_sql(db_, "j.id", "j.state", "?2") +
      ", (SELECT group_concat(tier, ';') FROM (SELECT DISTINCT t.tier FROM study_jobs t WHERE "
      "t.study_id=?1 AND t.job_id=j.id AND t.current ORDER BY t.tier)) FROM jobs j JOIN "
      "(SELECT job_id, min(ordinal) AS o FROM study_jobs WHERE study_id=?1" +
      member + " GROUP BY job_id) sj ON sj.job_id=j.id ORDER BY sj.o");
  q.bind(1, study_id).bind(2, fingerprint);
  if (tier)
    q.bind(3, *tier);
  while (q.step()) {
    StudyJob j;
    j.id = q.integer(0);
    j.key = q.text(1);
    j.state = job_state_from(q.text(2));
    j.scheme = q.text(3);
    j.params_json = q.text(4);
    j.output_dir = q.is_null(5) ? "" : job_folder(q.text(5));
    j.stale = q.integer(6) != 0;
    std::string tiers = q.is_null(7) ? "" : q.text(7);
    for (std::size_t a = 0; a < tiers.size();) {
      std::size_t b = tiers.find(';', a);
      if (b == std::string::npos)
        b = tiers.size();
      j.tiers.push_back(tiers.substr(a, b - a));
      a = b + 1;
    }
    out.push_back(std::move(j));
  }
  return out;
}

std::string Store::job_folder(const std::string& recorded) const {
  const fs::path p(recorded);
  if (p.empty() || p.is_absolute())
    return recorded;
  const fs::path base = path_.parent_path().empty() ? fs::path(".") : path_.parent_path();
  return (base / p.parent_path().filename() / p.filename()).string();
}

std::vector<MetricValue> Store::study_metrics(std::int64_t study_id) {
  std::vector<MetricValue> out;
  Stmt m = db_.prepare("SELECT m.job_id, m.name, m.value FROM metrics m WHERE m.job_id IN "
                       "(SELECT job_id FROM study_jobs WHERE study_id=?) ORDER BY m.job_id, "
                       "m.ordinal");
  m.bind(1, study_id);
  while (m.step())
    out.push_back({m.integer(0), m.text(1), m.opt_real(2)});
  return out;
}

std::map<std::int64_t, std::string> Store::metric_code_versions(std::int64_t study_id) {
  Stmt q = db_.prepare("SELECT DISTINCT m.job_id, a.code_version FROM metrics m JOIN attempts a ON "
                       "a.job_id=m.job_id AND a.attempt=m.attempt WHERE m.job_id IN (SELECT "
                       "job_id FROM study_jobs WHERE study_id=?)");
  q.bind(1, study_id);
  std::map<std::int64_t, std::string> out;
  while (q.step())
    out[q.integer(0)] = q.text(1);
  return out;
}

std::vector<std::string> Store::metric_names(std::int64_t study_id) {
  Stmt m = db_.prepare("SELECT DISTINCT m.name FROM metrics m JOIN study_jobs sj ON "
                       "sj.job_id=m.job_id WHERE sj.study_id=? ORDER BY 1");
  m.bind(1, study_id);
  std::vector<std::string> names;
  while (m.step())
    names.push_back(m.text(0));
  return names;
}

std::vector<std::string> Store::param_names(std::int64_t study_id) {
  std::vector<std::string> names;
  Stmt n = db_.prepare("SELECT DISTINCT name FROM job_params WHERE job_id IN (SELECT job_id "
                       "FROM study_jobs WHERE study_id=?) ORDER BY 1");
  n.bind(1, study_id);
  while (n.step())
    names.push_back(n.text(0));
  return names;
}

bool Store::has_param(std::int64_t study_id, const std::string& name) {
  Stmt k = db_.prepare("SELECT 1 FROM job_params p WHERE p.name=? AND EXISTS (SELECT 1 FROM "
                       "study_jobs sj WHERE sj.job_id=p.job_id AND sj.study_id=?) LIMIT 1");
  k.bind(1, name).bind(2, study_id);
  return k.step();
}

std::size_t Store::stale_in_study(std::int64_t study_id, const std::string& fingerprint,
                                  const std::optional<std::string>& tier, bool current_only) {
  Stmt c = db_.prepare("SELECT count(DISTINCT j.id) FROM jobs j JOIN study_jobs sj ON "
                       "sj.job_id=j.id AND sj.study_id=?1" +
                       std::string(tier ? " AND sj.tier=?3" : "") +
                       (current_only ? " AND sj.current" : "") + " WHERE " +
                       stale_sql(db_, "j.id", "j.state", "?2"));
  c.bind(1, study_id).bind(2, fingerprint);
  if (tier)
    c.bind(3, *tier);
  return c.step() ? static_cast<std::size_t>(c.integer(0)) : 0;
}

namespace {

Stmt& bind_value(Stmt& s, int i, const WhereValue& b) {
  if (std::holds_alternative<double>(b))
    return s.bind(i, std::get<double>(b));
  if (std::holds_alternative<std::int64_t>(b))
    return s.bind(i, std::get<std::int64_t>(b));
  return s.bind(i, std::get<std::string>(b));
}

SqlCell sql_cell(const Stmt& s, int i) {
  SqlCell c;
  c.type = s.type(i);
  if (c.type == SQLITE_INTEGER)
    c.integer = s.integer(i), c.real = s.real(i);
  else if (c.type == SQLITE_FLOAT)
    c.real = s.real(i);
  else if (c.type != SQLITE_NULL)
    c.text = s.text(i);
  return c;
}

// A subquery `SELECT ... AS id` of the distinct jobs of study `sid` (current expansion) matching
// the filter's parameters; appends the values of its placeholders, in order, to `binds`. The set
// is read from the job_params index, starting from the filter that matches the fewest jobs
// (counted first, on the covering index), so that a filtered pivot of a 100,000-job study touches
// only the jobs it shows.
std::string selected_jobs(Db& db, std::int64_t sid, const JobFilter& f,
                          std::vector<WhereValue>& binds) {
  if (f.params.empty()) {
    binds.emplace_back(sid);
    return "SELECT DISTINCT job_id AS id FROM study_jobs WHERE study_id=? AND current";
  }
  // Most selective first: it drives the join, the others are primary-key look-ups.
  std::vector<std::pair<std::int64_t, std::size_t>> order;
  for (std::size_t i = 0; i < f.params.size(); ++i) {
    Stmt c = db.prepare("SELECT count(*) FROM job_params WHERE name=? AND value=?");
    c.bind(1, f.params[i].first);
    bind_value(c, 2, f.params[i].second);
    c.step();
    order.emplace_back(c.integer(0), i);
  }
  std::sort(order.begin(), order.end());
  std::string from = "job_params f0", cond;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const auto& [name, value] = f.params[order[k].second];
    std::string a = "f";
    a += std::to_string(k);
    if (k > 0) {
      from += " CROSS JOIN job_params ";
      from += a;
      cond += " AND " + a + ".job_id=f0.job_id AND ";
    }
    cond += a + ".name=? AND " + a + ".value=?";
    binds.emplace_back(name);
    binds.push_back(value);
  }
  binds.emplace_back(sid);
  return "SELECT f0.job_id AS id FROM " + from + " WHERE " + cond +
         " AND EXISTS (SELECT 1 FROM study_jobs sj WHERE sj.job_id=f0.job_id AND sj.study_id=? "
         "AND sj.current)";
}

std::string safe_param_name(const std::string& param) {
  for (char c : param)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_')
      throw std::runtime_error("bad parameter name '" + param + "'");
  return param;
}

} // namespace

namespace {

// SQL of a pivot row parameter (or "scheme") of job j.
std::string pivot_param_expr(const std::string& p) {
  return p == "scheme" ? std::string("j.scheme")
                       : "(SELECT value FROM job_params WHERE job_id=j.id AND name='" +
                             safe_param_name(p) + "')";
}

} // namespace

// SELECT <columns> over the metric `metric` of the study's jobs passing the filter, <tail> after
// the WHERE clause; prepared and bound. CROSS JOIN keeps SQLite's join order: the selected jobs
// drive, the rest are look-ups.
Stmt Store::prepare_pivot(std::int64_t study_id, const std::string& columns,
                          const std::string& metric, const JobFilter& filter,
                          const std::string& tail) {
  std::vector<WhereValue> binds;
  std::string sel = selected_jobs(db_, study_id, filter, binds);
  std::string scheme_cond;
  for (const auto& sc : filter.schemes) {
    scheme_cond += " AND j.scheme = ?";
    binds.emplace_back(sc);
  }
  Stmt q = db_.prepare("SELECT " + columns + " FROM (" + sel +
                       ") sel CROSS JOIN jobs j CROSS JOIN metrics m "
                       "WHERE j.id=sel.id AND m.job_id=sel.id AND m.name=?" +
                       scheme_cond + " " + tail);
  int i = 1;
  for (std::size_t k = 0; k + filter.schemes.size() < binds.size(); ++k)
    bind_value(q, i++, binds[k]);
  q.bind(i++, metric);
  for (std::size_t k = binds.size() - filter.schemes.size(); k < binds.size(); ++k)
    bind_value(q, i++, binds[k]);
  return q;
}

std::vector<PivotCell> Store::pivot(std::int64_t study_id, const std::string& rows,
                                    const std::string& cols, const std::string& metric,
                                    const std::string& agg, const JobFilter& filter) {
  if (agg != "avg" && agg != "min" && agg != "max" && agg != "count")
    throw std::runtime_error("bad aggregate '" + agg + "'");
  Stmt q = prepare_pivot(
      study_id, pivot_param_expr(rows) + ", " + pivot_param_expr(cols) + ", " + agg + "(m.value)",
      metric, filter, "GROUP BY 1, 2 ORDER BY 1, 2");
  std::vector<PivotCell> out;
  while (q.step())
    out.push_back({sql_cell(q, 0), sql_cell(q, 1), q.opt_real(2)});
  return out;
}

std::vector<PivotMember> Store::pivot_members(std::int64_t study_id, const std::string& rows,
                                              const std::string& cols, const std::string& metric,
                                              const JobFilter& filter) {
  Stmt q = prepare_pivot(study_id,
                         pivot_param_expr(rows) + ", " + pivot_param_expr(cols) +
                             ", m.value, j.params_json, (SELECT min(ordinal) FROM study_jobs "
                             "WHERE job_id=j.id AND study_id=" +
                             std::to_string(study_id) + " AND current)",
                         metric, filter, "AND m.value IS NOT NULL ORDER BY 1, 2, j.id");
  std::vector<PivotMember> out;
  while (q.step())
    out.push_back(
        {sql_cell(q, 0), sql_cell(q, 1), q.real(2), q.text(3), q.is_null(4) ? 0 : q.integer(4)});
  return out;
}

namespace {

bool only_space(const char* p) {
  for (; p && *p; ++p)
    if (!std::isspace(static_cast<unsigned char>(*p)))
      return false;
  return true;
}

// The authorizer of `runner query`: reads only. Denies every write, schema change, transaction
// control, ATTACH/DETACH, and any PRAGMA that sets a value (PRAGMA x = y, or x(y) other than the
// table-valued read pragmas). Together with sqlite3_stmt_readonly() (which is false for VACUUM,
// VACUUM INTO, wal_checkpoint and journal_mode changes) the statement cannot change a file.
int query_authorizer(void* denied, int action, const char* a, const char* b, const char*,
                     const char*) {
  auto deny = [&](const std::string& what) {
    auto* d = static_cast<std::string*>(denied);
    if (d->empty())
      *d = what;
    return SQLITE_DENY;
  };
  switch (action) {
  case SQLITE_SELECT:
  case SQLITE_READ:
  case SQLITE_FUNCTION:
  case SQLITE_RECURSIVE:
    return SQLITE_OK;
  case SQLITE_PRAGMA: {
    static const std::set<std::string> with_argument = {
        "table_info",     "table_xinfo",      "index_info",        "index_xinfo",
        "index_list",     "foreign_key_list", "foreign_key_check", "integrity_check",
        "quick_check",    "table_list",       "function_list",     "pragma_list",
        "collation_list", "database_list",    "compile_options"};
    std::string name = a ? a : "";
    for (auto& c : name)
      c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (!b || with_argument.count(name))
      return SQLITE_OK;
    return deny("PRAGMA " + name + " with a value");
  }
  case SQLITE_ATTACH:
    return deny("ATTACH");
  case SQLITE_DETACH:
    return deny("DETACH");
  case SQLITE_TRANSACTION:
  case SQLITE_SAVEPOINT:
    return deny("transaction control");
  default:
    return deny("a statement that writes");
  }
}

} // namespace

void Store::set_deadline(double seconds) {
  if (!(seconds > 0)) {
    sqlite3_progress_handler(db_.handle(), 0, nullptr, nullptr);
    deadline_.reset();
    return;
  }
  deadline_ = std::make_unique<Deadline>();
  deadline_->at = std::chrono::steady_clock::now() +
                  std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                      std::chrono::duration<double>(seconds));
  sqlite3_progress_handler(
      db_.handle(), 10000,
      [](void* p) -> int {
        auto* d = static_cast<Deadline*>(p);
        d->passed = d->passed || std::chrono::steady_clock::now() >= d->at;
        return d->passed ? 1 : 0;
      },
      deadline_.get());
}

bool Store::deadline_passed() const {
  return deadline_ && deadline_->passed;
}

Stmt Store::prepare_read_query(const std::string& sql) {
  std::string denied;
  sqlite3* h = db_.handle();
  sqlite3_stmt* raw = nullptr;
  const char* tail = nullptr;
  const char* query_only =
      "runner query only reads: write with the sqlite3 shell on a copy, or through the runner";
  sqlite3_set_authorizer(h, query_authorizer, &denied);
  int rc = sqlite3_prepare_v2(h, sql.c_str(), -1, &raw, &tail);
  if (rc != SQLITE_OK) {
    if (!denied.empty())
      throw std::runtime_error("refused: " + denied + " is not allowed; " + query_only);
    throw std::runtime_error(std::string("SQL error: ") + sqlite3_errmsg(h));
  }
  if (!raw)
    throw std::runtime_error("runner query: the SQL statement is empty; e.g. runner query "
                             "\"SELECT * FROM job_metrics LIMIT 10\"");
  const bool readonly = sqlite3_stmt_readonly(raw) != 0;
  sqlite3_finalize(raw);
  if (!readonly)
    throw std::runtime_error("refused: the statement would change the database or write a file "
                             "(VACUUM, checkpoints, journal mode...); " +
                             std::string(query_only));
  if (!only_space(tail))
    throw std::runtime_error("runner query runs one SQL statement; remove what follows '" +
                             sql.substr(0, static_cast<std::size_t>(tail - sql.c_str())) + "'");
  return db_.prepare(sql);
}

std::int64_t Store::create_submission(std::int64_t study_id, const std::string& tier,
                                      std::size_t n_jobs, std::size_t n_tasks, double now,
                                      const std::function<fs::path(std::int64_t)>& dir_of) {
  WriteTx tx(db_);
  Stmt i = db_.prepare("INSERT INTO slurm_submissions(study_id, tier, manifest, dir, "
                       "n_jobs, n_tasks, submitted_at) VALUES(?,?,'','',?,?,?)");
  i.bind(1, study_id).bind(2, tier).bind(3, static_cast<std::int64_t>(n_jobs));
  i.bind(4, static_cast<std::int64_t>(n_tasks)).bind(5, now).run();
  const std::int64_t id = sqlite3_last_insert_rowid(db_.handle());
  const fs::path dir = dir_of(id);
  Stmt u = db_.prepare("UPDATE slurm_submissions SET manifest=?, dir=? WHERE id=?");
  u.bind(1, (dir / "manifest.json").string()).bind(2, dir.string()).bind(3, id).run();
  tx.commit();
  return id;
}

std::vector<std::pair<std::int64_t, int>>
Store::mark_submitted(const std::vector<std::int64_t>& ids, const AttemptStart& a,
                      std::int64_t submission,
                      const std::function<void(std::size_t, int)>& on_marked,
                      const std::function<std::size_t()>& before_commit) {
  std::vector<std::pair<std::int64_t, int>> marked;
  WriteTx tx(db_);
  Stmt u = db_.prepare(
      "UPDATE jobs SET state='submitted', attempts=attempts+1, owner_host=?, owner_pid=?, "
      "heartbeat_at=?, updated_at=?, progress=NULL, slurm_job_id=NULL WHERE id=? AND "
      "state='pending' RETURNING attempts");
  Stmt i = db_.prepare(
      "INSERT INTO attempts(job_id, attempt, state, started_at, host, pid, threads, "
      "code_version, compiler, solver_fingerprint) VALUES(?,?,'running',?,'slurm',?,?,?,?,?)");
  for (std::size_t k = 0; k < ids.size(); ++k) {
    u.bind(1, a.host).bind(2, a.pid).bind(3, a.started_at).bind(4, a.started_at).bind(5, ids[k]);
    if (!u.step()) {
      u.reset();
      continue;
    }
    int attempt = static_cast<int>(u.integer(0));
    u.reset();
    i.bind(1, ids[k]).bind(2, attempt).bind(3, a.started_at).bind(4, a.pid).bind(5, a.threads);
    i.bind(6, a.code_version).bind(7, a.compiler).bind(8, a.solver_fingerprint).run();
    on_marked(k, attempt);
    marked.emplace_back(ids[k], attempt);
  }
  const std::size_t n_tasks = before_commit();
  Stmt n = db_.prepare("UPDATE slurm_submissions SET n_jobs=?, n_tasks=? WHERE id=?");
  n.bind(1, static_cast<std::int64_t>(marked.size()));
  n.bind(2, static_cast<std::int64_t>(n_tasks)).bind(3, submission).run();
  tx.commit();
  return marked;
}

void Store::give_back_submitted(const std::vector<std::pair<std::int64_t, int>>& jobs,
                                const std::string& reason, double now) {
  WriteTx tx(db_);
  Stmt u = to_pending("id=?2 AND state='submitted' AND attempts=?3");
  Stmt a = end_attempt("job_id=?5 AND attempt=?6");
  for (const auto& [id, attempt] : jobs) {
    u.bind(1, now).bind(2, id).bind(3, attempt).run();
    a.bind(1, "interrupted").bind(2, "submit").bind(3, now).bind(4, reason);
    a.bind(5, id).bind(6, attempt).run();
  }
  tx.commit();
}

void Store::record_array(std::int64_t submission, const std::string& array_id,
                         const std::vector<std::pair<std::int64_t, int>>& jobs,
                         const std::vector<std::size_t>& tasks) {
  WriteTx tx(db_);
  Stmt s = db_.prepare("UPDATE slurm_submissions SET slurm_job_id=? WHERE id=?");
  s.bind(1, array_id).bind(2, submission).run();
  Stmt u = db_.prepare("UPDATE jobs SET slurm_job_id=? WHERE id=? AND attempts=?");
  Stmt a = db_.prepare("UPDATE attempts SET slurm_job_id=? WHERE job_id=? AND attempt=?");
  for (std::size_t k = 0; k < jobs.size() && k < tasks.size(); ++k) {
    std::string sid = array_id + "_" + std::to_string(tasks[k]);
    u.bind(1, sid).bind(2, jobs[k].first).bind(3, jobs[k].second).run();
    a.bind(1, sid).bind(2, jobs[k].first).bind(3, jobs[k].second).run();
  }
  tx.commit();
}

std::size_t Store::count_submitted_in_array(const std::string& array_id) {
  Stmt q = db_.prepare("SELECT count(*) FROM jobs WHERE state='submitted' AND slurm_job_id LIKE "
                       "? || '\\_%' ESCAPE '\\'");
  q.bind(1, array_id);
  return q.step() ? static_cast<std::size_t>(q.integer(0)) : 0;
}

std::size_t Store::requeue_orphan_submissions(const std::string& host, int self_pid, double now,
                                              const std::function<bool(int)>& pid_alive) {
  // The submitter is known dead when it ran on this host and its pid is gone; from another host,
  // after an hour.
  std::vector<std::pair<std::int64_t, int>> orphans;
  {
    Stmt q = db_.prepare("SELECT id, attempts, owner_host, owner_pid, updated_at FROM jobs "
                         "WHERE state='submitted' AND slurm_job_id IS NULL");
    while (q.step()) {
      bool dead = q.text(2) == host && !q.is_null(3) &&
                  static_cast<int>(q.integer(3)) != self_pid &&
                  !pid_alive(static_cast<int>(q.integer(3)));
      if (dead || now - q.real(4) > 3600)
        orphans.emplace_back(q.integer(0), static_cast<int>(q.integer(1)));
    }
  }
  if (orphans.empty())
    return 0;
  WriteTx tx(db_);
  Stmt u = to_pending("id=?2 AND state='submitted' AND slurm_job_id IS NULL AND attempts=?3");
  Stmt a = end_attempt("job_id=?5 AND attempt=?6 AND state='running'");
  for (const auto& [id, attempt] : orphans) {
    u.bind(1, now).bind(2, id).bind(3, attempt).run();
    a.bind(1, "abandoned").bind(2, "stale").bind(3, now);
    a.bind(4, "abandoned: the runner submitting this job died before sbatch returned");
    a.bind(5, id).bind(6, attempt).run();
  }
  tx.commit();
  return orphans.size();
}

std::vector<Submission> Store::open_submissions() {
  std::vector<Submission> subs;
  Stmt q =
      db_.prepare("SELECT s.id, coalesce(s.slurm_job_id, ''), s.dir FROM slurm_submissions s WHERE "
                  "EXISTS (SELECT 1 FROM jobs j WHERE j.state='submitted' AND j.slurm_job_id LIKE "
                  "s.slurm_job_id || '\\_%' ESCAPE '\\')");
  while (q.step())
    subs.push_back({q.integer(0), q.text(1), q.text(2)});
  return subs;
}

std::vector<SubmittedJob> Store::submitted_jobs_of_array(const std::string& array_id) {
  std::vector<SubmittedJob> js;
  Stmt jobs = db_.prepare("SELECT id, key, attempts, slurm_job_id, params_json FROM jobs WHERE "
                          "state='submitted' "
                          "AND slurm_job_id LIKE ? || '\\_%' ESCAPE '\\'");
  jobs.bind(1, array_id);
  while (jobs.step())
    js.push_back({jobs.integer(0), jobs.text(1), jobs.text(3), static_cast<int>(jobs.integer(2)),
                  jobs.text(4)});
  return js;
}

std::optional<std::string> Store::a_study_of_job(std::int64_t job_id) {
  Stmt od = db_.prepare("SELECT s.name FROM study_jobs sj JOIN studies s ON "
                        "s.id=sj.study_id WHERE sj.job_id=? LIMIT 1");
  od.bind(1, job_id);
  if (od.step())
    return od.text(0);
  return std::nullopt;
}

void Store::requeue_lost(const std::vector<std::pair<std::int64_t, int>>& jobs,
                         const std::string& reason, double now) {
  if (jobs.empty())
    return;
  WriteTx tx(db_);
  Stmt u = to_pending("id=?2 AND state='submitted' AND attempts=?3");
  Stmt a = end_attempt("job_id=?5 AND attempt=?6");
  for (const auto& [id, attempt] : jobs) {
    u.bind(1, now).bind(2, id).bind(3, attempt).run();
    a.bind(1, "abandoned").bind(2, "stale").bind(3, now).bind(4, reason);
    a.bind(5, id).bind(6, attempt).run();
  }
  tx.commit();
}

} // namespace sph::runner
