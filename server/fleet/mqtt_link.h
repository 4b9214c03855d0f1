// One MQTT client connection to a broker (Eclipse Paho's asynchronous C++ client): connects in the background and
// keeps trying until the broker answers, reconnects by itself after a loss (re-subscribing: the session is clean),
// holds what is published while disconnected and sends it on reconnection (the newest `max_buffered` messages), and
// leaves a last will with the broker. Callbacks run on Paho's threads: hand the work elsewhere.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace mqtt {
class async_client;
class iaction_listener;
}  // namespace mqtt

namespace corridor::server {

struct MqttMessage {
  std::string topic;
  std::string payload;
  int qos = 0;
  bool retained = false;
};

struct MqttLinkOptions {
  std::string broker;  // mqtt://host:port (also tcp://; mqtts:// and ssl:// for TLS)
  std::string client_id;
  MqttMessage will;  // empty topic: none
  std::vector<std::string> subscriptions;
  int subscription_qos = 0;
  int max_buffered = 1000;
  double keep_alive_s = 10.0;
};

class MqttLink {
 public:
  using OnMessage = std::function<void(std::string topic, std::string payload)>;
  using OnConnected = std::function<void()>;

  // Throws std::invalid_argument for a broker address that is not an MQTT URL.
  MqttLink(MqttLinkOptions options, OnMessage on_message, OnConnected on_connected);
  // Disconnects (without the last will), after `farewell` if Stop was not called.
  ~MqttLink();
  MqttLink(const MqttLink&) = delete;
  MqttLink& operator=(const MqttLink&) = delete;

  // Starts connecting, unless connected, connecting, or reconnecting by itself after a loss. Call it periodically
  // until the first connection: Paho retries by itself only once it has been connected.
  void Connect();
  // Queues `message`: sent now when connected, else on reconnection. Never throws; false when it was dropped.
  bool Publish(const MqttMessage& message);
  // Sends `farewell` (when it has a topic) and disconnects gracefully, so the broker does not send the last will.
  void Stop(const MqttMessage& farewell);
  bool connected() const { return connected_; }

 private:
  MqttLinkOptions options_;
  OnMessage on_message_;
  OnConnected on_connected_;
  std::unique_ptr<mqtt::iaction_listener> listener_;  // told of failed connection attempts; outlives client_
  std::unique_ptr<mqtt::async_client> client_;
  std::mutex mutex_;
  std::atomic<bool> connected_{false};
  std::atomic<bool> connecting_{false};
  std::atomic<bool> ever_connected_{false};
  bool stopped_ = false;  // guarded by mutex_
};

// The broker's address as Paho takes it: mqtt:// becomes tcp://, mqtts:// ssl://. Throws std::invalid_argument for
// anything else, or without host and port.
std::string PahoServerUri(const std::string& broker);

}  // namespace corridor::server
