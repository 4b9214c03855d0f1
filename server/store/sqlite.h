// A thin layer over SQLite's C API shared by the robot's databases (store.h, server/auth/accounts.h): a connection
// that opens in WAL mode with full sync, and prepared statements that finalize themselves.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>

struct sqlite3;
struct sqlite3_stmt;

namespace corridor::server {

// The database cannot be opened, read or written; what() says what and where.
class StoreError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Database {
 public:
  // Opens or creates `file` and runs `schema` (CREATE ... IF NOT EXISTS statements). Throws StoreError naming the file.
  Database(const std::filesystem::path& file, const std::string& schema);
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;
  ~Database();

  void Exec(const std::string& sql) const;
  sqlite3* handle() const { return db_; }

 private:
  sqlite3* db_ = nullptr;
};

// A prepared statement that finalizes itself.
class Statement {
 public:
  Statement(const Database& db, const char* sql);
  ~Statement();
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  Statement& Bind(int index, const std::string& text);
  Statement& Bind(int index, int value);
  Statement& Bind(int index, std::int64_t value);
  Statement& Bind(int index, double value);
  // True while rows come; false at the end. Throws StoreError.
  bool Step();
  std::string Text(int column) const;
  double Double(int column) const;
  int Int(int column) const;
  std::int64_t Int64(int column) const;
  int changes() const;

 private:
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
};

// Runs `work` between BEGIN and COMMIT, rolling back when it throws.
template <typename Work>
void InTransaction(const Database& db, Work&& work) {
  db.Exec("BEGIN");
  try {
    work();
    db.Exec("COMMIT");
  } catch (...) {
    db.Exec("ROLLBACK");
    throw;
  }
}

}  // namespace corridor::server
