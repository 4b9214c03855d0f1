// The robot's recent events (face/events.h), numbered as they happen: the face node appends what its EventWatch finds,
// the event node reads them (into the database and to the webhooks). Thread-safe. The newest kKept are kept; a reader
// that remembers the last number it read never misses one unless it falls that far behind.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "face/events.h"

namespace corridor::server {

// `time` as ISO 8601 in UTC with milliseconds: 2026-11-25T20:14:03.250Z.
std::string IsoUtc(std::chrono::system_clock::time_point time);

struct LoggedEvent {
  std::uint64_t sequence = 0;  // from 1
  std::string time;            // wall clock, ISO 8601 UTC
  face::RobotEvent event;
};

// {"time", "type", "data"}: data holds what the event says beyond its type (mission_id, place, detail, person), each
// only when known. The log's own sequence is left out: it restarts with the daemon (the database numbers events).
nlohmann::json ToJson(const LoggedEvent& event);

class EventLog {
 public:
  static constexpr std::size_t kKept = 256;

  void Append(const face::RobotEvent& event);
  // The events numbered above `after`, oldest first.
  std::vector<LoggedEvent> After(std::uint64_t after) const;

 private:
  mutable std::mutex mutex_;
  std::deque<LoggedEvent> events_;
  std::uint64_t last_ = 0;
};

}  // namespace corridor::server
