#include "server/auth/gate.h"

#include <array>

#include "server/auth/secrets.h"

namespace corridor::server::auth {
namespace {

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

}  // namespace

std::string_view ToString(Access access) {
  switch (access) {
    case Access::kPublic: return "anyone";
    case Access::kFace: return "the robot's screen";
    case Access::kViewer: return "viewer";
    case Access::kOperator: return "operator";
    case Access::kAdmin: return "admin";
  }
  return "admin";
}

bool Allows(const std::optional<Principal>& who, Access access, bool local, const AuthOptions& options) {
  if (access == Access::kPublic) return true;
  if (!who) {
    if (access == Access::kFace && local && options.local_face) return true;
    return options.anonymous_viewer && access <= Access::kViewer;
  }
  const Role needed = access == Access::kAdmin      ? Role::kAdmin
                      : access == Access::kOperator ? Role::kOperator
                                                    : Role::kViewer;
  return who->role >= needed;
}

std::string SessionFromCookies(std::string_view header) {
  while (!header.empty()) {
    const auto semicolon = header.find(';');
    const std::string_view pair = Trim(header.substr(0, semicolon));
    const auto eq = pair.find('=');
    if (eq != std::string_view::npos && pair.substr(0, eq) == kSessionCookie) return std::string(pair.substr(eq + 1));
    if (semicolon == std::string_view::npos) break;
    header.remove_prefix(semicolon + 1);
  }
  return "";
}

std::string SessionCookie(const std::string& id, std::chrono::seconds lifetime, bool secure) {
  return std::string(kSessionCookie) + "=" + id + "; Path=/; Max-Age=" + std::to_string(lifetime.count()) +
         "; HttpOnly; SameSite=Strict" + (secure ? "; Secure" : "");
}

std::string ClearedSessionCookie(bool secure) {
  // Appended in steps: GCC 12's -Warray-bounds misreads the one-expression concatenation once this is inlined
  // beside the accounts' code (a false positive, GCC bug 105329).
  std::string cookie(kSessionCookie);
  cookie += "=; Path=/; Max-Age=0; HttpOnly; SameSite=Strict";
  if (secure) cookie += "; Secure";
  return cookie;
}

std::string BearerToken(std::string_view authorization) {
  authorization = Trim(authorization);
  constexpr std::string_view kScheme = "Bearer ";
  if (authorization.size() <= kScheme.size()) return "";
  for (std::size_t i = 0; i < kScheme.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(authorization[i])) !=
        std::tolower(static_cast<unsigned char>(kScheme[i]))) {
      return "";
    }
  }
  return std::string(Trim(authorization.substr(kScheme.size())));
}

bool SameOrigin(std::string_view origin, std::string_view host) {
  const auto scheme_end = origin.find("://");
  if (scheme_end == std::string_view::npos || host.empty()) return false;
  const std::string_view scheme = origin.substr(0, scheme_end);
  if (scheme != "http" && scheme != "https") return false;
  return origin.substr(scheme_end + 3) == host;
}

void LoginLimiter::Forget(std::deque<Time>& times, Time now) const {
  while (!times.empty() && now - times.front() >= std::chrono::minutes(1)) times.pop_front();
}

int LoginLimiter::RetryAfter(const std::string& key, Time now) {
  std::lock_guard lock(mutex_);
  const auto it = failures_.find(key);
  if (it == failures_.end()) return 0;
  Forget(it->second, now);
  if (it->second.empty()) {
    failures_.erase(it);
    return 0;
  }
  if (static_cast<int>(it->second.size()) < limit_) return 0;
  const auto wait = std::chrono::minutes(1) - (now - it->second.front());
  return static_cast<int>(std::chrono::ceil<std::chrono::seconds>(wait).count());
}

void LoginLimiter::Failed(const std::string& key, Time now) {
  std::lock_guard lock(mutex_);
  auto& times = failures_[key];
  Forget(times, now);
  times.push_back(now);
  // A flood of names cannot grow this without bound: forget keys whose minute has passed.
  if (failures_.size() > 10000) {
    for (auto it = failures_.begin(); it != failures_.end();) {
      Forget(it->second, now);
      it = it->second.empty() ? failures_.erase(it) : std::next(it);
    }
  }
}

Setup::Setup(Accounts& accounts) : accounts_(accounts) {
  if (!accounts_.HasUsers()) code_ = RandomCode(8);
}

std::optional<std::string> Setup::code() const {
  std::lock_guard lock(mutex_);
  if (!code_.empty() && accounts_.HasUsers()) code_.clear();  // a user was made otherwise (with a token)
  if (code_.empty()) return std::nullopt;
  return code_.substr(0, 4) + "-" + code_.substr(4);
}

UserRecord Setup::Complete(const std::string& code, const std::string& username, const std::string& password) {
  std::lock_guard lock(mutex_);
  if (code_.empty() || accounts_.HasUsers()) throw SetupError{true};
  std::string typed;
  for (char c : code) {
    if (c != '-' && c != ' ') typed += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  if (!SameSecret(typed, code_)) throw SetupError{false};
  UserRecord admin = accounts_.AddUser(username, password, Role::kAdmin);
  code_.clear();
  return admin;
}

}  // namespace corridor::server::auth
