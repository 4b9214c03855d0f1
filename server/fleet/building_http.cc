#include "server/fleet/building_http.h"

#include <boost/beast/http.hpp>

#include "server/api/http_client.h"

namespace corridor::server {
namespace {

namespace http = boost::beast::http;

std::string Shortened(std::string text) {
  if (text.size() > 200) text = text.substr(0, 200) + "...";
  return text;
}

}  // namespace

std::string Filled(std::string text, const Placeholders& values) {
  for (const auto& [name, value] : values) {
    const std::string key = "{" + name + "}";
    for (std::size_t at = text.find(key); at != std::string::npos; at = text.find(key, at + value.size())) {
      text.replace(at, key.size(), value);
    }
  }
  return text;
}

bool HttpSuccess(int status) { return status >= 200 && status < 300; }

bool HttpRefusal(int status) { return status >= 400 && status < 500 && status != 408 && status != 429; }

std::string ValueText(const nlohmann::json& answer, const std::string& pointer) {
  const nlohmann::json::json_pointer at(pointer);
  if (!answer.contains(at)) return "";
  const nlohmann::json& v = answer.at(at);
  return v.is_string() ? v.get<std::string>() : v.dump();
}

BuildingHttp::BuildingHttp(boost::asio::io_context& io, std::vector<std::pair<std::string, std::string>> headers,
                           double timeout_s, const std::vector<const HttpRequestTemplate*>& templates,
                           const std::vector<std::string>& placeholders)
    : io_(io), headers_(std::move(headers)), timeout_s_(timeout_s), tls_(boost::asio::ssl::context::tls_client) {
  tls_.set_default_verify_paths();
  Placeholders names;
  for (const std::string& p : placeholders) names.emplace_back(p, p);
  for (const HttpRequestTemplate* t : templates) {
    if (!t->url.empty()) ParseHttpUrl(Filled(t->url, names));
  }
}

void BuildingHttp::Send(const HttpRequestTemplate& t, const Placeholders& values, Done done) {
  if (t.url.empty()) return done(0, "", "no request configured");
  HttpUrl url;
  try {
    url = ParseHttpUrl(Filled(t.url, values));
  } catch (const std::invalid_argument& e) {
    return done(0, "", e.what());
  }
  http::request<http::string_body> request{http::string_to_verb(t.method), url.target, 11};
  request.set(http::field::user_agent, "corridord");
  for (const auto& [name, value] : headers_) request.set(name, value);
  if (!t.body.empty()) {
    request.set(http::field::content_type, "application/json");
    request.body() = Filled(t.body, values);
  }
  request.prepare_payload();
  HttpExchange(io_, tls_, url, std::move(request), timeout_s_, [done = std::move(done)](HttpAnswer answer) {
    std::string error;
    if (answer.status == 0) {
      error = answer.error;
    } else if (!HttpSuccess(answer.status)) {
      error = std::to_string(answer.status) + " " + answer.reason;
      if (!answer.body.empty()) error += ": " + Shortened(answer.body);
    }
    done(answer.status, std::move(answer.body), std::move(error));
  });
}

}  // namespace corridor::server
