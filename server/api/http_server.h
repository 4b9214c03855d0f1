// One embedded HTTP/1.1 + WebSocket server on one port (Boost.Beast on Asio), running on the io executor.
// HTTP requests go to Api::Handle; a WebSocket upgrade at /api/v1/stream opens a stream session that pushes the
// subscribed topics (by default "state") at the configured rate and accepts teleop messages.
#pragma once

#include <boost/asio/ip/tcp.hpp>

#include <memory>

#include "server/api/api.h"
#include "server/runtime/executor.h"

namespace corridor::server {

class HttpServer {
 public:
  HttpServer(Executor& io, const Api& api, const ServerOptions& options);
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;
  ~HttpServer();

  // Binds and starts accepting. Throws std::runtime_error when the address cannot be bound.
  void Start();
  // Stops accepting; open sessions end with the io executor.
  void Stop();
  // The bound port (useful with port 0).
  unsigned short port() const;

 private:
  void Accept();

  Executor& io_;
  const Api& api_;
  ServerOptions options_;
  boost::asio::ip::tcp::acceptor acceptor_;
};

}  // namespace corridor::server
