#include "face/events.h"

#include <array>
#include <cmath>
#include <stdexcept>

namespace corridor::face {
namespace {

constexpr std::array<std::string_view, kEventTypeCount> kEventNames = {
    "person_detected", "person_left", "mission_succeeded", "mission_failed", "blocked", "lost",
    "fault",           "bump",        "waiting",           "battery_low"};
// A low battery is news again once the charge has risen this far above the threshold (or it charges).
constexpr double kBatteryRearmPercent = 5.0;

bool Ended(MissionPhase phase) {
  return phase == MissionPhase::kSucceeded || phase == MissionPhase::kFailed || phase == MissionPhase::kCanceled;
}

}  // namespace

std::string_view ToString(EventType type) {
  const auto i = static_cast<std::size_t>(type);
  return i < kEventNames.size() ? kEventNames[i] : "bump";
}

std::optional<EventType> EventTypeFromString(std::string_view name) {
  for (std::size_t i = 0; i < kEventNames.size(); ++i) {
    if (kEventNames[i] == name) return static_cast<EventType>(i);
  }
  return std::nullopt;
}

EventWatch::EventWatch(const EventOptions& options) : options_(options) {
  for (const double t : {options.person_left_after_s, options.blocked_after_s}) {
    if (!(t >= 0.0) || !std::isfinite(t)) throw std::invalid_argument("events: times must be finite and >= 0");
  }
  if (!(options.battery_low_percent >= 0.0 && options.battery_low_percent <= 100.0)) {
    throw std::invalid_argument("events: battery_low_percent must be within 0 to 100");
  }
}

std::vector<RobotEvent> EventWatch::Update(const Situation& s, const std::vector<Detection>& detections) {
  std::vector<RobotEvent> out;
  const auto emit = [&](EventType type) -> RobotEvent& { return out.emplace_back(RobotEvent{type, s.now_ns}); };

  // People: a new track id is a person detected; one unseen for a while has left.
  for (const Detection& d : detections) {
    if (d.label != "person" || d.track_id == 0) continue;
    auto [it, inserted] = people_.try_emplace(d.track_id);
    it->second.last = d;
    it->second.last_seen_ns = s.now_ns;
    if (inserted) emit(EventType::kPersonDetected).person = d;
  }
  for (auto it = people_.begin(); it != people_.end();) {
    if (s.now_ns - it->second.last_seen_ns >= drivers::FromSeconds(options_.person_left_after_s)) {
      emit(EventType::kPersonLeft).person = it->second.last;
      it = people_.erase(it);
    } else {
      ++it;
    }
  }

  // The mission's end, seen as it happens.
  const bool same_mission = s.mission_id == mission_id_;
  const bool was_running = same_mission && (mission_ == MissionPhase::kActive || mission_ == MissionPhase::kPaused);
  const bool new_and_ended = !same_mission && started_;  // it started and ended between two samples
  if (Ended(s.mission) && s.mission != MissionPhase::kCanceled && (was_running || new_and_ended)) {
    RobotEvent& e =
        emit(s.mission == MissionPhase::kSucceeded ? EventType::kMissionSucceeded : EventType::kMissionFailed);
    e.mission_id = s.mission_id;
    e.place = s.place;
    if (s.mission == MissionPhase::kFailed) e.detail = s.mission_error;
  }
  mission_id_ = s.mission_id;
  mission_ = s.mission;
  started_ = true;

  // Blocked: a mission that has not moved on for a while, once per blocking.
  const bool blocking = s.mission == MissionPhase::kActive && (s.person_blocking || s.waiting);
  if (!blocking) {
    blocked_since_ns_ = -1;
    blocked_told_ = false;
  } else {
    if (blocked_since_ns_ < 0) blocked_since_ns_ = s.now_ns;
    if (!blocked_told_ && s.now_ns - blocked_since_ns_ >= drivers::FromSeconds(options_.blocked_after_s)) {
      RobotEvent& e = emit(EventType::kBlocked);
      e.mission_id = s.mission_id;
      e.place = s.place;
      e.detail = s.person_blocking ? "person" : "waiting";
      blocked_told_ = true;
    }
  }

  // Each thing a mission waits for at a door or a lift, as it starts waiting for it.
  if (!s.waiting_for.empty() && s.waiting_for != waiting_for_) {
    RobotEvent& e = emit(EventType::kWaiting);
    e.mission_id = s.mission_id;
    e.place = s.place;
    e.detail = s.waiting_for;
  }
  waiting_for_ = s.waiting_for;

  // The battery running low, once until it charges or rises again.
  if (s.battery_percent) {
    const double low = options_.battery_low_percent;
    if (s.charging || *s.battery_percent >= low + kBatteryRearmPercent) battery_low_ = false;
    if (!battery_low_ && !s.charging && *s.battery_percent < low) {
      emit(EventType::kBatteryLow).detail = std::to_string(static_cast<int>(std::lround(*s.battery_percent))) + " %";
      battery_low_ = true;
    }
  }

  // Rising edges.
  if (s.lost && !lost_) emit(EventType::kLost);
  if (s.fault && !fault_) emit(EventType::kFault).detail = s.fault_detail;
  if (s.bumped && !bumped_) emit(EventType::kBump);
  lost_ = s.lost;
  fault_ = s.fault;
  bumped_ = s.bumped;
  return out;
}

}  // namespace corridor::face
