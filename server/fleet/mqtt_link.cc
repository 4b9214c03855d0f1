#include "server/fleet/mqtt_link.h"

#include <chrono>
#include <stdexcept>

#include <mqtt/async_client.h>
#include <spdlog/spdlog.h>

namespace corridor::server {
namespace {

// Told when a connection attempt fails, so the next Connect() tries again.
class ConnectListener final : public mqtt::iaction_listener {
 public:
  ConnectListener(std::atomic<bool>& connecting, std::string broker)
      : connecting_(connecting), broker_(std::move(broker)) {}
  void on_failure(const mqtt::token& token) override {
    spdlog::debug("mqtt: cannot connect to {} (code {})", broker_, token.get_return_code());
    connecting_ = false;
  }
  void on_success(const mqtt::token&) override {}

 private:
  std::atomic<bool>& connecting_;
  std::string broker_;
};

}  // namespace

std::string PahoServerUri(const std::string& broker) {
  const auto scheme_end = broker.find("://");
  if (scheme_end == std::string::npos)
    throw std::invalid_argument("'" + broker + "' is not an MQTT URL (mqtt://host:port)");
  const std::string scheme = broker.substr(0, scheme_end);
  const std::string rest = broker.substr(scheme_end + 3);
  const auto colon = rest.rfind(':');
  if (rest.empty() || colon == std::string::npos || colon == 0 || colon + 1 == rest.size() ||
      rest.find_first_of("/?#") != std::string::npos ||
      rest.substr(colon + 1).find_first_not_of("0123456789") != std::string::npos) {
    throw std::invalid_argument("'" + broker + "' needs a host and a port (mqtt://host:port)");
  }
  if (scheme == "mqtt" || scheme == "tcp") return "tcp://" + rest;
  if (scheme == "mqtts" || scheme == "ssl") return "ssl://" + rest;
  throw std::invalid_argument("'" + broker + "': the scheme must be mqtt:// or mqtts://");
}

MqttLink::MqttLink(MqttLinkOptions options, OnMessage on_message, OnConnected on_connected)
    : options_(std::move(options)), on_message_(std::move(on_message)), on_connected_(std::move(on_connected)) {
  const std::string uri = PahoServerUri(options_.broker);
  mqtt::create_options create(MQTTVERSION_3_1_1);
  create.set_send_while_disconnected(true, true);
  create.set_max_buffered_messages(options_.max_buffered);
  create.set_delete_oldest_messages(true);
  client_ = std::make_unique<mqtt::async_client>(uri, options_.client_id, create);
  listener_ = std::make_unique<ConnectListener>(connecting_, options_.broker);
  client_->set_connected_handler([this](const std::string&) {
    connected_ = true;
    connecting_ = false;
    ever_connected_ = true;
    spdlog::info("mqtt: connected to {}", options_.broker);
    try {
      for (const std::string& topic : options_.subscriptions) client_->subscribe(topic, options_.subscription_qos);
    } catch (const mqtt::exception& e) {
      spdlog::warn("mqtt: cannot subscribe: {}", e.what());
    }
    if (on_connected_) on_connected_();
  });
  client_->set_connection_lost_handler([this](const std::string& cause) {
    connected_ = false;
    spdlog::warn("mqtt: lost the connection to {}{}; reconnecting", options_.broker, cause.empty() ? "" : ": " + cause);
  });
  client_->set_message_callback([this](mqtt::const_message_ptr message) {
    if (on_message_) on_message_(message->get_topic(), message->to_string());
  });
}

MqttLink::~MqttLink() { Stop({}); }

void MqttLink::Connect() {
  std::lock_guard lock(mutex_);
  if (stopped_ || connected_ || connecting_ || ever_connected_) return;
  const auto keep_alive = std::chrono::milliseconds(static_cast<long>(options_.keep_alive_s * 1000.0));
  mqtt::connect_options_builder builder;
  builder.clean_session(true)
      .keep_alive_interval(keep_alive)
      .connect_timeout(std::chrono::seconds(5))
      .automatic_reconnect(std::chrono::milliseconds(500), std::chrono::seconds(5));
  if (!options_.will.topic.empty()) {
    builder.will(mqtt::message(options_.will.topic, options_.will.payload, options_.will.qos, options_.will.retained));
  }
  connecting_ = true;
  try {
    client_->connect(builder.finalize(), nullptr, *listener_);
  } catch (const mqtt::exception& e) {
    connecting_ = false;
    spdlog::warn("mqtt: cannot connect to {}: {}", options_.broker, e.what());
  }
}

bool MqttLink::Publish(const MqttMessage& message) {
  try {
    client_->publish(message.topic, message.payload.data(), message.payload.size(), message.qos, message.retained);
    return true;
  } catch (const mqtt::exception& e) {
    spdlog::debug("mqtt: not sent to {}: {}", message.topic, e.what());
    return false;
  }
}

void MqttLink::Stop(const MqttMessage& farewell) {
  std::lock_guard lock(mutex_);
  if (stopped_) return;
  stopped_ = true;
  try {
    if (connected_ && !farewell.topic.empty()) {
      client_
          ->publish(farewell.topic, farewell.payload.data(), farewell.payload.size(), farewell.qos, farewell.retained)
          ->wait_for(std::chrono::seconds(2));
    }
    if (client_->is_connected() || connecting_ || ever_connected_) {
      client_->disconnect(std::chrono::milliseconds(500))->wait_for(std::chrono::seconds(2));
    }
  } catch (const mqtt::exception& e) {
    spdlog::debug("mqtt: disconnecting from {}: {}", options_.broker, e.what());
  }
  connected_ = false;
}

}  // namespace corridor::server
