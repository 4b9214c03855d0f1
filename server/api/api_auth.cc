// Who may call what (server/auth/gate.h) applied to every request, and the routes that manage it: the first admin's
// setup, browser sessions, users, API tokens and the audit log.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdint>
#include <limits>

#include "server/api/api.h"
#include "server/api/api_auth.h"

namespace corridor::server {
namespace {

using auth::Access;
using auth::Principal;
using auth::Role;
using nlohmann::json;

constexpr int kAuditPerPage = 256;

bool IsRead(http::verb method) { return method == http::verb::get || method == http::verb::head; }

std::string Who(const std::optional<Principal>& who) {
  if (!who) return "anonymous";
  return who->kind == "token" ? "token:" + who->name : who->name;
}

json PrincipalJson(const Principal& who) {
  return {{"name", who.name}, {"role", std::string(auth::ToString(who.role))}, {"kind", who.kind}};
}

std::string RequireString(const json& body, const char* key) {
  const auto it = body.find(key);
  if (it == body.end() || !it->is_string()) {
    throw ApiError(http::status::bad_request, "Invalid request", std::string("'") + key + "' must be a string");
  }
  return it->get<std::string>();
}

Role RequireRole(const json& body) {
  const auto role = auth::RoleFromString(RequireString(body, "role"));
  if (!role) throw ApiError(http::status::bad_request, "Invalid request", "'role' must be viewer, operator or admin");
  return *role;
}

// A change to the accounts the request asked for but that cannot be made becomes 409 (taken) or 422 (invalid).
template <typename Work>
auto AccountChange(Work&& work) {
  try {
    return work();
  } catch (const auth::AccountError& e) {
    const bool conflict = e.kind() == auth::AccountError::Kind::kConflict;
    throw ApiError(conflict ? http::status::conflict : http::status::unprocessable_entity, "Not accepted", e.what());
  }
}

ApiError TooManyAttempts(int retry_after_s) {
  return ApiError(http::status::too_many_requests, "Too many attempts",
                  "too many wrong passwords or codes; try again in " + std::to_string(retry_after_s) + " s",
                  "rate_limited")
      .RetryAfter(retry_after_s);
}

}  // namespace

Identity Api::Identify(const Request& request, const Caller& caller) const {
  if (caller.trusted) return {Principal{"corridord", Role::kAdmin, "system", ""}, false};
  const std::string token = auth::BearerToken(request[http::field::authorization]);
  if (!token.empty()) {
    auto who = c_.access.accounts.Token(token);
    if (!who) {
      throw ApiError(http::status::unauthorized, "Unauthorized", "the API token is not valid (revoked?)",
                     "invalid_token");
    }
    return {std::move(who), false};
  }
  const std::string session = auth::SessionFromCookies(request[http::field::cookie]);
  if (!session.empty()) {
    if (auto who = c_.access.accounts.Session(session)) return {std::move(who), true};
  }
  return {};
}

void Api::CheckAccess(const Request& request, const Caller& caller, const Identity& identity, Access needed) const {
  if (!auth::Allows(identity.who, needed, caller.local, c_.access.options)) {
    if (!identity.who) {
      throw ApiError(http::status::unauthorized, "Unauthorized",
                     "log in (POST /api/v1/session) or send an API token (Authorization: Bearer)", "unauthenticated");
    }
    throw ApiError(http::status::forbidden, "Forbidden",
                   std::string(auth::ToString(needed)) + " role needed; " + Who(identity.who) + " is " +
                       std::string(auth::ToString(identity.who->role)),
                   "forbidden");
  }
  // A browser sends the session cookie with requests other sites make it send; a write must come from our own page.
  if (identity.by_cookie && !IsRead(request.method()) && needed != Access::kPublic) {
    const std::string_view origin = request[http::field::origin];
    const std::string_view fetch_site = request["Sec-Fetch-Site"];
    const bool same =
        origin.empty() ? fetch_site == "same-origin" : auth::SameOrigin(origin, request[http::field::host]);
    if (!same) {
      throw ApiError(http::status::forbidden, "Cross-site request refused",
                     "writes with a session cookie must come from the console's own origin", "cross_site");
    }
  }
}

Api::StreamAdmission Api::AdmitStream(const Request& request, const Caller& caller) const {
  Identity who = Identify(request, caller);
  const std::string path = "/api/v1/stream";
  Params params;
  bool path_matched = false;
  CheckAccess(request, caller, who, AccessFor(routes_.Find(http::verb::get, path, params, path_matched), path));
  const std::string_view origin = request[http::field::origin];
  if (!origin.empty() && !auth::SameOrigin(origin, request[http::field::host])) {
    throw ApiError(http::status::forbidden, "Cross-site WebSocket refused",
                   "the stream opens only from the console's own origin", "cross_site");
  }
  const bool reads = who.who.has_value() || c_.access.options.anonymous_viewer;
  return {std::move(who), reads ? std::vector<std::string>{"state"} : std::vector<std::string>{}};
}

Reply Api::Audited(const Request& request, const Caller& caller, const Identity& identity, const std::string& path,
                   Reply reply) const {
  if (IsRead(request.method()) || !path.starts_with("/api/") || caller.trusted) return reply;
  auth::AuditRecord record{Who(identity.who), caller.address, std::string(request.method_string()), path, 0, ""};
  return [this, record = std::move(record), reply = std::move(reply)](Response response) mutable {
    record.status = response.result_int();
    if (response.result_int() < 300 && response[http::field::content_type] == "application/json") {
      const json body = json::parse(response.body(), nullptr, false);
      if (body.is_object() && body.contains("id") && body["id"].is_string()) record.detail = body["id"];
    } else if (response.result_int() >= 400) {
      const json body = json::parse(response.body(), nullptr, false);
      if (body.is_object() && body.contains("detail") && body["detail"].is_string()) record.detail = body["detail"];
    }
    try {
      c_.access.accounts.Audit(record, c_.access.options.keep_audit);
    } catch (const std::exception& e) {
      spdlog::error("audit log: {}", e.what());
    }
    reply(std::move(response));
  };
}

AccountsApi::AccountsApi(auth::AccessControl& access, bool secure, std::string tls_fingerprint)
    : access_(access), secure_(secure), tls_fingerprint_(std::move(tls_fingerprint)) {}

void AccountsApi::AddRoutes(Router& routes) const {
  const auto lifetime = std::chrono::seconds(static_cast<std::int64_t>(access_.options.session_hours * 3600));
  // Logs `who` in: a session and its cookie.
  const auto login = [this, lifetime](const Request& r, const Principal& who, http::status status) {
    Response res = JsonResponse(r, PrincipalJson(who), status);
    res.set(http::field::set_cookie,
            auth::SessionCookie(access_.accounts.OpenSession(who.name, lifetime), lifetime, secure_));
    return res;
  };

  // Public: whether the robot is still to be set up, and who the caller is logged in as (null: nobody), so that a
  // page can tell without a request that fails.
  routes.AddWithCaller(http::verb::get, "/api/v1/setup", Access::kPublic,
                       [this](const Request& r, const Params&, const Caller& caller, const Identity& identity) {
                         const auto code = access_.setup.code();
                         json body = {{"needed", code.has_value()}};
                         body["session"] = identity.who ? PrincipalJson(*identity.who) : json(nullptr);
                         // The code is shown on the robot's own screen (and in its journal), never sent over the
                         // network.
                         if (code && caller.local && access_.options.local_face) body["code"] = *code;
                         if (!tls_fingerprint_.empty()) body["tls_fingerprint"] = tls_fingerprint_;
                         return JsonResponse(r, body);
                       });
  routes.AddWithCaller(
      http::verb::post, "/api/v1/setup", Access::kPublic,
      [this, login](const Request& r, const Params&, const Caller& caller, const Identity&) {
        const json body = ParseJsonBody(r);
        AllowOnlyKeys(body, {"code", "username", "password"}, "");
        const std::string key = "setup@" + caller.address;
        const auto now = std::chrono::steady_clock::now();
        if (const int wait = access_.limiter.RetryAfter(key, now); wait > 0) throw TooManyAttempts(wait);
        try {
          const auth::UserRecord admin = AccountChange([&] {
            return access_.setup.Complete(RequireString(body, "code"), RequireString(body, "username"),
                                          RequireString(body, "password"));
          });
          spdlog::info("setup: {} is the first admin", admin.username);
          return login(r, Principal{admin.username, Role::kAdmin, "user", ""}, http::status::created);
        } catch (const auth::Setup::SetupError& e) {
          if (e.done) {
            throw ApiError(http::status::conflict, "Already set up", "the first admin exists; log in", "setup_done");
          }
          access_.limiter.Failed(key, now);
          throw ApiError(http::status::forbidden, "Wrong setup code",
                         "the setup code is shown on the robot's screen and in its journal", "wrong_setup_code");
        }
      });

  routes.AddWithCaller(
      http::verb::post, "/api/v1/session", Access::kPublic,
      [this, login](const Request& r, const Params&, const Caller& caller, const Identity&) {
        const json body = ParseJsonBody(r);
        AllowOnlyKeys(body, {"username", "password"}, "");
        const std::string username = RequireString(body, "username");
        const std::string password = RequireString(body, "password");
        const std::string by_client = "client@" + caller.address;
        const std::string by_user = "user@" + username;
        const auto now = std::chrono::steady_clock::now();
        const int wait = std::max(access_.limiter.RetryAfter(by_client, now), access_.limiter.RetryAfter(by_user, now));
        if (wait > 0) throw TooManyAttempts(wait);
        const auto who = access_.accounts.CheckPassword(username, password);
        if (!who) {
          access_.limiter.Failed(by_client, now);
          access_.limiter.Failed(by_user, now);
          throw ApiError(http::status::unauthorized, "Login failed", "wrong username or password", "wrong_password");
        }
        return login(r, *who, http::status::ok);
      });
  routes.AddWithCaller(http::verb::get, "/api/v1/session", Access::kPublic,
                       [this](const Request& r, const Params&, const Caller&, const Identity& identity) {
                         if (!identity.who) {
                           throw ApiError(http::status::unauthorized, "Not logged in", "POST /api/v1/session to log in",
                                          "unauthenticated");
                         }
                         json body = PrincipalJson(*identity.who);
                         body["anonymous_viewer"] = access_.options.anonymous_viewer;
                         return JsonResponse(r, body);
                       });
  routes.Add(http::verb::delete_, "/api/v1/session", Access::kPublic, Sync([this](const Request& r, const Params&) {
               const std::string session = auth::SessionFromCookies(r[http::field::cookie]);
               if (!session.empty()) access_.accounts.CloseSession(session);
               Response res = MakeResponse(r, http::status::no_content, "application/json", "");
               res.set(http::field::set_cookie, auth::ClearedSessionCookie(secure_));
               return res;
             }));

  routes.Add(http::verb::get, "/api/v1/users", Access::kAdmin, Sync([this](const Request& r, const Params&) {
               json users = json::array();
               for (const auth::UserRecord& u : access_.accounts.Users()) users.push_back(ToJson(u));
               return JsonResponse(r, {{"users", users}});
             }));
  routes.Add(http::verb::post, "/api/v1/users", Access::kAdmin, Sync([this](const Request& r, const Params&) {
               const json body = ParseJsonBody(r);
               AllowOnlyKeys(body, {"username", "password", "role"}, "");
               const auth::UserRecord user = AccountChange([&] {
                 return access_.accounts.AddUser(RequireString(body, "username"), RequireString(body, "password"),
                                                 RequireRole(body));
               });
               Response res = JsonResponse(r, ToJson(user), http::status::created);
               res.set(http::field::location, "/api/v1/users/" + user.username);
               return res;
             }));
  routes.Add(http::verb::delete_, "/api/v1/users/{username}", Access::kAdmin,
             Sync([this](const Request& r, const Params& p) {
               const bool deleted = AccountChange([&] { return access_.accounts.DeleteUser(p.at("username")); });
               if (!deleted) throw ApiError(http::status::not_found, "Not found", "no user " + p.at("username"));
               return MakeResponse(r, http::status::no_content, "application/json", "");
             }));

  routes.Add(http::verb::get, "/api/v1/tokens", Access::kAdmin, Sync([this](const Request& r, const Params&) {
               json tokens = json::array();
               for (const auth::TokenRecord& t : access_.accounts.Tokens()) tokens.push_back(ToJson(t));
               return JsonResponse(r, {{"tokens", tokens}});
             }));
  routes.AddWithCaller(http::verb::post, "/api/v1/tokens", Access::kAdmin,
                       [this](const Request& r, const Params&, const Caller&, const Identity& identity) {
                         const json body = ParseJsonBody(r);
                         AllowOnlyKeys(body, {"name", "role"}, "");
                         const std::string by = Who(identity.who);
                         const auto [token, secret] = AccountChange([&] {
                           return access_.accounts.CreateToken(RequireString(body, "name"), RequireRole(body), by);
                         });
                         json out = ToJson(token);
                         out["token"] = secret;  // shown this once; kept only as a digest
                         Response res = JsonResponse(r, out, http::status::created);
                         res.set(http::field::location, "/api/v1/tokens/" + token.id);
                         return res;
                       });
  routes.Add(http::verb::delete_, "/api/v1/tokens/{id}", Access::kAdmin,
             Sync([this](const Request& r, const Params& p) {
               if (!access_.accounts.RevokeToken(p.at("id"))) {
                 throw ApiError(http::status::not_found, "Not found", "no token " + p.at("id"));
               }
               return MakeResponse(r, http::status::no_content, "application/json", "");
             }));

  // The newest records, or those after `after` (a poller's last sequence).
  routes.Add(
      http::verb::get, "/api/v1/audit", Access::kAdmin, Sync([this](const Request& r, const Params&) {
        auth::AuditQuery query;
        query.after = AfterParameter(r.target());
        const std::string before = QueryValue(r.target(), "before");
        if (!before.empty()) {
          query.before = static_cast<std::int64_t>(std::min<std::uint64_t>(
              ParseCount(before, "before: a sequence number, 1 or more"), std::numeric_limits<std::int64_t>::max()));
        }
        query.who = QueryValue(r.target(), "who");
        query.path_contains = QueryValue(r.target(), "path");
        const std::string failed = QueryValue(r.target(), "failed");
        if (!failed.empty() && failed != "true" && failed != "false") {
          throw ApiError(http::status::bad_request, "Invalid request", "failed: true or false, got '" + failed + "'");
        }
        query.failed_only = failed == "true";
        const std::string limit = QueryValue(r.target(), "limit");
        query.limit = kAuditPerPage;
        if (!limit.empty()) {
          const std::uint64_t n = ParseCount(limit, "limit: a count of records, 1 to 256");
          if (n < 1 || n > static_cast<std::uint64_t>(kAuditPerPage)) {
            throw ApiError(http::status::bad_request, "Invalid request", "limit: a count of records, 1 to 256");
          }
          query.limit = static_cast<int>(n);
        }
        return JsonResponse(r, {{"records", access_.accounts.AuditLog(query)}});
      }));
}

}  // namespace corridor::server
