// Requests to a building system's own REST API (door and lift controllers), as the configuration describes them:
// request templates whose URL and body have "{name}" placeholders filled per call, the same headers on each, one
// timeout per exchange. Asynchronous on the io executor through server/api/http_client.h.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ssl/context.hpp>
#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "server/config/config.h"

namespace corridor::server {

using Placeholders = std::vector<std::pair<std::string, std::string>>;  // name (without braces), value

// `text` with every "{name}" replaced by its value.
std::string Filled(std::string text, const Placeholders& values);

// 2xx.
bool HttpSuccess(int status);
// A 4xx other than "try later": the building system will not do it.
bool HttpRefusal(int status);

// The value at `pointer` in `answer` as text ("open"; true for a flag); "" when there is none.
std::string ValueText(const nlohmann::json& answer, const std::string& pointer);

class BuildingHttp {
 public:
  using Done = std::function<void(int status, std::string body, std::string error)>;

  // Throws std::invalid_argument when a template's URL (filled with its placeholders' names) is not an http(s) URL.
  BuildingHttp(boost::asio::io_context& io, std::vector<std::pair<std::string, std::string>> headers, double timeout_s,
               const std::vector<const HttpRequestTemplate*>& templates, const std::vector<std::string>& placeholders);

  // Sends `t` filled with `values`; `done` gets the status (0: no answer), the body and, unless 2xx, what went wrong
  // ("404 Not Found: <body>", or why there was no answer). A template without a URL answers "no request configured".
  void Send(const HttpRequestTemplate& t, const Placeholders& values, Done done);

 private:
  boost::asio::io_context& io_;
  std::vector<std::pair<std::string, std::string>> headers_;
  double timeout_s_;
  boost::asio::ssl::context tls_;
};

}  // namespace corridor::server
