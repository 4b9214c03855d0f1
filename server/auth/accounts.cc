#include "server/auth/accounts.h"

#include <sqlite3.h>

#include <algorithm>

#include "server/auth/secrets.h"
#include "server/runtime/event_log.h"

namespace corridor::server::auth {
namespace {

using nlohmann::json;
using Clock = std::chrono::system_clock;

const char* const kSchema =
    "CREATE TABLE IF NOT EXISTS users (username TEXT PRIMARY KEY, password_hash TEXT NOT NULL, role TEXT NOT NULL,"
    " created TEXT NOT NULL);"
    "CREATE TABLE IF NOT EXISTS sessions (digest TEXT PRIMARY KEY, username TEXT NOT NULL, lifetime_s INTEGER NOT NULL,"
    " expires INTEGER NOT NULL);"
    "CREATE TABLE IF NOT EXISTS tokens (id TEXT PRIMARY KEY, digest TEXT NOT NULL UNIQUE, name TEXT NOT NULL,"
    " role TEXT NOT NULL, created TEXT NOT NULL, created_by TEXT NOT NULL, last_used TEXT NOT NULL);"
    "CREATE TABLE IF NOT EXISTS audit (seq INTEGER PRIMARY KEY AUTOINCREMENT, time TEXT NOT NULL, who TEXT NOT NULL,"
    " client TEXT NOT NULL, method TEXT NOT NULL, path TEXT NOT NULL, status INTEGER NOT NULL, detail TEXT NOT NULL);";

constexpr std::size_t kMinPassword = 8;
constexpr std::size_t kMaxPassword = 256;

std::int64_t UnixNow() {
  return std::chrono::duration_cast<std::chrono::seconds>(Clock::now().time_since_epoch()).count();
}
std::string Now() { return IsoUtc(Clock::now()); }

void CheckName(const std::string& name, const char* what) {
  const bool ok = !name.empty() && name.size() <= 64 && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-';
  });
  if (!ok)
    throw AccountError(AccountError::Kind::kInvalid,
                       std::string(what) + " must be 1 to 64 letters, digits, '.', '_' or '-'");
}

Role ReadRole(const std::string& text) { return RoleFromString(text).value_or(Role::kViewer); }

TokenRecord ReadToken(const Statement& s) {
  return {s.Text(0), s.Text(1), ReadRole(s.Text(2)), s.Text(3), s.Text(4), s.Text(5)};
}

}  // namespace

std::string_view ToString(Role role) {
  switch (role) {
    case Role::kViewer: return "viewer";
    case Role::kOperator: return "operator";
    case Role::kAdmin: return "admin";
  }
  return "viewer";
}

std::optional<Role> RoleFromString(std::string_view name) {
  for (Role r : {Role::kViewer, Role::kOperator, Role::kAdmin}) {
    if (ToString(r) == name) return r;
  }
  return std::nullopt;
}

json ToJson(const UserRecord& u) {
  return {{"username", u.username}, {"role", std::string(ToString(u.role))}, {"created", u.created}};
}

json ToJson(const TokenRecord& t) {
  return {{"id", t.id},
          {"name", t.name},
          {"role", std::string(ToString(t.role))},
          {"created", t.created},
          {"created_by", t.created_by},
          {"last_used", t.last_used.empty() ? json(nullptr) : json(t.last_used)}};
}

Accounts::Accounts(const std::filesystem::path& file) : db_(file, kSchema) {
  std::error_code ec;
  std::filesystem::permissions(file, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write, ec);
}

bool Accounts::HasUsers() const {
  std::lock_guard lock(mutex_);
  Statement s(db_, "SELECT 1 FROM users LIMIT 1");
  return s.Step();
}

UserRecord Accounts::AddUser(const std::string& username, const std::string& password, Role role) {
  CheckName(username, "username");
  if (password.size() < kMinPassword || password.size() > kMaxPassword) {
    throw AccountError(AccountError::Kind::kInvalid, "password must be 8 to 256 characters long");
  }
  const std::string hash = HashPassword(password);  // outside the lock: it takes tens of milliseconds
  std::lock_guard lock(mutex_);
  Statement exists(db_, "SELECT 1 FROM users WHERE username = ?");
  exists.Bind(1, username);
  if (exists.Step()) throw AccountError(AccountError::Kind::kConflict, "user '" + username + "' already exists");
  UserRecord user{username, role, Now()};
  Statement s(db_, "INSERT INTO users (username, password_hash, role, created) VALUES (?,?,?,?)");
  s.Bind(1, username).Bind(2, hash).Bind(3, std::string(ToString(role))).Bind(4, user.created);
  s.Step();
  return user;
}

std::vector<UserRecord> Accounts::Users() const {
  std::lock_guard lock(mutex_);
  Statement s(db_, "SELECT username, role, created FROM users ORDER BY username");
  std::vector<UserRecord> out;
  while (s.Step()) out.push_back({s.Text(0), ReadRole(s.Text(1)), s.Text(2)});
  return out;
}

bool Accounts::DeleteUser(const std::string& username) {
  std::lock_guard lock(mutex_);
  bool deleted = false;
  InTransaction(db_, [&] {
    Statement admins(db_, "SELECT COUNT(*) FROM users WHERE role = 'admin' AND username != ?");
    admins.Bind(1, username);
    admins.Step();
    Statement role(db_, "SELECT role FROM users WHERE username = ?");
    role.Bind(1, username);
    if (role.Step() && role.Text(0) == "admin" && admins.Int(0) == 0) {
      throw AccountError(AccountError::Kind::kConflict,
                         "'" + username + "' is the last admin; make another admin first");
    }
    Statement sessions(db_, "DELETE FROM sessions WHERE username = ?");
    sessions.Bind(1, username);
    sessions.Step();
    Statement s(db_, "DELETE FROM users WHERE username = ?");
    s.Bind(1, username);
    s.Step();
    deleted = s.changes() > 0;
  });
  return deleted;
}

std::optional<Principal> Accounts::CheckPassword(const std::string& username, const std::string& password) const {
  std::optional<std::pair<std::string, std::string>> user;  // hash, role
  {
    std::lock_guard lock(mutex_);
    Statement s(db_, "SELECT password_hash, role FROM users WHERE username = ?");
    s.Bind(1, username);
    if (s.Step()) user.emplace(s.Text(0), s.Text(1));
  }
  if (!user) {
    SpendVerificationTime(password);
    return std::nullopt;
  }
  if (!VerifyPassword(user->first, password)) return std::nullopt;
  return Principal{username, ReadRole(user->second), "user", ""};
}

std::string Accounts::OpenSession(const std::string& username, std::chrono::seconds lifetime) {
  const std::string id = RandomSecret(32);
  std::lock_guard lock(mutex_);
  Statement prune(db_, "DELETE FROM sessions WHERE expires < ?");
  prune.Bind(1, UnixNow());
  prune.Step();
  Statement s(db_, "INSERT INTO sessions (digest, username, lifetime_s, expires) VALUES (?,?,?,?)");
  s.Bind(1, SecretDigest(id)).Bind(2, username).Bind(3, static_cast<std::int64_t>(lifetime.count()));
  s.Bind(4, UnixNow() + lifetime.count());
  s.Step();
  return id;
}

std::optional<Principal> Accounts::Session(const std::string& id) {
  const std::string digest = SecretDigest(id);
  std::lock_guard lock(mutex_);
  const std::int64_t now = UnixNow();
  Statement s(db_,
              "SELECT users.username, users.role, sessions.lifetime_s, sessions.expires FROM sessions JOIN users"
              " ON users.username = sessions.username WHERE sessions.digest = ? AND sessions.expires >= ?");
  s.Bind(1, digest).Bind(2, now);
  if (!s.Step()) return std::nullopt;
  Principal who{s.Text(0), ReadRole(s.Text(1)), "user", ""};
  // Extended at most once a minute: a console makes several requests a second, and each write is a sync to disk.
  if (now + s.Int64(2) - s.Int64(3) >= 60) {
    Statement touch(db_, "UPDATE sessions SET expires = ? WHERE digest = ?");
    touch.Bind(1, now + s.Int64(2)).Bind(2, digest);
    touch.Step();
  }
  return who;
}

void Accounts::CloseSession(const std::string& id) {
  std::lock_guard lock(mutex_);
  Statement s(db_, "DELETE FROM sessions WHERE digest = ?");
  s.Bind(1, SecretDigest(id));
  s.Step();
}

std::pair<TokenRecord, std::string> Accounts::CreateToken(const std::string& name, Role role,
                                                          const std::string& created_by) {
  CheckName(name, "token name");
  const std::string secret = "cor_" + RandomSecret(32);
  TokenRecord token{RandomSecret(9), name, role, Now(), created_by, ""};
  std::lock_guard lock(mutex_);
  Statement s(db_,
              "INSERT INTO tokens (id, digest, name, role, created, created_by, last_used) VALUES (?,?,?,?,?,?,'')");
  s.Bind(1, token.id).Bind(2, SecretDigest(secret)).Bind(3, name).Bind(4, std::string(ToString(role)));
  s.Bind(5, token.created).Bind(6, created_by);
  s.Step();
  return {token, secret};
}

std::optional<Principal> Accounts::Token(const std::string& secret) {
  const std::string digest = SecretDigest(secret);
  std::lock_guard lock(mutex_);
  Statement s(db_, "SELECT id, name, role, last_used FROM tokens WHERE digest = ?");
  s.Bind(1, digest);
  if (!s.Step()) return std::nullopt;
  Principal who{s.Text(1), ReadRole(s.Text(2)), "token", s.Text(0)};
  // The last use to the minute: enough to tell a live token from a forgotten one, without a write per request.
  const std::string now = Now();
  if (s.Text(3).substr(0, 16) != now.substr(0, 16)) {
    Statement touch(db_, "UPDATE tokens SET last_used = ? WHERE id = ?");
    touch.Bind(1, now).Bind(2, who.token_id);
    touch.Step();
  }
  return who;
}

bool Accounts::RevokeToken(const std::string& id) {
  std::lock_guard lock(mutex_);
  Statement s(db_, "DELETE FROM tokens WHERE id = ?");
  s.Bind(1, id);
  s.Step();
  return s.changes() > 0;
}

std::vector<TokenRecord> Accounts::Tokens() const {
  std::lock_guard lock(mutex_);
  Statement s(db_, "SELECT id, name, role, created, created_by, last_used FROM tokens ORDER BY created");
  std::vector<TokenRecord> out;
  while (s.Step()) out.push_back(ReadToken(s));
  return out;
}

void Accounts::Audit(const AuditRecord& r, int keep) {
  std::lock_guard lock(mutex_);
  InTransaction(db_, [&] {
    Statement s(db_, "INSERT INTO audit (time, who, client, method, path, status, detail) VALUES (?,?,?,?,?,?,?)");
    s.Bind(1, Now()).Bind(2, r.who).Bind(3, r.client).Bind(4, r.method).Bind(5, r.path).Bind(6, r.status);
    s.Bind(7, r.detail);
    s.Step();
    Statement prune(db_, "DELETE FROM audit WHERE seq <= ?");
    prune.Bind(1, static_cast<std::int64_t>(sqlite3_last_insert_rowid(db_.handle()) - keep));
    prune.Step();
  });
}

std::vector<json> Accounts::AuditLog(const AuditQuery& q) const {
  std::lock_guard lock(mutex_);
  Statement s(db_,
              "SELECT * FROM (SELECT seq, time, who, client, method, path, status, detail FROM audit"
              " WHERE seq > ? AND (? = 0 OR seq < ?) AND (? = '' OR who = ?) AND (? = '' OR instr(path, ?) > 0)"
              " AND (? = 0 OR status >= 400) ORDER BY seq DESC LIMIT ?) ORDER BY seq");
  s.Bind(1, q.after)
      .Bind(2, q.before)
      .Bind(3, q.before)
      .Bind(4, q.who)
      .Bind(5, q.who)
      .Bind(6, q.path_contains)
      .Bind(7, q.path_contains)
      .Bind(8, q.failed_only ? 1 : 0)
      .Bind(9, q.limit);
  std::vector<json> out;
  while (s.Step()) {
    out.push_back({{"sequence", s.Int64(0)},
                   {"time", s.Text(1)},
                   {"who", s.Text(2)},
                   {"client", s.Text(3)},
                   {"method", s.Text(4)},
                   {"path", s.Text(5)},
                   {"status", s.Int(6)},
                   {"detail", s.Text(7)}});
  }
  return out;
}

}  // namespace corridor::server::auth
