#include "server/api/webhooks.h"

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <nlohmann/json.hpp>
#include <openssl/evp.h>
#include <openssl/rand.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace corridor::server {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;

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
    HttpUrl url;
    try {
      url = ParseHttpUrl(webhook->url);
    } catch (const std::invalid_argument& e) {
      p.in_flight = true;
      asio::post(io_, [this, alive = alive_, id = id, why = std::string(e.what())] {
        if (*alive) Finished(id, 0, why);
      });
      continue;
    }
    http::request<http::string_body> request{http::verb::post, url.target, 11};
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
    HttpExchange(io_, tls_, url, std::move(request), options_.timeout_s,
                 [this, alive = alive_, id = id](const HttpAnswer& answer) {
                   if (!*alive) return;
                   // The receiver's answer counts only by its status.
                   const bool ok = answer.status >= 200 && answer.status < 300;
                   Finished(id, answer.status,
                            answer.status == 0 ? answer.error
                            : ok               ? ""
                                               : std::to_string(answer.status) + " " + answer.reason);
                 });
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
