#include "server/store/sqlite.h"

#include <sqlite3.h>

namespace corridor::server {

Database::Database(const std::filesystem::path& file, const std::string& schema) {
  if (sqlite3_open(file.c_str(), &db_) != SQLITE_OK) {
    const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    throw StoreError("database " + file.string() + ": cannot be opened: " + why);
  }
  sqlite3_busy_timeout(db_, 2000);
  try {
    // WAL: readers never wait for the writer; synchronous=FULL: a committed write survives a power cut.
    Exec("PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL;");
    Exec(schema);
  } catch (const StoreError& e) {
    sqlite3_close(db_);
    throw StoreError("database " + file.string() + ": " + e.what() + " (is it a corridor database?)");
  }
}

Database::~Database() { sqlite3_close(db_); }

void Database::Exec(const std::string& sql) const {
  char* error = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
    const std::string why = error ? error : "unknown error";
    sqlite3_free(error);
    throw StoreError(why);
  }
}

Statement::Statement(const Database& db, const char* sql) : db_(db.handle()) {
  if (sqlite3_prepare_v2(db_, sql, -1, &stmt_, nullptr) != SQLITE_OK) {
    throw StoreError(std::string("database: cannot prepare '") + sql + "': " + sqlite3_errmsg(db_));
  }
}

Statement::~Statement() { sqlite3_finalize(stmt_); }

Statement& Statement::Bind(int index, const std::string& text) {
  sqlite3_bind_text(stmt_, index, text.c_str(), static_cast<int>(text.size()), SQLITE_TRANSIENT);
  return *this;
}

Statement& Statement::Bind(int index, int value) {
  sqlite3_bind_int(stmt_, index, value);
  return *this;
}

Statement& Statement::Bind(int index, std::int64_t value) {
  sqlite3_bind_int64(stmt_, index, value);
  return *this;
}

Statement& Statement::Bind(int index, double value) {
  sqlite3_bind_double(stmt_, index, value);
  return *this;
}

bool Statement::Step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  throw StoreError(std::string("database: ") + sqlite3_errmsg(db_));
}

std::string Statement::Text(int column) const {
  const auto* p = sqlite3_column_text(stmt_, column);
  return p ? reinterpret_cast<const char*>(p) : "";
}

double Statement::Double(int column) const { return sqlite3_column_double(stmt_, column); }
int Statement::Int(int column) const { return sqlite3_column_int(stmt_, column); }
std::int64_t Statement::Int64(int column) const { return sqlite3_column_int64(stmt_, column); }
int Statement::changes() const { return sqlite3_changes(db_); }

}  // namespace corridor::server
