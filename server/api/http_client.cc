#include "server/api/http_client.h"

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/host_name_verification.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/ssl.hpp>
#include <openssl/ssl.h>

#include <memory>
#include <regex>
#include <stdexcept>

namespace corridor::server {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

// One request from start to answer; keeps itself alive through its handlers.
struct Exchange : std::enable_shared_from_this<Exchange> {
  Exchange(asio::io_context& io, asio::ssl::context& tls, HttpUrl to, http::request<http::string_body> out,
           double timeout_s, std::function<void(HttpAnswer)> on_done, std::size_t max_body_bytes)
      : resolver(io),
        stream(io, tls),
        url(std::move(to)),
        request(std::move(out)),
        timeout(std::chrono::milliseconds(static_cast<long>(timeout_s * 1000.0))),
        done(std::move(on_done)) {
    parser.body_limit(max_body_bytes);
  }

  void Start() {
    resolver.async_resolve(url.host, url.port, [self = shared_from_this()](beast::error_code resolved, auto results) {
      if (resolved) return self->Fail("cannot resolve " + self->url.host + ": " + resolved.message());
      self->Lowest().expires_after(self->timeout);
      self->Lowest().async_connect(results, [self](beast::error_code connected, const tcp::endpoint&) {
        if (connected) return self->Fail("cannot connect: " + connected.message());
        if (!self->url.tls) return self->Send(self->Lowest());
        self->stream.set_verify_mode(asio::ssl::verify_peer);
        self->stream.set_verify_callback(asio::ssl::host_name_verification(self->url.host));
        // SNI, for servers behind a shared address.
        if (!SSL_set_tlsext_host_name(self->stream.native_handle(), self->url.host.c_str())) {
          return self->Fail("TLS: cannot set the server name");
        }
        self->stream.async_handshake(asio::ssl::stream_base::client, [self](beast::error_code shaken) {
          if (shaken) return self->Fail("TLS handshake: " + shaken.message());
          self->Send(self->stream);
        });
      });
    });
  }

  template <typename Stream>
  void Send(Stream& s) {
    http::async_write(s, request, [self = shared_from_this(), &s](beast::error_code written, std::size_t) {
      if (written) return self->Fail("cannot send: " + written.message());
      http::async_read(s, self->buffer, self->parser, [self](beast::error_code read, std::size_t) {
        // An answer too long to read whole still has its status.
        if (read && !(read == http::error::body_limit && self->parser.is_header_done())) {
          return self->Fail("no answer: " + read.message());
        }
        auto& answer = self->parser.get();
        beast::error_code ignored;
        self->Lowest().socket().shutdown(tcp::socket::shutdown_both, ignored);
        HttpAnswer out;
        out.status = static_cast<int>(answer.result_int());
        out.reason = std::string(answer.reason());
        if (!read) out.body = std::move(answer.body());
        self->Finish(std::move(out));
      });
    });
  }

  beast::tcp_stream& Lowest() { return beast::get_lowest_layer(stream); }
  void Fail(std::string why) {
    HttpAnswer out;
    out.error = std::move(why);
    Finish(std::move(out));
  }
  void Finish(HttpAnswer answer) {
    if (done) std::exchange(done, nullptr)(std::move(answer));
  }

  tcp::resolver resolver;
  beast::ssl_stream<beast::tcp_stream> stream;
  HttpUrl url;
  http::request<http::string_body> request;
  std::chrono::milliseconds timeout;
  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  std::function<void(HttpAnswer)> done;
};

}  // namespace

HttpUrl ParseHttpUrl(const std::string& url) {
  // scheme://host[:port][/path?query]; host: a name, IPv4, or [IPv6].
  static const std::regex kUrl(R"(^(https?)://([A-Za-z0-9._~-]+|\[[0-9A-Fa-f:.]+\])(?::([0-9]{1,5}))?([/?][^\s#]*)?$)",
                               std::regex::ECMAScript);
  std::smatch m;
  if (url.size() > 2000 || !std::regex_match(url, m, kUrl)) {
    throw std::invalid_argument("url: an http:// or https:// URL with a host, no user, spaces or fragment");
  }
  HttpUrl out;
  out.tls = m[1] == "https";
  out.host = m[2];
  if (out.host.front() == '[') out.host = out.host.substr(1, out.host.size() - 2);
  out.port = m[3].matched ? m[3].str() : (out.tls ? "443" : "80");
  if (const int port = std::stoi(out.port); port < 1 || port > 65535) {
    throw std::invalid_argument("url: the port must be 1 to 65535");
  }
  out.target = m[4].matched ? m[4].str() : "/";
  if (out.target.front() == '?') out.target = "/" + out.target;
  return out;
}

void HttpExchange(asio::io_context& io, asio::ssl::context& tls, const HttpUrl& url,
                  http::request<http::string_body> request, double timeout_s, std::function<void(HttpAnswer)> done,
                  std::size_t max_body_bytes) {
  request.set(http::field::host, url.host + ":" + url.port);
  std::make_shared<Exchange>(io, tls, url, std::move(request), timeout_s, std::move(done), max_body_bytes)->Start();
}

}  // namespace corridor::server
