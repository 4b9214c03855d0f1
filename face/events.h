// What building systems are told about (webhooks, the stream's "events" topic): the moments the robot's situation
// changes in a way someone outside may act on. A pure edge detector over the same Situation the face reads
// (expression.h), sampled by server/nodes/face_node a few times a second, and the people detected then.
//
//   person_detected   a person's track appears (face/detect's Tracker gives it an id)
//   person_left       a person's track has not been seen for person_left_after_s
//   mission_succeeded a mission reaches its last goal (seen turning from active or paused; one that ended before the
//   mission_failed    first sample is not news), or fails (no way, a fault)
//   blocked           an active mission's way has been blocked (a person in it, or the mission holding the robot
//                     still) for blocked_after_s; once per blocking
//   lost              localization stops knowing where the robot is
//   fault             the robot stopped because something is wrong (a protective stop; a device that stopped
//                     answering is one)
//   bump              the bumper is pressed
//   waiting           a mission holds for a door to open or a lift (each thing it waits for in turn: the lift to come,
//                     its car to be empty, the ride)
//   battery_low       the battery's charge fell below battery_low_percent while not charging; again only after it
//                     charged, or rose 5 points above it
// Each fires on the change, not while the condition lasts (a robot already lost or stopped at its first sample is
// news: someone should know).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "drivers/clock.h"
#include "face/detect/detection.h"
#include "face/expression.h"

namespace corridor::face {

enum class EventType {
  kPersonDetected,
  kPersonLeft,
  kMissionSucceeded,
  kMissionFailed,
  kBlocked,
  kLost,
  kFault,
  kBump,
  kWaiting,
  kBatteryLow
};
inline constexpr int kEventTypeCount = 10;
std::string_view ToString(EventType type);
// The event type named `name` (as ToString writes it); nullopt for any other name.
std::optional<EventType> EventTypeFromString(std::string_view name);

struct RobotEvent {
  EventType type = EventType::kBump;
  drivers::TimeNs stamp_ns = 0;
  std::string mission_id{};           // mission_*, blocked, waiting
  std::string place{};                // mission_*: the named place of the last goal, if any
  std::string detail{};               // mission_failed: why; fault: what failed; blocked: "person" or "waiting";
                                      // waiting: what for; battery_low: the charge ("18 %")
  std::optional<Detection> person{};  // person_detected: the detection; person_left: the last one seen
};

struct EventOptions {
  double person_left_after_s = 2.0;   // a track unseen this long has left (the tracker forgets after 1.5 s)
  double blocked_after_s = 3.0;       // blocked this long before it is news
  double battery_low_percent = 20.0;  // a charge below this is news (0: never)
};

class EventWatch {
 public:
  // Throws std::invalid_argument for a negative time in the options.
  explicit EventWatch(const EventOptions& options = {});

  // The events since the last update: `situation` (with mission_error and fault_detail filled where known) and the
  // detections fresh now. Call with non-decreasing times.
  std::vector<RobotEvent> Update(const Situation& situation, const std::vector<Detection>& detections);

 private:
  struct Seen {
    Detection last;
    drivers::TimeNs last_seen_ns = 0;
  };

  EventOptions options_;
  bool started_ = false;  // the first update takes the mission as it is: one that ended before is not news
  bool lost_ = false;
  bool fault_ = false;
  bool bumped_ = false;
  std::string waiting_for_;   // as last sampled
  bool battery_low_ = false;  // told, and not yet charged or risen again
  std::string mission_id_;
  MissionPhase mission_ = MissionPhase::kNone;
  drivers::TimeNs blocked_since_ns_ = -1;
  bool blocked_told_ = false;
  std::map<int, Seen> people_;  // by track id
};

}  // namespace corridor::face
