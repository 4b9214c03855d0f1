// One embedded HTTP/1.1 + WebSocket server on one port (Boost.Beast on Asio), running on the io executor, over plain
// TCP or TLS (HTTPS and WSS, OpenSSL). HTTP requests go to Api::Handle; a WebSocket upgrade at /api/v1/stream opens a
// stream session that pushes the subscribed topics (by default "state") at the configured rate and accepts teleop
// messages. With TLS, a second port may answer plain HTTP with a redirect to HTTPS.
#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>

#include <memory>
#include <optional>

#include "server/api/api.h"
#include "server/api/tls.h"
#include "server/runtime/executor.h"

namespace corridor::server {

class HttpServer {
 public:
  // `tls`: serve HTTPS with this identity; nullopt: plain HTTP.
  HttpServer(Executor& io, const Api& api, const ServerOptions& options, std::optional<TlsIdentity> tls);
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;
  ~HttpServer();

  // Binds and starts accepting. Throws std::runtime_error when an address cannot be bound or the certificate and key
  // cannot be used.
  void Start();
  // Stops accepting; open sessions end with the io executor.
  void Stop();
  // The bound port (useful with port 0).
  unsigned short port() const;
  bool tls() const { return ssl_.has_value(); }

 private:
  void Accept();
  void AcceptRedirects();

  Executor& io_;
  const Api& api_;
  ServerOptions options_;
  std::optional<boost::asio::ssl::context> ssl_;
  boost::asio::ip::tcp::acceptor acceptor_;
  boost::asio::ip::tcp::acceptor redirect_acceptor_;
};

}  // namespace corridor::server
