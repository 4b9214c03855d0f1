// Feeds the face's expression machine (face/expression.h) from the bus and publishes the expression, and what the
// robot says, on face/expression, on the perception executor, five times a second: base motion and the bumper (a bump
// is seen however briefly the bumper was pressed, through safety/bumped, which the control node publishes for each
// odometry message with the bumper pressed: it stops pushing at once, so that may be one message between two ticks;
// the face does not take every odometry message itself), the control mode (teleop, a protective stop), localization's
// health, the mission (its phase, the place it goes to, whether it holds the robot still), the people detected
// (perception/detections, through face/social.h: near, in the way, looking at the robot; where the eyes look), and
// requests from apps (face/command: an expression for a while, a phrase to say). What it says is synthesized
// (espeak-ng, face/speech.h) into SpokenPhrases for the page to play. The same situation, sampled once, also gives the
// robot's events for building systems (face/events.h), appended to the EventLog.
#pragma once

#include <deque>
#include <memory>
#include <mutex>
#include <string>

#include "face/events.h"
#include "face/expression.h"
#include "face/social.h"
#include "face/speech.h"
#include "server/config/config.h"
#include "server/runtime/bus.h"
#include "server/runtime/event_log.h"
#include "server/runtime/node.h"
#include "server/runtime/topics.h"

namespace corridor::server {

// The phrases the robot said lately, as WAV audio by their sequence number (FaceState::said_sequence), for the face
// page to play: the newest 16 kept. Thread-safe: the face node adds, the API reads.
class SpokenPhrases {
 public:
  void Add(std::uint64_t sequence, std::shared_ptr<const std::string> wav);
  // The phrase's audio, or null when it was not said aloud (muted) or is too old.
  std::shared_ptr<const std::string> Find(std::uint64_t sequence) const;

 private:
  static constexpr std::size_t kKept = 16;
  mutable std::mutex mutex_;
  std::deque<std::pair<std::uint64_t, std::shared_ptr<const std::string>>> phrases_;
};

class FaceNode final : public PeriodicNode {
 public:
  // speech: the voice (null: muted); spoken: where the audio of what is said goes; events: where the events go (each
  // may be null).
  FaceNode(Executor& executor, Bus& bus, const FaceOptions& options = {}, const face::SocialOptions& social = {},
           std::shared_ptr<const face::Speech> speech = nullptr, std::shared_ptr<SpokenPhrases> spoken = nullptr,
           std::shared_ptr<EventLog> events = nullptr);
  void Activate() override;

 private:
  void Tick() override;
  void OnCommand(const FaceCommand& command);
  face::Situation Sample();
  void Say(std::string text, std::string kind);

  face::ExpressionMachine machine_;
  face::SocialSense social_;
  face::EventWatch watch_;
  std::shared_ptr<EventLog> events_;
  std::vector<face::Detection> people_;  // fresh at the last sample
  std::shared_ptr<const face::Speech> speech_;
  std::shared_ptr<SpokenPhrases> spoken_;
  FaceState state_;
  bool bumped_since_tick_ = false;       // on the node's executor
  drivers::TimeNs still_since_ns_ = -1;  // the base has not moved since; -1: it is moving

  // The topics it reads and writes, resolved once.
  Topic<drivers::BatteryState>& battery_topic_ = bus().Get(topics::kBattery);
  Topic<BaseCommand>& cmd_vel_topic_ = bus().Get(topics::kCmdVel);
  Topic<Detections>& detections_topic_ = bus().Get(topics::kDetections);
  Topic<FaceState>& face_expression_topic_ = bus().Get(topics::kFaceExpression);
  Topic<LocalizationState>& localization_topic_ = bus().Get(topics::kLocalization);
  Topic<MissionState>& mission_topic_ = bus().Get(topics::kMission);
  Topic<drivers::WheelOdometry>& odometry_topic_ = bus().Get(topics::kOdometry);
};

}  // namespace corridor::server
