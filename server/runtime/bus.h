// The in-process topic bus. A topic has one name and one message type; publishers hand it immutable messages
// (shared_ptr<const T>), it keeps the latest, and each subscriber gets messages on its own executor. A subscriber
// that falls behind gets the newest message, not a backlog: a control loop must act on the latest frame. A topic of
// events that must each be handled (a mission's state to record, a lift's arrival on a floor) delivers every message,
// in order, as a ROS 2 topic with a keep-all history does. A latched topic (what holds, such as the map in use, rather
// than what happens) also gives a new subscriber its latest message at once, as one with transient-local durability.
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <typeinfo>
#include <utility>
#include <vector>

#include "nav/demand.h"
#include "server/runtime/executor.h"
#include "server/runtime/messages.h"

namespace corridor::server {

// What a subscriber that falls behind gets: the newest message only, or every message in order.
enum class Delivery { kNewest, kEvery };

// A topic's name carrying its message type, so that publisher and subscriber agree at compile time.
template <typename T>
struct TopicName {
  std::string_view name;
  bool latched = false;
  Delivery delivery = Delivery::kNewest;
};

template <typename T>
concept JsonMessage = requires(const T& message) {
  { ToJson(message) } -> std::same_as<nlohmann::json>;
};

class TopicBase {
 public:
  TopicBase(std::string name, bool latched, Delivery delivery)
      : name_(std::move(name)), latched_(latched), delivery_(delivery) {}
  TopicBase(const TopicBase&) = delete;
  TopicBase& operator=(const TopicBase&) = delete;
  virtual ~TopicBase() = default;

  const std::string& name() const { return name_; }
  bool latched() const { return latched_; }
  Delivery delivery() const { return delivery_; }
  virtual const std::type_info& type() const = 0;
  // The latest message as JSON; nullopt before the first message or for binary types (camera frames).
  virtual std::optional<nlohmann::json> LatestJson() const = 0;

 private:
  std::string name_;
  bool latched_;
  Delivery delivery_;
};

template <typename T>
class Topic final : public TopicBase {
 public:
  using Message = std::shared_ptr<const T>;
  using Callback = std::function<void(const Message&)>;

  using TopicBase::TopicBase;

  const std::type_info& type() const override { return typeid(T); }

  // Thread-safe. Stores the message as the latest and schedules delivery to every subscriber, those on an urgent
  // executor (the control loop's) first: each delivery wakes a thread, which the scheduler may run at once in the
  // publisher's place, and a depth frame must not wait behind the mapping's wake-up to reach the control loop.
  void Publish(Message message) {
    DEMAND(message != nullptr);
    std::shared_ptr<const Listeners> listeners;
    Message replaced;  // freed after the deliveries are scheduled (a depth frame's buffers take a while to free)
    {
      std::lock_guard lock(mutex_);
      replaced = std::exchange(latest_, message);
      listeners = listeners_;
    }
    for (const auto& tap : listeners->taps) tap(*message);
    for (const auto& s : listeners->subscribers) s->Offer(message);
  }
  void Publish(T message) { Publish(std::make_shared<const T>(std::move(message))); }

  Message latest() const {
    std::lock_guard lock(mutex_);
    return latest_;
  }

  // Delivers future messages to `callback` on `executor`, and on a latched topic the latest one first. Thread-safe.
  void Subscribe(Executor& executor, Callback callback) {
    auto s = std::make_shared<Subscriber>(executor, std::move(callback), delivery() == Delivery::kEvery);
    std::lock_guard lock(mutex_);
    auto next = std::make_shared<Listeners>(*listeners_);
    auto& subscribers = next->subscribers;
    const auto at = executor.urgent() ? std::find_if(subscribers.begin(), subscribers.end(),
                                                     [](const auto& other) { return !other->executor.urgent(); })
                                      : subscribers.end();
    subscribers.insert(at, s);
    listeners_ = std::move(next);
    if (latched() && latest_) s->Offer(latest_);
  }

  // Runs `tap` with each message on the publisher's thread, before the deliveries: for what must see each message
  // when it comes and costs less than waking a thread for it (a device's arrivals counted, a pose made from odometry
  // and published), never for work or anything that may block. Thread-safe; a tap stays as long as the topic.
  void Tap(std::function<void(const T&)> tap) {
    std::lock_guard lock(mutex_);
    auto next = std::make_shared<Listeners>(*listeners_);
    next->taps.push_back(std::move(tap));
    listeners_ = std::move(next);
  }

  std::optional<nlohmann::json> LatestJson() const override {
    if constexpr (JsonMessage<T>) {
      const Message m = latest();
      if (m) return ToJson(*m);
    }
    return std::nullopt;
  }

 private:
  // A one-slot mailbox, where a new message replaces one that has not been delivered yet; or, for every message, a
  // queue handed over whole to each delivery.
  struct Subscriber : std::enable_shared_from_this<Subscriber> {
    Subscriber(Executor& e, Callback c, bool each) : executor(e), callback(std::move(c)), every(each) {}
    void Offer(const Message& message) {
      {
        std::lock_guard lock(mutex);
        if (every) {
          queue.push_back(message);
        } else {
          pending = message;
        }
        if (scheduled) return;
        scheduled = true;
      }
      executor.Post([self = this->shared_from_this()] { self->Deliver(); });
    }
    void Deliver() {
      Message m;
      std::vector<Message> due;
      {
        std::lock_guard lock(mutex);
        m = std::move(pending);
        due.swap(queue);
        scheduled = false;
      }
      if (m) callback(m);
      for (const Message& each : due) callback(each);
    }
    Executor& executor;
    Callback callback;
    const bool every;
    std::mutex mutex;
    Message pending;             // the newest
    std::vector<Message> queue;  // every one, oldest first
    bool scheduled = false;
  };

  // Replaced, never changed, when someone subscribes or taps: a publish takes it without copying (nor allocating)
  // before the first delivery.
  struct Listeners {
    std::vector<std::function<void(const T&)>> taps;
    std::vector<std::shared_ptr<Subscriber>> subscribers;
  };

  mutable std::mutex mutex_;
  Message latest_;
  std::shared_ptr<const Listeners> listeners_ = std::make_shared<const Listeners>();
};

class Bus {
 public:
  Bus() = default;
  Bus(const Bus&) = delete;
  Bus& operator=(const Bus&) = delete;

  // The topic with this name, created on first use. Asking for an existing name with another type, latched where it
  // is not, or with another delivery, is a bug.
  template <typename T>
  Topic<T>& Get(TopicName<T> name) {
    std::lock_guard lock(mutex_);
    auto& slot = topics_[std::string(name.name)];
    if (!slot) slot = std::make_unique<Topic<T>>(std::string(name.name), name.latched, name.delivery);
    DEMAND(slot->type() == typeid(T) && slot->latched() == name.latched && slot->delivery() == name.delivery);
    return static_cast<Topic<T>&>(*slot);
  }

  // A topic by name for generic consumers (the WebSocket stream); nullptr if no such topic exists.
  const TopicBase* Find(std::string_view name) const {
    std::lock_guard lock(mutex_);
    auto it = topics_.find(std::string(name));
    return it == topics_.end() ? nullptr : it->second.get();
  }

  std::vector<std::string> names() const {
    std::lock_guard lock(mutex_);
    std::vector<std::string> out;
    for (const auto& [name, topic] : topics_) out.push_back(name);
    return out;
  }

 private:
  mutable std::mutex mutex_;
  std::map<std::string, std::unique_ptr<TopicBase>, std::less<>> topics_;
};

}  // namespace corridor::server
