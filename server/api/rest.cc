#include "server/api/rest.h"

#include <openssl/evp.h>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

namespace corridor::server {

using nlohmann::json;

std::uint64_t ParseCount(const std::string& text, const std::string& what) {
  std::uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size()) {
    throw ApiError(http::status::bad_request, "Invalid request", what);
  }
  return value;
}

namespace {

// `text` with its percent escapes and '+' (a space, in a form's query) decoded; a malformed escape is kept as it is.
std::string PercentDecoded(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  const auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '+') {
      out += ' ';
    } else if (text[i] == '%' && i + 2 < text.size() && hex(text[i + 1]) >= 0 && hex(text[i + 2]) >= 0) {
      out += static_cast<char>(hex(text[i + 1]) * 16 + hex(text[i + 2]));
      i += 2;
    } else {
      out += text[i];
    }
  }
  return out;
}

}  // namespace

std::string QueryValue(std::string_view target, std::string_view key) {
  const auto q = target.find('?');
  if (q == std::string_view::npos) return "";
  std::string_view query = target.substr(q + 1);
  while (!query.empty()) {
    const auto amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    const auto eq = pair.find('=');
    if (pair.substr(0, eq) == key) return eq == std::string_view::npos ? "true" : PercentDecoded(pair.substr(eq + 1));
    if (amp == std::string_view::npos) break;
    query.remove_prefix(amp + 1);
  }
  return "";
}

std::string ToBase64(std::string_view bytes) {
  std::string out(4 * ((bytes.size() + 2) / 3), '\0');
  const int n = EVP_EncodeBlock(reinterpret_cast<unsigned char*>(out.data()),
                                reinterpret_cast<const unsigned char*>(bytes.data()), static_cast<int>(bytes.size()));
  out.resize(static_cast<std::size_t>(std::max(0, n)));
  return out;
}

std::optional<std::string> FromBase64(std::string_view text) {
  std::string out(3 * (text.size() / 4) + 3, '\0');
  EVP_ENCODE_CTX* context = EVP_ENCODE_CTX_new();
  if (context == nullptr) return std::nullopt;
  EVP_DecodeInit(context);
  int n = 0;
  int last = 0;
  const int updated =
      EVP_DecodeUpdate(context, reinterpret_cast<unsigned char*>(out.data()), &n,
                       reinterpret_cast<const unsigned char*>(text.data()), static_cast<int>(text.size()));
  const int finished =
      updated < 0 ? -1 : EVP_DecodeFinal(context, reinterpret_cast<unsigned char*>(out.data()) + n, &last);
  EVP_ENCODE_CTX_free(context);
  if (updated < 0 || finished < 0) return std::nullopt;
  out.resize(static_cast<std::size_t>(n + last));
  return out;
}

std::int64_t AfterParameter(std::string_view target) {
  const std::string text = QueryValue(target, "after");
  const std::uint64_t after = text.empty() ? 0 : ParseCount(text, "after: a sequence number, 0 or more");
  return static_cast<std::int64_t>(std::min<std::uint64_t>(after, std::numeric_limits<std::int64_t>::max()));
}

std::string Dump(const json& value) { return value.dump(-1, ' ', false, json::error_handler_t::replace); }

Response MakeResponse(const Request& request, http::status status, std::string content_type, std::string body) {
  Response res{status, request.version()};
  res.set(http::field::server, "corridord");
  res.set(http::field::content_type, std::move(content_type));
  res.set(http::field::cache_control, "no-store");
  res.keep_alive(request.keep_alive());
  res.body() = std::move(body);
  res.prepare_payload();
  return res;
}

Response JsonResponse(const Request& request, const json& body, http::status status) {
  return MakeResponse(request, status, "application/json", Dump(body));
}

Response ProblemResponse(http::status status, const std::string& title, const std::string& detail, unsigned version,
                         bool keep_alive, const std::string& code) {
  Response res{status, version};
  res.set(http::field::server, "corridord");
  res.set(http::field::content_type, "application/problem+json");
  res.keep_alive(keep_alive);
  json body = {{"type", "about:blank"}, {"title", title}, {"status", static_cast<int>(status)}, {"detail", detail}};
  if (!code.empty()) body["code"] = code;
  res.body() = Dump(body);
  res.prepare_payload();
  return res;
}

json ParseJsonBody(const Request& request) {
  const auto content_type = request[http::field::content_type];
  if (!content_type.starts_with("application/json")) {
    throw ApiError(http::status::unsupported_media_type, "Unsupported media type", "send the body as application/json");
  }
  json body = json::parse(request.body(), nullptr, /*allow_exceptions=*/false);
  if (body.is_discarded()) throw ApiError(http::status::bad_request, "Malformed JSON", "the body is not valid JSON");
  if (!body.is_object()) throw ApiError(http::status::bad_request, "Malformed request", "expected a JSON object");
  return body;
}

double RequireNumber(const json& body, const char* key, const std::string& where) {
  const std::string name = where.empty() ? key : where + "." + key;
  const auto it = body.find(key);
  if (it == body.end()) throw ApiError(http::status::bad_request, "Invalid request", "missing '" + name + "'");
  if (!it->is_number() || !std::isfinite(it->get<double>())) {
    throw ApiError(http::status::bad_request, "Invalid request", "'" + name + "' must be a finite number");
  }
  return it->get<double>();
}

void AllowOnlyKeys(const json& body, std::initializer_list<const char*> allowed, const std::string& where) {
  for (const auto& [key, value] : body.items()) {
    if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; })) {
      throw ApiError(http::status::bad_request, "Invalid request",
                     "unknown key '" + (where.empty() ? key : where + "." + key) + "'");
    }
  }
}

Response Respond(const Request& request, const std::function<Response()>& work) {
  try {
    return work();
  } catch (const ApiError& e) {
    Response response =
        ProblemResponse(e.status(), e.title(), e.what(), request.version(), request.keep_alive(), e.code());
    if (e.status() == http::status::method_not_allowed) {
      response.set(http::field::allow, "GET, POST, PUT, PATCH, DELETE");
    }
    if (e.retry_after_s() > 0) response.set(http::field::retry_after, std::to_string(e.retry_after_s()));
    return response;
  } catch (const std::exception& e) {
    spdlog::error("{} {}: {}", std::string(request.method_string()), std::string(request.target()), e.what());
    return ProblemResponse(http::status::internal_server_error, "Internal error", e.what(), request.version(), false);
  }
}

json ObjectBody(const Request& request, std::initializer_list<const char*> allowed) {
  json body = ParseJsonBody(request);
  AllowOnlyKeys(body, allowed, "");
  return body;
}

}  // namespace corridor::server
