// Thin RAII wrappers over the SQLite C API: a connection, prepared statements with typed binding,
// and an IMMEDIATE write transaction that retries while another writer holds the lock.
#pragma once

#include <sqlite3.h>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

namespace sph::runner {

class SqliteError : public std::runtime_error {
public:
  SqliteError(const std::string& what, int code) : std::runtime_error(what), code_(code) {}
  int code() const { return code_; }

private:
  int code_;
};

class Stmt {
public:
  Stmt() = default;
  Stmt(sqlite3* db, const std::string& sql);
  Stmt(Stmt&& o) noexcept : db_(o.db_), s_(o.s_) { o.s_ = nullptr; }
  Stmt& operator=(Stmt&& o) noexcept;
  Stmt(const Stmt&) = delete;
  Stmt& operator=(const Stmt&) = delete;
  ~Stmt();

  // Binding (1-based), chainable. nullopt binds NULL.
  Stmt& bind(int i, std::int64_t v);
  Stmt& bind(int i, int v) { return bind(i, static_cast<std::int64_t>(v)); }
  Stmt& bind(int i, double v);
  Stmt& bind(int i, const std::string& v);
  Stmt& bind(int i, const char* v) { return bind(i, std::string(v)); }
  Stmt& bind_null(int i);
  template <class T>
  Stmt& bind(int i, const std::optional<T>& v) {
    return v ? bind(i, *v) : bind_null(i);
  }

  // true: a row is available; false: done.
  bool step();
  // Runs to completion (for statements without results) and resets.
  void run();
  void reset();

  int columns() const { return sqlite3_column_count(s_); }
  std::string column_name(int i) const { return sqlite3_column_name(s_, i); }
  int type(int i) const { return sqlite3_column_type(s_, i); }
  bool is_null(int i) const { return type(i) == SQLITE_NULL; }
  std::int64_t integer(int i) const { return sqlite3_column_int64(s_, i); }
  double real(int i) const { return sqlite3_column_double(s_, i); }
  std::string text(int i) const;
  std::optional<double> opt_real(int i) const {
    return is_null(i) ? std::nullopt : std::optional<double>(real(i));
  }
  sqlite3_stmt* handle() const { return s_; }

private:
  sqlite3* db_ = nullptr;
  sqlite3_stmt* s_ = nullptr;
  void check(int rc) const;
};

class Db {
public:
  Db() = default;
  // flags: SQLITE_OPEN_READONLY or SQLITE_OPEN_READWRITE|SQLITE_OPEN_CREATE (NOMUTEX is added:
  // a connection is used by one thread only).
  Db(const std::string& path, int flags);
  // A connection that only reads (PRAGMA query_only). It is opened read-write when the file is
  // writable: after a writer was killed (kill -9) the WAL index must be rebuilt by the next
  // connection, which a SQLITE_OPEN_READONLY one cannot do ("attempt to write a readonly
  // database"); a read-only file gets a read-only connection.
  static Db reader(const std::string& path);
  Db(Db&& o) noexcept : db_(o.db_) { o.db_ = nullptr; }
  Db& operator=(Db&& o) noexcept;
  Db(const Db&) = delete;
  Db& operator=(const Db&) = delete;
  ~Db();

  void exec(const std::string& sql);
  Stmt prepare(const std::string& sql) { return Stmt(db_, sql); }
  std::int64_t scalar_int(const std::string& sql);
  std::int64_t changes() const { return sqlite3_changes64(db_); }
  sqlite3* handle() const { return db_; }
  bool is_open() const { return db_ != nullptr; }

private:
  sqlite3* db_ = nullptr;
};

// BEGIN IMMEDIATE (retried with backoff while the database is busy); rolls back unless committed.
class WriteTx {
public:
  explicit WriteTx(Db& db);
  WriteTx(const WriteTx&) = delete;
  WriteTx& operator=(const WriteTx&) = delete;
  ~WriteTx();
  void commit();

private:
  Db& db_;
  bool done_ = false;
};

} // namespace sph::runner
