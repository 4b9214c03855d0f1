// What every part of the REST API shares: the request and response types, the problem+json error (RFC 9457) with a
// machine-readable "code" where a client may want to act on the kind of error, who a request comes from, and the
// helpers that read bodies and query strings strictly.
#pragma once

#include <boost/beast/http.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "server/auth/accounts.h"

namespace corridor::server {

namespace http = boost::beast::http;
using Request = http::request<http::string_body>;
using Response = http::response<http::string_body>;
using Reply = std::function<void(Response)>;
using Params = std::map<std::string, std::string, std::less<>>;

// A request the API refuses; becomes a problem+json response with this status (and `code`, when not empty).
class ApiError : public std::runtime_error {
 public:
  ApiError(http::status status, std::string title, const std::string& detail, std::string code = "")
      : std::runtime_error(detail), status_(status), title_(std::move(title)), code_(std::move(code)) {}
  http::status status() const { return status_; }
  const std::string& title() const { return title_; }
  const std::string& code() const { return code_; }
  // For 429 and 503: when to try again (the Retry-After header); 0: not said.
  int retry_after_s() const { return retry_after_s_; }
  ApiError& RetryAfter(int seconds) {
    retry_after_s_ = seconds;
    return *this;
  }

 private:
  http::status status_;
  std::string title_;
  std::string code_;
  int retry_after_s_ = 0;
};

Response ProblemResponse(http::status status, const std::string& title, const std::string& detail, unsigned version,
                         bool keep_alive, const std::string& code = "");
// `work`'s response, or the problem it throws (ApiError as itself, anything else as a 500). Never throws.
Response Respond(const Request& request, const std::function<Response()>& work);

// Where a request comes from. The API works out who sends it from its credentials (Api::Identify).
struct Caller {
  std::string address;   // the peer's IP address; "" in process
  bool local = false;    // on the robot itself (loopback): the face screen
  bool trusted = false;  // a tool driving the graph in process (the scenario runner): no credentials needed
};

// Who sends a request, from its bearer token or session cookie; nobody when it has neither.
struct Identity {
  std::optional<auth::Principal> who;
  bool by_cookie = false;  // the credentials are a cookie the browser sends by itself (CSRF matters)
};

// JSON text of `value`; bytes that are not UTF-8 (a request's path, say) become U+FFFD instead of throwing.
std::string Dump(const nlohmann::json& value);
Response JsonResponse(const Request& request, const nlohmann::json& body, http::status status = http::status::ok);
Response MakeResponse(const Request& request, http::status status, std::string content_type, std::string body);
nlohmann::json ParseJsonBody(const Request& request);
// ParseJsonBody's object with no key outside `allowed` (400 otherwise).
nlohmann::json ObjectBody(const Request& request, std::initializer_list<const char*> allowed);
// A required finite number; throws ApiError 400 naming `where` and `key`.
double RequireNumber(const nlohmann::json& body, const char* key, const std::string& where);
// A whole number >= 0 written in `text` (a path segment or query value); throws ApiError 400 with `what` it must be.
std::uint64_t ParseCount(const std::string& text, const std::string& what);
// One query parameter's value from "/path?a=1&b=2", percent escapes decoded; "true" for a bare key, "" when absent.
std::string QueryValue(std::string_view target, std::string_view key);
// `bytes` as base64 (RFC 4648's alphabet, padded), and back; nullopt for text that is not base64.
std::string ToBase64(std::string_view bytes);
std::optional<std::string> FromBase64(std::string_view text);
// The "after" query parameter of a log's page (events, audit): a sequence number, 0 when absent; 400 otherwise.
std::int64_t AfterParameter(std::string_view target);
// Throws ApiError 400 for a key not in `allowed`.
void AllowOnlyKeys(const nlohmann::json& body, std::initializer_list<const char*> allowed, const std::string& where);

}  // namespace corridor::server
