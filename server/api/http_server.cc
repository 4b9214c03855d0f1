#include "server/api/http_server.h"

#include <array>

#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <spdlog/spdlog.h>

#include <deque>

namespace corridor::server {
namespace {

namespace beast = boost::beast;
namespace websocket = beast::websocket;
namespace ssl = boost::asio::ssl;
using tcp = boost::asio::ip::tcp;
using PlainStream = beast::tcp_stream;
using TlsStream = beast::ssl_stream<beast::tcp_stream>;

constexpr auto kReadTimeout = std::chrono::seconds(30);
constexpr auto kLingerTime = std::chrono::seconds(2);      // a lingering close reads on this long at most
constexpr std::size_t kMaxLingerBytes = 64 * 1024 * 1024;  // and this much
constexpr std::size_t kMaxStreamMessageBytes = 16 * 1024;
constexpr std::size_t kMaxQueuedStreamMessages = 16;

template <typename Stream>
constexpr bool kIsTls = std::is_same_v<Stream, TlsStream>;

Caller CallerOf(const tcp::socket& socket) {
  beast::error_code ec;
  const tcp::endpoint peer = socket.remote_endpoint(ec);
  if (ec) return {};
  auto address = peer.address();
  if (address.is_v6() && address.to_v6().is_v4_mapped()) address = address.to_v6().to_v4();
  return {address.to_string(), address.is_loopback(), false};
}

// One WebSocket client of /api/v1/stream, over `Stream` (plain or TLS).
template <typename Stream>
class StreamSession : public std::enable_shared_from_this<StreamSession<Stream>> {
 public:
  StreamSession(Stream stream, const Api& api, double rate_hz, Api::StreamAdmission admission)
      : ws_(std::move(stream)),
        api_(api),
        timer_(ws_.get_executor()),
        period_(std::chrono::nanoseconds(static_cast<std::int64_t>(1e9 / rate_hz))),
        who_(std::move(admission.who)),
        subscriptions_(std::move(admission.subscriptions)) {}

  void Start(Request request) {
    beast::get_lowest_layer(ws_).expires_never();
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(kMaxStreamMessageBytes);
    ws_.async_accept(request, [self = this->shared_from_this()](beast::error_code ec) {
      if (ec) return;
      self->Read();
      self->Push();
    });
  }

 private:
  void Read() {
    ws_.async_read(buffer_, [self = this->shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) {
        self->closed_ = true;
        self->timer_.cancel();
        return;
      }
      std::string text = beast::buffers_to_string(self->buffer_.data());
      self->buffer_.consume(self->buffer_.size());
      self->Send(Dump(self->api_.StreamReply(text, self->subscriptions_, self->who_)));
      self->Read();
    });
  }

  void Push() {
    if (closed_) return;
    for (const std::string& topic : subscriptions_) {
      if (auto message = api_.TopicMessage(topic)) Send(std::move(*message));
    }
    timer_.expires_after(period_);
    timer_.async_wait([self = this->shared_from_this()](beast::error_code ec) {
      if (!ec) self->Push();
    });
  }

  void Send(std::string text) {
    // A client that cannot keep up loses the oldest pushes rather than growing our memory.
    if (queue_.size() >= kMaxQueuedStreamMessages) queue_.pop_front();
    queue_.push_back(std::move(text));
    if (!writing_) Write();
  }

  void Write() {
    if (queue_.empty() || closed_) {
      writing_ = false;
      return;
    }
    writing_ = true;
    current_ = std::move(queue_.front());
    queue_.pop_front();
    ws_.text(true);
    ws_.async_write(boost::asio::buffer(current_),
                    [self = this->shared_from_this()](beast::error_code ec, std::size_t) {
                      if (ec) {
                        self->closed_ = true;
                        self->timer_.cancel();
                        return;
                      }
                      self->Write();
                    });
  }

  websocket::stream<Stream> ws_;
  const Api& api_;
  boost::asio::steady_timer timer_;
  std::chrono::nanoseconds period_;
  Identity who_;
  beast::flat_buffer buffer_;
  std::vector<std::string> subscriptions_;
  std::deque<std::string> queue_;
  std::string current_;
  bool writing_ = false;
  bool closed_ = false;
};

// One HTTP connection over `Stream` (plain or TLS): read a request, answer it, repeat while keep-alive. With
// `redirect_port` set, every request is answered with a redirect to HTTPS on that port instead.
template <typename Stream>
class HttpSession : public std::enable_shared_from_this<HttpSession<Stream>> {
 public:
  HttpSession(Stream stream, const Api& api, const ServerOptions& options, int redirect_port = 0)
      : stream_(std::move(stream)),
        api_(api),
        options_(options),
        redirect_port_(redirect_port),
        caller_(CallerOf(beast::get_lowest_layer(stream_).socket())) {}

  void Start() {
    if constexpr (kIsTls<Stream>) {
      beast::get_lowest_layer(stream_).expires_after(kReadTimeout);
      stream_.async_handshake(ssl::stream_base::server, [self = this->shared_from_this()](beast::error_code ec) {
        if (!ec) self->Read();
      });
    } else {
      Read();
    }
  }

 private:
  void Read() {
    parser_.emplace();
    parser_->body_limit(static_cast<std::uint64_t>(options_.max_body_bytes));
    parser_->header_limit(16 * 1024);
    beast::get_lowest_layer(stream_).expires_after(kReadTimeout);
    http::async_read(stream_, buffer_, *parser_,
                     [self = this->shared_from_this()](beast::error_code ec, std::size_t) { self->OnRead(ec); });
  }

  void OnRead(beast::error_code ec) {
    if (ec == http::error::end_of_stream || ec == beast::error::timeout || ec == boost::asio::error::eof) {
      return Close();
    }
    if (ec == http::error::body_limit) {
      return Reply(ProblemResponse(
          http::status::payload_too_large, "Payload too large",
          "request bodies are limited to " + std::to_string(options_.max_body_bytes) + " bytes", 11, false));
    }
    if (ec == http::error::header_limit) {
      return Reply(ProblemResponse(http::status::request_header_fields_too_large, "Headers too large",
                                   "request headers are limited to 16 KiB", 11, false));
    }
    if (ec) {
      if (ec.category() == ssl::error::get_stream_category() || ec == ssl::error::stream_truncated) return;
      return Reply(ProblemResponse(http::status::bad_request, "Malformed request", ec.message(), 11, false));
    }
    Request request = parser_->release();
    if (redirect_port_ != 0) return Redirect(request);
    if (websocket::is_upgrade(request)) return Upgrade(std::move(request));
    api_.Handle(request, caller_,
                [self = this->shared_from_this()](Response response) { self->Reply(std::move(response)); });
  }

  // Plain HTTP beside HTTPS: the same path on https://, so bookmarks and typed addresses still work.
  void Redirect(const Request& request) {
    std::string host(request[http::field::host]);
    if (host.empty() || host.find_first_of("/\\ @") != std::string::npos) host = "localhost";
    // Drop the port: the text after the last ':', unless that ':' is inside an IPv6 literal's brackets.
    const auto colon = host.rfind(':');
    const auto bracket = host.rfind(']');
    if (colon != std::string::npos && (bracket == std::string::npos || colon > bracket)) host.resize(colon);
    Response res{http::status::permanent_redirect, request.version()};
    res.set(http::field::server, "corridord");
    res.set(http::field::location,
            "https://" + host + ":" + std::to_string(redirect_port_) + std::string(request.target()));
    res.keep_alive(false);
    res.prepare_payload();
    Reply(std::move(res));
  }

  // A WebSocket at /api/v1/stream, for a caller who may read (or the robot's own screen), from a page of our own
  // origin when a browser opens it.
  void Upgrade(Request request) {
    const std::string_view target = request.target();
    const std::string path(target.substr(0, target.find('?')));
    if (path != "/api/v1/stream") {
      return Reply(ProblemResponse(http::status::not_found, "Not found", "WebSocket is served at /api/v1/stream",
                                   request.version(), false));
    }
    Api::StreamAdmission admission;
    try {
      admission = api_.AdmitStream(request, caller_);
    } catch (const ApiError& e) {
      return Reply(ProblemResponse(e.status(), e.title(), e.what(), request.version(), false, e.code()));
    }
    std::make_shared<StreamSession<Stream>>(std::move(stream_), api_, options_.stream_rate_hz, std::move(admission))
        ->Start(std::move(request));
  }

  void Reply(Response response) {
    auto shared = std::make_shared<Response>(std::move(response));
    http::async_write(stream_, *shared, [self = this->shared_from_this(), shared](beast::error_code ec, std::size_t) {
      if (ec) return;
      if (!shared->keep_alive()) return self->Close();
      self->Read();
    });
  }

  void Close() {
    if constexpr (kIsTls<Stream>) {
      beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(5));
      stream_.async_shutdown([self = this->shared_from_this()](beast::error_code) {});
    } else {
      beast::error_code ec;
      stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
      // A lingering close: what the client still sends (the rest of a refused body) is read and dropped for a
      // moment, else the kernel resets the connection and the client may lose the answer before reading it.
      beast::get_lowest_layer(stream_).expires_after(kLingerTime);
      Drain(0);
    }
  }

  void Drain(std::size_t drained) {
    stream_.async_read_some(boost::asio::buffer(drain_),
                            [self = this->shared_from_this(), drained](beast::error_code ec, std::size_t n) {
                              if (!ec && drained + n < kMaxLingerBytes) self->Drain(drained + n);
                            });
  }

  Stream stream_;
  const Api& api_;
  const ServerOptions& options_;
  int redirect_port_;
  Caller caller_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::array<char, 16 * 1024> drain_{};
};

tcp::endpoint Endpoint(const std::string& bind_address, int port) {
  beast::error_code ec;
  const auto address = boost::asio::ip::make_address(bind_address, ec);
  if (ec) throw std::runtime_error("server.bind_address: '" + bind_address + "' is not an IP address");
  return {address, static_cast<unsigned short>(port)};
}

void Listen(tcp::acceptor& acceptor, const tcp::endpoint& endpoint) {
  beast::error_code ec;
  acceptor.open(endpoint.protocol());
  acceptor.set_option(boost::asio::socket_base::reuse_address(true));
  acceptor.bind(endpoint, ec);
  if (ec) {
    throw std::runtime_error("cannot listen on " + endpoint.address().to_string() + ":" +
                             std::to_string(endpoint.port()) + ": " + ec.message());
  }
  acceptor.listen(boost::asio::socket_base::max_listen_connections);
}

}  // namespace

HttpServer::HttpServer(Executor& io, const Api& api, const ServerOptions& options, std::optional<TlsIdentity> tls)
    : io_(io), api_(api), options_(options), acceptor_(io.context()), redirect_acceptor_(io.context()) {
  if (tls) {
    ssl_.emplace(ssl::context::tls_server);
    ssl_->set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 | ssl::context::no_sslv3 |
                      ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1 | ssl::context::single_dh_use);
    beast::error_code ec;
    ssl_->use_certificate_chain_file(tls->certificate.string(), ec);
    if (ec) throw std::runtime_error("server.tls.certificate: " + tls->certificate.string() + ": " + ec.message());
    ssl_->use_private_key_file(tls->key.string(), ssl::context::pem, ec);
    if (ec) throw std::runtime_error("server.tls.key: " + tls->key.string() + ": " + ec.message());
  }
}

HttpServer::~HttpServer() { Stop(); }

void HttpServer::Start() {
  Listen(acceptor_, Endpoint(options_.bind_address, options_.port));
  Accept();
  if (ssl_ && options_.tls.redirect_port != 0) {
    Listen(redirect_acceptor_, Endpoint(options_.bind_address, options_.tls.redirect_port));
    AcceptRedirects();
  }
}

void HttpServer::Stop() {
  boost::system::error_code ec;
  acceptor_.close(ec);
  redirect_acceptor_.close(ec);
}

unsigned short HttpServer::port() const { return acceptor_.local_endpoint().port(); }

void HttpServer::Accept() {
  acceptor_.async_accept(io_.context(), [this](beast::error_code ec, tcp::socket socket) {
    if (ec == boost::asio::error::operation_aborted) return;
    if (!ec) {
      if (ssl_) {
        std::make_shared<HttpSession<TlsStream>>(TlsStream(std::move(socket), *ssl_), api_, options_)->Start();
      } else {
        std::make_shared<HttpSession<PlainStream>>(PlainStream(std::move(socket)), api_, options_)->Start();
      }
    }
    Accept();
  });
}

void HttpServer::AcceptRedirects() {
  redirect_acceptor_.async_accept(io_.context(), [this](beast::error_code ec, tcp::socket socket) {
    if (ec == boost::asio::error::operation_aborted) return;
    if (!ec) {
      std::make_shared<HttpSession<PlainStream>>(PlainStream(std::move(socket)), api_, options_, port())->Start();
    }
    AcceptRedirects();
  });
}

}  // namespace corridor::server
