#include "server/api/http_server.h"

#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <spdlog/spdlog.h>

#include <deque>

namespace corridor::server {
namespace {

namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = boost::asio::ip::tcp;

constexpr auto kReadTimeout = std::chrono::seconds(30);
constexpr std::size_t kMaxStreamMessageBytes = 16 * 1024;
constexpr std::size_t kMaxQueuedStreamMessages = 16;

// One WebSocket client of /api/v1/stream.
class StreamSession : public std::enable_shared_from_this<StreamSession> {
 public:
  StreamSession(tcp::socket socket, const Api& api, double rate_hz, Api::Identity who, bool sees_state)
      : ws_(std::move(socket)), api_(api), timer_(ws_.get_executor()),
        period_(std::chrono::nanoseconds(static_cast<std::int64_t>(1e9 / rate_hz))), who_(std::move(who)) {
    if (!sees_state) subscriptions_.clear();  // the face screen subscribes to what it shows
  }

  void Start(Request request) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(kMaxStreamMessageBytes);
    ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
      if (ec) return;
      self->Read();
      self->Push();
    });
  }

 private:
  void Read() {
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
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
      if (auto message = api_.TopicMessage(topic)) Send(Dump(*message));
    }
    timer_.expires_after(period_);
    timer_.async_wait([self = shared_from_this()](beast::error_code ec) {
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
    ws_.async_write(boost::asio::buffer(current_), [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) {
        self->closed_ = true;
        self->timer_.cancel();
        return;
      }
      self->Write();
    });
  }

  websocket::stream<beast::tcp_stream> ws_;
  const Api& api_;
  boost::asio::steady_timer timer_;
  std::chrono::nanoseconds period_;
  Api::Identity who_;
  beast::flat_buffer buffer_;
  std::vector<std::string> subscriptions_{"state"};
  std::deque<std::string> queue_;
  std::string current_;
  bool writing_ = false;
  bool closed_ = false;
};

// One HTTP connection: read a request, answer it, repeat while keep-alive.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, const Api& api, const ServerOptions& options)
      : stream_(std::move(socket)), api_(api), options_(options) {}

  void Read() {
    parser_.emplace();
    parser_->body_limit(static_cast<std::uint64_t>(options_.max_body_bytes));
    parser_->header_limit(16 * 1024);
    stream_.expires_after(kReadTimeout);
    http::async_read(stream_, buffer_, *parser_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      self->OnRead(ec);
    });
  }

 private:
  void OnRead(beast::error_code ec) {
    if (ec == http::error::end_of_stream || ec == beast::error::timeout || ec == boost::asio::error::eof) {
      stream_.socket().shutdown(tcp::socket::shutdown_both, ec);
      return;
    }
    if (ec == http::error::body_limit) {
      return Reply(ProblemResponse(http::status::payload_too_large, "Payload too large",
                                   "request bodies are limited to " + std::to_string(options_.max_body_bytes) + " bytes",
                                   11, false));
    }
    if (ec == http::error::header_limit) {
      return Reply(ProblemResponse(http::status::request_header_fields_too_large, "Headers too large",
                                   "request headers are limited to 16 KiB", 11, false));
    }
    if (ec) {
      return Reply(ProblemResponse(http::status::bad_request, "Malformed request", ec.message(), 11, false));
    }
    Request request = parser_->release();
    const Caller caller = CallerOf(stream_.socket());
    if (websocket::is_upgrade(request)) return Upgrade(std::move(request), caller);
    api_.Handle(request, caller, [self = shared_from_this()](Response response) { self->Reply(std::move(response)); });
  }

  static Caller CallerOf(const tcp::socket& socket) {
    beast::error_code ec;
    const tcp::endpoint peer = socket.remote_endpoint(ec);
    if (ec) return {};
    auto address = peer.address();
    if (address.is_v6() && address.to_v6().is_v4_mapped()) address = address.to_v6().to_v4();
    return {address.to_string(), address.is_loopback(), false};
  }

  // A WebSocket at /api/v1/stream, for a caller who may read (or the robot's own screen), from a page of our own
  // origin when a browser opens it.
  void Upgrade(Request request, const Caller& caller) {
    const std::string_view target = request.target();
    const std::string path(target.substr(0, target.find('?')));
    if (path != "/api/v1/stream") {
      return Reply(ProblemResponse(http::status::not_found, "Not found", "WebSocket is served at /api/v1/stream",
                                   request.version(), false));
    }
    Api::Identity who;
    try {
      who = api_.Identify(request, caller);
      api_.CheckAccess(request, caller, who, path);
      const std::string_view origin = request[http::field::origin];
      if (!origin.empty() && !auth::SameOrigin(origin, request[http::field::host])) {
        throw ApiError(http::status::forbidden, "Cross-site WebSocket refused",
                       "the stream opens only from the console's own origin", "cross_site");
      }
    } catch (const ApiError& e) {
      return Reply(ProblemResponse(e.status(), e.title(), e.what(), request.version(), false, e.code()));
    }
    const bool sees_state = who.who.has_value() || api_.anonymous_viewer();
    stream_.expires_never();
    std::make_shared<StreamSession>(stream_.release_socket(), api_, options_.stream_rate_hz, std::move(who), sees_state)
        ->Start(std::move(request));
  }

  void Reply(Response response) {
    auto shared = std::make_shared<Response>(std::move(response));
    http::async_write(stream_, *shared, [self = shared_from_this(), shared](beast::error_code ec, std::size_t) {
      if (ec) return;
      if (!shared->keep_alive()) {
        self->stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
        return;
      }
      self->Read();
    });
  }

  beast::tcp_stream stream_;
  const Api& api_;
  const ServerOptions& options_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
};

}  // namespace

HttpServer::HttpServer(Executor& io, const Api& api, const ServerOptions& options)
    : io_(io), api_(api), options_(options), acceptor_(io.context()) {}

HttpServer::~HttpServer() { Stop(); }

void HttpServer::Start() {
  beast::error_code ec;
  const auto address = boost::asio::ip::make_address(options_.bind_address, ec);
  if (ec) throw std::runtime_error("server.bind_address: '" + options_.bind_address + "' is not an IP address");
  const tcp::endpoint endpoint(address, static_cast<unsigned short>(options_.port));
  acceptor_.open(endpoint.protocol());
  acceptor_.set_option(boost::asio::socket_base::reuse_address(true));
  acceptor_.bind(endpoint, ec);
  if (ec) {
    throw std::runtime_error("cannot listen on " + options_.bind_address + ":" + std::to_string(options_.port) + ": " +
                             ec.message());
  }
  acceptor_.listen(boost::asio::socket_base::max_listen_connections);
  Accept();
}

void HttpServer::Stop() {
  boost::system::error_code ec;
  acceptor_.close(ec);
}

unsigned short HttpServer::port() const { return acceptor_.local_endpoint().port(); }

void HttpServer::Accept() {
  acceptor_.async_accept(io_.context(), [this](beast::error_code ec, tcp::socket socket) {
    if (ec == boost::asio::error::operation_aborted) return;
    if (!ec) std::make_shared<HttpSession>(std::move(socket), api_, options_)->Read();
    Accept();
  });
}

}  // namespace corridor::server
