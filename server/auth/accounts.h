// Who may use the robot: users (Argon2id password hashes), browser sessions and API tokens (kept as digests), and the
// audit log of every write. SQLite, <state_dir>/accounts.db, readable only by the daemon's user.
// Thread-safe: one connection behind a mutex.
#pragma once

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "server/store/sqlite.h"

namespace corridor::server::auth {

// What a caller may do; each role may do everything the ones before it may.
enum class Role { kViewer = 1, kOperator = 2, kAdmin = 3 };
std::string_view ToString(Role role);
std::optional<Role> RoleFromString(std::string_view name);

// Who is calling: a user (through a session), an API token, or nobody.
struct Principal {
  std::string name;  // the username, or the token's name
  Role role = Role::kViewer;
  std::string kind;      // "user", "token" or "system" (in-process tools)
  std::string token_id;  // for tokens
};

// A request to change the accounts that cannot be done; what() says why.
class AccountError : public std::runtime_error {
 public:
  enum class Kind {
    kInvalid,   // a malformed name, a password too short or too long
    kConflict,  // a taken name, the last admin
  };
  AccountError(Kind kind, const std::string& what) : std::runtime_error(what), kind_(kind) {}
  Kind kind() const { return kind_; }

 private:
  Kind kind_;
};

struct UserRecord {
  std::string username;
  Role role = Role::kViewer;
  std::string created;  // ISO 8601, UTC
};

struct TokenRecord {
  std::string id;
  std::string name;
  Role role = Role::kViewer;
  std::string created;
  std::string created_by;
  std::string last_used;  // empty: never
};

struct AuditRecord {
  std::string who;     // "alice", "token:fleet", "anonymous"
  std::string client;  // the caller's address
  std::string method;
  std::string path;
  int status = 0;
  std::string detail;  // e.g. the id of what was created
};

// Which audit records to read: numbered above `after` and below `before` (0: no bound), by `who` (exactly; empty:
// anyone), with `path_contains` in their path (empty: any), only those that failed (status 400 or more); the newest
// `limit` of them.
struct AuditQuery {
  std::int64_t after = 0;
  std::int64_t before = 0;
  std::string who{};
  std::string path_contains{};
  bool failed_only = false;
  int limit = 256;
};

nlohmann::json ToJson(const UserRecord& user);
nlohmann::json ToJson(const TokenRecord& token);

class Accounts {
 public:
  // Opens or creates the database (mode 0600). Throws StoreError.
  explicit Accounts(const std::filesystem::path& file);

  bool HasUsers() const;
  // Throws AccountError for an invalid or taken name, or a password shorter than 8 or longer than 256 characters.
  UserRecord AddUser(const std::string& username, const std::string& password, Role role);
  std::vector<UserRecord> Users() const;
  // Deletes the user and their sessions; false when there was none. Throws AccountError for the last admin.
  bool DeleteUser(const std::string& username);
  // The user when the password is theirs. Takes as long for an unknown user as for a wrong password.
  std::optional<Principal> CheckPassword(const std::string& username, const std::string& password) const;

  // A new session for `user`, valid for `lifetime` after its last use; returns its id (the cookie's value).
  std::string OpenSession(const std::string& username, std::chrono::seconds lifetime);
  // The session's user while it is valid (and extends it); nullopt for an unknown or expired session.
  std::optional<Principal> Session(const std::string& id);
  void CloseSession(const std::string& id);

  // A new token; returns its record and the secret, which is shown once and kept only as a digest.
  std::pair<TokenRecord, std::string> CreateToken(const std::string& name, Role role, const std::string& created_by);
  // The token's principal when `secret` is a valid, unrevoked token (and records its use).
  std::optional<Principal> Token(const std::string& secret);
  bool RevokeToken(const std::string& id);
  std::vector<TokenRecord> Tokens() const;

  // Appends to the audit log and forgets all but the newest `keep` records.
  void Audit(const AuditRecord& record, int keep = 100000);
  // The records `query` asks for, oldest first.
  std::vector<nlohmann::json> AuditLog(const AuditQuery& query) const;

 private:
  mutable std::mutex mutex_;
  Database db_;
};

}  // namespace corridor::server::auth
