#include "server/runtime/event_log.h"

#include <ctime>

#include "server/runtime/messages.h"

namespace corridor::server {

std::string IsoUtc(std::chrono::system_clock::time_point time) {
  using namespace std::chrono;
  const auto ms = duration_cast<milliseconds>(time.time_since_epoch()).count();
  const std::time_t seconds = static_cast<std::time_t>(ms / 1000);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char text[40];
  const std::size_t n = std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%S", &utc);
  std::snprintf(text + n, sizeof(text) - n, ".%03dZ", static_cast<int>(ms % 1000));
  return text;
}

nlohmann::json ToJson(const LoggedEvent& logged) {
  const face::RobotEvent& e = logged.event;
  nlohmann::json data = nlohmann::json::object();
  if (!e.mission_id.empty()) data["mission_id"] = e.mission_id;
  if (!e.place.empty()) data["place"] = e.place;
  if (!e.detail.empty()) data["detail"] = e.detail;
  if (e.person) data["person"] = ToJson(*e.person);
  return {{"time", logged.time}, {"type", std::string(face::ToString(e.type))}, {"data", std::move(data)}};
}

void EventLog::Append(const face::RobotEvent& event) {
  const std::string time = IsoUtc(std::chrono::system_clock::now());
  std::lock_guard lock(mutex_);
  events_.push_back({++last_, time, event});
  while (events_.size() > kKept) events_.pop_front();
}

std::vector<LoggedEvent> EventLog::After(std::uint64_t after) const {
  std::lock_guard lock(mutex_);
  std::vector<LoggedEvent> out;
  for (const LoggedEvent& e : events_) {
    if (e.sequence > after) out.push_back(e);
  }
  return out;
}

}  // namespace corridor::server
