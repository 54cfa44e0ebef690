// RAII wrappers over the SQLite C API.
#include "sqlite.hpp"

#include <unistd.h>

#include <chrono>
#include <random>
#include <thread>

namespace sph::runner {

namespace {
[[noreturn]] void fail(sqlite3* db, int rc, const std::string& context) {
  std::string msg = context + ": " + (db ? sqlite3_errmsg(db) : sqlite3_errstr(rc));
  throw SqliteError(msg, rc);
}
} // namespace

Stmt::Stmt(sqlite3* db, const std::string& sql) : db_(db) {
  int rc = sqlite3_prepare_v2(db, sql.c_str(), static_cast<int>(sql.size()), &s_, nullptr);
  if (rc != SQLITE_OK)
    fail(db, rc, "SQL error in \"" + sql + "\"");
}

Stmt& Stmt::operator=(Stmt&& o) noexcept {
  if (this != &o) {
    sqlite3_finalize(s_);
    db_ = o.db_;
    s_ = o.s_;
    o.s_ = nullptr;
  }
  return *this;
}

Stmt::~Stmt() {
  sqlite3_finalize(s_);
}

void Stmt::check(int rc) const {
  if (rc != SQLITE_OK)
    fail(db_, rc, "SQLite bind");
}

Stmt& Stmt::bind(int i, std::int64_t v) {
  check(sqlite3_bind_int64(s_, i, v));
  return *this;
}
Stmt& Stmt::bind(int i, double v) {
  check(sqlite3_bind_double(s_, i, v));
  return *this;
}
Stmt& Stmt::bind(int i, const std::string& v) {
  check(sqlite3_bind_text(s_, i, v.data(), static_cast<int>(v.size()), SQLITE_TRANSIENT));
  return *this;
}
Stmt& Stmt::bind_null(int i) {
  check(sqlite3_bind_null(s_, i));
  return *this;
}

bool Stmt::step() {
  int rc = sqlite3_step(s_);
  if (rc == SQLITE_ROW)
    return true;
  if (rc == SQLITE_DONE)
    return false;
  std::string sql = sqlite3_sql(s_) ? sqlite3_sql(s_) : "";
  sqlite3_reset(s_);
  fail(db_, rc, "SQL error in \"" + sql + "\"");
}

void Stmt::run() {
  while (step()) {
  }
  reset();
}

void Stmt::reset() {
  sqlite3_reset(s_);
  sqlite3_clear_bindings(s_);
}

std::string Stmt::text(int i) const {
  auto p = sqlite3_column_text(s_, i);
  if (!p)
    return {};
  return std::string(reinterpret_cast<const char*>(p),
                     static_cast<std::size_t>(sqlite3_column_bytes(s_, i)));
}

Db::Db(const std::string& path, int flags) {
  // SQLite's unix VFS opens its files with O_CLOEXEC, so job processes never inherit them.
  int rc = sqlite3_open_v2(path.c_str(), &db_, flags | SQLITE_OPEN_NOMUTEX, nullptr);
  if (rc != SQLITE_OK) {
    std::string msg =
        "cannot open database '" + path + "': " + (db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(rc));
    sqlite3_close(db_);
    db_ = nullptr;
    throw SqliteError(msg, rc);
  }
  sqlite3_extended_result_codes(db_, 1);
}

Db Db::reader(const std::string& path) {
  const bool writable = ::access(path.c_str(), W_OK) == 0;
  Db db(path, writable ? SQLITE_OPEN_READWRITE : SQLITE_OPEN_READONLY);
  db.exec("PRAGMA query_only=ON");
  return db;
}

Db& Db::operator=(Db&& o) noexcept {
  if (this != &o) {
    sqlite3_close_v2(db_);
    db_ = o.db_;
    o.db_ = nullptr;
  }
  return *this;
}

Db::~Db() {
  sqlite3_close_v2(db_);
}

void Db::exec(const std::string& sql) {
  char* err = nullptr;
  int rc = sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err);
  if (rc != SQLITE_OK) {
    std::string msg = err ? err : sqlite3_errstr(rc);
    sqlite3_free(err);
    throw SqliteError("SQL error: " + msg, rc);
  }
}

std::int64_t Db::scalar_int(const std::string& sql) {
  Stmt s(db_, sql);
  return s.step() ? s.integer(0) : 0;
}

WriteTx::WriteTx(Db& db) : db_(db) {
  // busy_timeout already waits inside BEGIN IMMEDIATE; this loop adds jittered retries on top.
  std::minstd_rand rng(std::random_device{}());
  for (int attempt = 0;; ++attempt) {
    try {
      db_.exec("BEGIN IMMEDIATE");
      return;
    } catch (const SqliteError& e) {
      if ((e.code() & 0xff) != SQLITE_BUSY || attempt >= 5)
        throw;
      std::this_thread::sleep_for(std::chrono::milliseconds(50 + rng() % 200));
    }
  }
}

WriteTx::~WriteTx() {
  if (!done_)
    sqlite3_exec(db_.handle(), "ROLLBACK", nullptr, nullptr, nullptr);
}

void WriteTx::commit() {
  db_.exec("COMMIT");
  done_ = true;
}

} // namespace sph::runner
