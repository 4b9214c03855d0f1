#include "server/api/webhooks.h"

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/host_name_verification.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <nlohmann/json.hpp>
#include <openssl/evp.h>
#include <openssl/rand.h>
#include <openssl/ssl.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <regex>
#include <stdexcept>

namespace corridor::server {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

constexpr std::size_t kMaxAnswerBytes = 64 * 1024;  // a receiver's answer is read only for its status

// Worth another attempt: the receiver may take it later.
bool Retryable(int status) { return status == 0 || status == 408 || status == 429 || status >= 500; }

std::string Now() { return IsoUtc(std::chrono::system_clock::now()); }

std::string Hex(const unsigned char* bytes, std::size_t size) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < size; ++i) {
    out += kDigits[bytes[i] >> 4];
    out += kDigits[bytes[i] & 15];
  }
  return out;
}

}  // namespace

WebhookUrl ParseWebhookUrl(const std::string& url) {
  // scheme://host[:port][/path?query]; host: a name, IPv4, or [IPv6].
  static const std::regex kUrl(R"(^(https?)://([A-Za-z0-9._~-]+|\[[0-9A-Fa-f:.]+\])(?::([0-9]{1,5}))?([/?][^\s#]*)?$)",
                               std::regex::ECMAScript);
  std::smatch m;
  if (url.size() > 2000 || !std::regex_match(url, m, kUrl)) {
    throw std::invalid_argument("url: an http:// or https:// URL with a host, no user, spaces or fragment");
  }
  WebhookUrl out;
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

std::string WebhookSignature(const std::string& secret, const std::string& body) {
  std::array<unsigned char, EVP_MAX_MD_SIZE> mac{};
  std::size_t length = 0;
  if (EVP_Q_mac(nullptr, "HMAC", nullptr, "SHA256", nullptr, secret.data(), secret.size(),
                reinterpret_cast<const unsigned char*>(body.data()), body.size(), mac.data(), mac.size(),
                &length) == nullptr) {
    throw std::runtime_error("webhooks: HMAC-SHA256 failed");
  }
  return "sha256=" + Hex(mac.data(), length);
}

std::string NewWebhookSecret() {
  std::array<unsigned char, 32> bytes{};
  if (RAND_bytes(bytes.data(), static_cast<int>(bytes.size())) != 1) {
    throw std::runtime_error("webhooks: no random bytes for a secret");
  }
  return Hex(bytes.data(), bytes.size());
}

// One POST: resolve, connect, (TLS handshake), send, read the status line and headers, close. Every step is bounded
// by the stream's deadline; `done` is called once with the receiver's status (0 when there was none) and, on failure,
// why.
struct Webhooks::Attempt : std::enable_shared_from_this<Attempt> {
  using Done = std::function<void(int status, std::string error)>;

  Attempt(asio::io_context& io, asio::ssl::context& tls, WebhookUrl to, http::request<http::string_body> post,
          double timeout_s, Done on_done)
      : resolver(io),
        stream(io, tls),
        url(std::move(to)),
        request(std::move(post)),
        timeout(std::chrono::milliseconds(static_cast<long>(timeout_s * 1000.0))),
        done(std::move(on_done)) {
    parser.body_limit(kMaxAnswerBytes);
  }

  void Start() {
    resolver.async_resolve(url.host, url.port, [self = shared_from_this()](beast::error_code resolved, auto results) {
      if (resolved) return self->Fail("cannot resolve " + self->url.host + ": " + resolved.message());
      self->Lowest().expires_after(self->timeout);
      self->Lowest().async_connect(results, [self](beast::error_code connected, const tcp::endpoint&) {
        if (connected) return self->Fail("cannot connect: " + connected.message());
        if (!self->url.tls) return self->Exchange(self->Lowest());
        self->stream.set_verify_mode(asio::ssl::verify_peer);
        self->stream.set_verify_callback(asio::ssl::host_name_verification(self->url.host));
        // SNI, for receivers behind a shared address.
        if (!SSL_set_tlsext_host_name(self->stream.native_handle(), self->url.host.c_str())) {
          return self->Fail("TLS: cannot set the server name");
        }
        self->stream.async_handshake(asio::ssl::stream_base::client, [self](beast::error_code shaken) {
          if (shaken) return self->Fail("TLS handshake: " + shaken.message());
          self->Exchange(self->stream);
        });
      });
    });
  }

  template <typename Stream>
  void Exchange(Stream& s) {
    http::async_write(s, request, [self = shared_from_this(), &s](beast::error_code written, std::size_t) {
      if (written) return self->Fail("cannot send: " + written.message());
      http::async_read(s, self->buffer, self->parser, [self](beast::error_code read, std::size_t) {
        // An answer too long to read whole still has its status.
        if (read && !(read == http::error::body_limit && self->parser.is_header_done())) {
          return self->Fail("no answer: " + read.message());
        }
        const auto& answer = self->parser.get();
        const int status = static_cast<int>(answer.result_int());
        beast::error_code ignored;
        self->Lowest().socket().shutdown(tcp::socket::shutdown_both, ignored);
        self->Finish(status, status >= 200 && status < 300
                                 ? ""
                                 : std::to_string(status) + " " + std::string(answer.reason()));
      });
    });
  }

  beast::tcp_stream& Lowest() { return beast::get_lowest_layer(stream); }
  void Fail(const std::string& why) { Finish(0, why); }
  void Finish(int status, const std::string& error) {
    if (done) std::exchange(done, nullptr)(status, error);
  }

  tcp::resolver resolver;
  beast::ssl_stream<beast::tcp_stream> stream;
  WebhookUrl url;
  http::request<http::string_body> request;
  std::chrono::milliseconds timeout;
  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  Done done;
};

Webhooks::Webhooks(asio::io_context& io, Store& store, const drivers::Clock& clock, const WebhookOptions& options)
    : io_(io), store_(store), clock_(clock), options_(options), tls_(asio::ssl::context::tls_client) {
  tls_.set_default_verify_paths();
  if (!options.ca_file.empty()) {
    beast::error_code ec;
    tls_.load_verify_file(options.ca_file, ec);
    if (ec) throw std::runtime_error("webhooks.ca_file " + options.ca_file + ": " + ec.message());
  }
  const drivers::TimeNs now = clock_.Now();
  for (DeliveryRecord& d : store_.PendingDeliveries()) {
    const std::string id = d.id;
    pending_[id] = {std::move(d), now, false};
  }
}

Webhooks::~Webhooks() { *alive_ = false; }

void Webhooks::Publish(const nlohmann::json& event) {
  const std::string type = event.at("type").get<std::string>();
  std::vector<WebhookRecord> subscribed;
  for (WebhookRecord& w : store_.Webhooks()) {
    if (std::find(w.events.begin(), w.events.end(), type) != w.events.end()) subscribed.push_back(std::move(w));
  }
  if (subscribed.empty()) return;
  nlohmann::json payload = event;
  payload["id"] = NewId();
  payload["robot"] = options_.robot;
  const std::string body = payload.dump();
  for (const WebhookRecord& w : subscribed) Queue(w, type, body);
}

std::string Webhooks::Ping(const WebhookRecord& webhook) {
  const nlohmann::json payload = {{"id", NewId()},
                                  {"time", Now()},
                                  {"type", "ping"},
                                  {"robot", options_.robot},
                                  {"data", {{"webhook", webhook.id}}}};
  return Queue(webhook, "ping", payload.dump());
}

std::string Webhooks::Queue(const WebhookRecord& webhook, const std::string& type, const std::string& payload) {
  DeliveryRecord d;
  d.id = NewId();
  d.webhook = webhook.id;
  d.event = type;
  d.payload = payload;
  d.created = Now();
  // Too many undelivered for this webhook: its receiver is gone; the oldest fails rather than memory growing.
  std::vector<std::pair<std::string, std::string>> mine;  // (created, id) of its pending deliveries
  for (const auto& [id, p] : pending_) {
    if (p.record.webhook == webhook.id && !p.in_flight) mine.emplace_back(p.record.created, id);
  }
  if (static_cast<int>(mine.size()) >= options_.max_pending) {
    std::sort(mine.begin(), mine.end());
    Pending& oldest = pending_.at(mine.front().second);
    oldest.record.status = "failed";
    oldest.record.error = "dropped: " + std::to_string(mine.size()) + " deliveries waiting for this receiver";
    Save(oldest.record);
    pending_.erase(mine.front().second);
  }
  try {
    store_.AddDelivery(d, options_.keep_deliveries);
  } catch (const StoreError& e) {
    // Not kept across a restart, but still sent.
    spdlog::warn("webhooks: delivery {} not recorded: {}", d.id, e.what());
  }
  const std::string id = d.id;
  pending_[id] = {std::move(d), clock_.Now(), false};
  return id;
}

void Webhooks::Dispatch() {
  const drivers::TimeNs now = clock_.Now();
  for (auto& [id, p] : pending_) {
    if (p.in_flight || p.due_ns > now) continue;
    const std::optional<WebhookRecord> webhook = store_.Webhook(p.record.webhook);
    if (!webhook) continue;  // deleted; Forget drops it
    WebhookUrl url;
    try {
      url = ParseWebhookUrl(webhook->url);
    } catch (const std::invalid_argument& e) {
      p.in_flight = true;
      asio::post(io_, [this, alive = alive_, id = id, why = std::string(e.what())] {
        if (*alive) Finished(id, 0, why);
      });
      continue;
    }
    http::request<http::string_body> request{http::verb::post, url.target, 11};
    request.set(http::field::host, url.host + ":" + url.port);
    request.set(http::field::user_agent, "corridord");
    request.set(http::field::content_type, "application/json");
    request.set("X-Corridor-Event", p.record.event);
    request.set("X-Corridor-Delivery", p.record.id);
    request.set("X-Corridor-Signature", WebhookSignature(webhook->secret, p.record.payload));
    request.body() = p.record.payload;
    request.prepare_payload();
    p.in_flight = true;
    p.record.last_attempt = Now();
    ++p.record.attempts;
    std::make_shared<Attempt>(io_, tls_, std::move(url), std::move(request), options_.timeout_s,
                              [this, alive = alive_, id = id](int status, std::string error) {
                                if (*alive) Finished(id, status, error);
                              })
        ->Start();
  }
}

void Webhooks::Finished(const std::string& delivery_id, int status, const std::string& error) {
  const auto it = pending_.find(delivery_id);
  if (it == pending_.end()) return;  // forgotten meanwhile
  DeliveryRecord& d = it->second.record;
  d.response_status = status;
  d.error = error;
  if (error.empty()) {
    d.status = "delivered";
  } else if (!Retryable(status) || d.attempts >= options_.max_attempts) {
    d.status = "failed";
    spdlog::warn("webhooks: delivery {} of {} to webhook {} failed after {} attempts: {}", d.id, d.event, d.webhook,
                 d.attempts, error);
  }
  Save(d);
  if (d.status != "pending") {
    pending_.erase(it);
    return;
  }
  const double wait_s =
      std::min(options_.max_retry_s, options_.first_retry_s * std::pow(2.0, std::max(0, d.attempts - 1)));
  it->second.due_ns = clock_.Now() + drivers::FromSeconds(wait_s);
  it->second.in_flight = false;
}

void Webhooks::Forget(const std::string& webhook_id) {
  std::erase_if(pending_, [&](const auto& entry) { return entry.second.record.webhook == webhook_id; });
}

void Webhooks::Save(const DeliveryRecord& record) {
  try {
    store_.UpdateDelivery(record);
  } catch (const StoreError& e) {
    spdlog::warn("webhooks: delivery {} not recorded: {}", record.id, e.what());
  }
}

}  // namespace corridor::server
