#include "server/fleet/doors.h"

#include <spdlog/spdlog.h>
#include <boost/beast/http.hpp>
#include <nlohmann/json.hpp>

#include "server/api/http_client.h"

namespace corridor::server {
namespace {

namespace http = boost::beast::http;

bool Success(int status) { return status >= 200 && status < 300; }

// A 4xx other than "try later": the controller will not do it.
bool Refusal(int status) { return status >= 400 && status < 500 && status != 408 && status != 429; }

std::string Shortened(std::string text) {
  if (text.size() > 200) text = text.substr(0, 200) + "...";
  return text;
}

}  // namespace

std::string ForDoor(std::string text, const std::string& door) {
  for (std::size_t at = text.find("{door}"); at != std::string::npos; at = text.find("{door}", at + door.size())) {
    text.replace(at, 6, door);
  }
  return text;
}

HttpDoorController::HttpDoorController(boost::asio::io_context& io, const DoorControllerOptions& options)
    : io_(io), options_(options), tls_(boost::asio::ssl::context::tls_client) {
  tls_.set_default_verify_paths();
  for (const HttpRequestTemplate* t : {&options_.open, &options_.state, &options_.release}) {
    if (!t->url.empty()) ParseHttpUrl(ForDoor(t->url, "door"));
  }
}

void HttpDoorController::Send(const HttpRequestTemplate& t, const std::string& door,
                              std::function<void(int, std::string, std::string)> done) {
  if (t.url.empty()) return done(0, "", "no request configured");
  HttpUrl url;
  try {
    url = ParseHttpUrl(ForDoor(t.url, door));
  } catch (const std::invalid_argument& e) {
    return done(0, "", e.what());
  }
  http::request<http::string_body> request{http::string_to_verb(t.method), url.target, 11};
  request.set(http::field::user_agent, "corridord");
  for (const auto& [name, value] : options_.headers) request.set(name, value);
  if (!t.body.empty()) {
    request.set(http::field::content_type, "application/json");
    request.body() = ForDoor(t.body, door);
  }
  request.prepare_payload();
  HttpExchange(io_, tls_, url, std::move(request), options_.request_timeout_s,
               [done = std::move(done)](HttpAnswer answer) {
                 done(answer.status, std::move(answer.body),
                      answer.status == 0 ? answer.error : std::to_string(answer.status) + " " + answer.reason);
               });
}

void HttpDoorController::Open(const std::string& door, Done done) {
  Send(options_.open, door, [done = std::move(done)](int status, std::string body, std::string error) {
    if (Success(status)) return done({nav::DoorStatus::kOpening, ""});
    const std::string why = body.empty() ? error : error + ": " + Shortened(body);
    done({Refusal(status) ? nav::DoorStatus::kRefused : nav::DoorStatus::kFailed, why});
  });
}

void HttpDoorController::State(const std::string& door, Done done) {
  Send(options_.state, door, [this, done = std::move(done)](int status, std::string body, std::string error) {
    if (!Success(status)) return done({nav::DoorStatus::kFailed, error});
    try {
      const nlohmann::json answer = nlohmann::json::parse(body);
      const nlohmann::json::json_pointer pointer(options_.open_pointer);
      // The value as text: "open", or true for a flag.
      const auto value = [&](const nlohmann::json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); };
      const bool open = answer.contains(pointer) && value(answer.at(pointer)) == options_.open_value;
      done({open ? nav::DoorStatus::kOpen : nav::DoorStatus::kOpening, ""});
    } catch (const nlohmann::json::exception& e) {
      done({nav::DoorStatus::kFailed, std::string("the door's state is not the JSON expected: ") + e.what()});
    }
  });
}

void HttpDoorController::Release(const std::string& door) {
  if (options_.release.url.empty()) return;  // this building's doors close by themselves
  Send(options_.release, door, [door](int status, std::string, std::string error) {
    if (!Success(status)) spdlog::warn("doors: releasing {}: {}", door, error);
  });
}

}  // namespace corridor::server
