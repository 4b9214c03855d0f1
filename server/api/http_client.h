// One outgoing HTTP(S) request, asynchronously on an io_context (Boost.Beast): resolve, connect, TLS handshake with
// the peer verified by name, send, read the answer, close; every step bounded by one deadline. For the robot's calls
// to building systems: webhooks, door controllers.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ssl/context.hpp>
#include <boost/beast/http.hpp>

#include <functional>
#include <string>

namespace corridor::server {

// A URL, taken apart. Only http and https; no user info, no fragment.
struct HttpUrl {
  bool tls = false;
  std::string host;
  std::string port;    // "80" or "443" when the URL has none
  std::string target;  // path and query; "/" when empty
};
// Throws std::invalid_argument saying what is wrong.
HttpUrl ParseHttpUrl(const std::string& url);

struct HttpAnswer {
  int status = 0;      // 0: no answer (see error)
  std::string reason;  // the status line's reason phrase
  std::string body;    // at most max_body_bytes of it
  std::string error;   // why there was no answer; "" when there was one
};

// Sends `request` (its host header set here) to `url` and calls `done` once, on `io`'s thread.
void HttpExchange(boost::asio::io_context& io, boost::asio::ssl::context& tls, const HttpUrl& url,
                  boost::beast::http::request<boost::beast::http::string_body> request, double timeout_s,
                  std::function<void(HttpAnswer)> done, std::size_t max_body_bytes = 64 * 1024);

}  // namespace corridor::server
