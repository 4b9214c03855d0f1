// Who may call what: the access each route needs, the credentials a request carries (a bearer token or a session
// cookie), the one-time setup code that creates the first admin, and the limit on wrong passwords.
// Independent of HTTP's types: the API (server/api/api_auth.cc) hands it header values.
#pragma once

#include <chrono>
#include <deque>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "server/auth/accounts.h"
#include "server/auth/options.h"

namespace corridor::server::auth {

// What a route needs, from least to most.
enum class Access { kPublic, kFace, kViewer, kOperator, kAdmin };
// Each route declares the access it needs (server/api: Api::Routes(), and x-corridor-access in openapi.json).
std::string_view ToString(Access access);

// Whether `who` has `access`; `local` tells a caller on the robot itself (for kFace).
bool Allows(const std::optional<Principal>& who, Access access, bool local, const AuthOptions& options);

// The session id in a Cookie header ("" when none), and the cookie that sets or clears it.
inline constexpr std::string_view kSessionCookie = "corridor_session";
std::string SessionFromCookies(std::string_view cookie_header);
std::string SessionCookie(const std::string& id, std::chrono::seconds lifetime, bool secure);
std::string ClearedSessionCookie(bool secure);
// The token of "Authorization: Bearer <token>" ("" when the header is absent or another scheme).
std::string BearerToken(std::string_view authorization);
// Whether a browser's Origin header ("https://robot.local:8443") names the host the request was sent to (Host).
bool SameOrigin(std::string_view origin, std::string_view host);

// Counts wrong passwords per key (a client address, a username) over a sliding minute.
class LoginLimiter {
 public:
  using Time = std::chrono::steady_clock::time_point;
  explicit LoginLimiter(int failures_per_minute) : limit_(failures_per_minute) {}
  // Whole seconds until `key` may try again; 0 when it may now.
  int RetryAfter(const std::string& key, Time now);
  void Failed(const std::string& key, Time now);

 private:
  void Forget(std::deque<Time>& times, Time now) const;

  int limit_;
  std::mutex mutex_;
  std::map<std::string, std::deque<Time>> failures_;
};

// The one-time code that lets the first admin in when there are no users (ETSI EN 303 645, 5.1: no default password).
class Setup {
 public:
  // Makes a code when `accounts` has no users.
  explicit Setup(Accounts& accounts);
  // The code while setup is open ("7KQ4-MZ2P"); nullopt once a user exists.
  std::optional<std::string> code() const;
  // Creates the first admin when `code` is right (any case, with or without the dash). Throws AccountError for a bad
  // username or password and SetupError when setup is done (`done`) or the code is wrong.
  struct SetupError {
    bool done;
  };
  UserRecord Complete(const std::string& code, const std::string& username, const std::string& password);

 private:
  Accounts& accounts_;
  mutable std::mutex mutex_;
  mutable std::string code_;  // 8 characters; "" once a user exists
};

// Everything the API needs to decide who may call what.
struct AccessControl {
  AccessControl(const std::filesystem::path& accounts_file, AuthOptions options_)
      : options(options_), accounts(accounts_file), setup(accounts), limiter(options_.login_failures_per_minute) {}
  AuthOptions options;
  Accounts accounts;
  Setup setup;
  LoginLimiter limiter;
};

}  // namespace corridor::server::auth
