// Webhooks: the robot's events (face/events.h) POSTed as JSON to the URLs building systems subscribed
// (/api/v1/webhooks, kept in the database). Each delivery is signed with HMAC-SHA256 of the body under the webhook's
// secret (header X-Corridor-Signature: sha256=<hex>), recorded in the database with how it went, and retried with
// exponential backoff while the receiver cannot be reached, times out, or answers 408, 429 or 5xx; any other answer
// outside 2xx fails it at once (the receiver refuses it; sending it again would not help). Deliveries still pending
// when the daemon stops are sent after it starts again.
//
// Runs on the io executor (never the control path): Publish, Ping, Dispatch and Forget must be called there. HTTP and
// HTTPS (OpenSSL: the system's trusted certificates, or options.ca_file) through Boost.Beast, asynchronously, each
// attempt bounded by options.timeout_s.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ssl/context.hpp>
#include <nlohmann/json.hpp>

#include <map>
#include <memory>
#include <optional>
#include <string>

#include "drivers/clock.h"
#include "server/api/http_client.h"
#include "server/config/config.h"
#include "server/runtime/event_log.h"
#include "server/store/store.h"

namespace corridor::server {

// "sha256=" and the lower-case hex of HMAC-SHA256(secret, body).
std::string WebhookSignature(const std::string& secret, const std::string& body);
// 32 random bytes from OpenSSL's CSPRNG as 64 hex digits: a secret for a webhook that brought none.
std::string NewWebhookSecret();

class Webhooks {
 public:
  // Loads the deliveries still pending from the store (due at once). Throws std::runtime_error when options.ca_file
  // cannot be read.
  Webhooks(boost::asio::io_context& io, Store& store, const drivers::Clock& clock, const WebhookOptions& options);
  Webhooks(const Webhooks&) = delete;
  Webhooks& operator=(const Webhooks&) = delete;
  ~Webhooks();

  // Queues `event` (ToJson of a LoggedEvent) for every webhook subscribed to its type.
  void Publish(const nlohmann::json& event);
  // Queues a "ping" event for one webhook (to check a subscription works). Returns the delivery's id.
  std::string Ping(const WebhookRecord& webhook);
  // Starts the attempts that are due.
  void Dispatch();
  // Drops what is queued for a webhook that was deleted (attempts in flight finish unrecorded).
  void Forget(const std::string& webhook_id);

 private:
  struct Pending {
    DeliveryRecord record;
    drivers::TimeNs due_ns = 0;
    bool in_flight = false;
  };

  // Returns the new delivery's id.
  std::string Queue(const WebhookRecord& webhook, const std::string& type, const std::string& payload);
  void Finished(const std::string& delivery_id, int status, const std::string& error);
  void Save(const DeliveryRecord& record);

  boost::asio::io_context& io_;
  Store& store_;
  const drivers::Clock& clock_;
  WebhookOptions options_;
  boost::asio::ssl::context tls_;
  std::map<std::string, Pending> pending_;                      // by delivery id
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);  // attempts in flight check it before calling back
};

}  // namespace corridor::server
