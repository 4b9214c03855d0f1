#include "server/nodes/face_node.h"

#include <utility>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

constexpr double kRateHz = 5.0;
constexpr double kMovingMps = 0.02;
constexpr double kMovingRps = 0.05;
constexpr double kWaitingAfterS = 2.0;  // a mission holding the robot still this long is waiting
constexpr double kDetectionsFreshS = 1.0;

face::MissionPhase Phase(nav::MissionStatus status) {
  switch (status) {
    case nav::MissionStatus::kActive: return face::MissionPhase::kActive;
    case nav::MissionStatus::kPaused: return face::MissionPhase::kPaused;
    case nav::MissionStatus::kSucceeded: return face::MissionPhase::kSucceeded;
    case nav::MissionStatus::kFailed: return face::MissionPhase::kFailed;
    case nav::MissionStatus::kCanceled: return face::MissionPhase::kCanceled;
  }
  return face::MissionPhase::kNone;
}

const char* KindName(face::PhraseKind kind) {
  switch (kind) {
    case face::PhraseKind::kGreeting: return "greeting";
    case face::PhraseKind::kExcuseMe: return "excuse_me";
    case face::PhraseKind::kArrived: return "arrived";
  }
  return "request";
}

}  // namespace

FaceNode::FaceNode(Executor& executor, Bus& bus, const face::ExpressionOptions& options,
                   const face::SocialOptions& social)
    : PeriodicNode("face", executor, bus, kRateHz), machine_(options), social_(social) {}

void FaceNode::Activate() {
  Subscribe(topics::kOdometry, "odometry", [this](const auto& odometry) {
    if (odometry->bumper_pressed) bumped_since_tick_ = true;
  });
  Subscribe(topics::kFaceCommand, "command", [this](const auto& command) { OnCommand(*command); });
  // New detections move the eyes at once, not at the next tick: a person appearing is looked at within a frame.
  Subscribe(topics::kDetections, "people", [this](const auto&) { Tick(); });
  PeriodicNode::Activate();
}

void FaceNode::OnCommand(const FaceCommand& command) {
  // The API validated it: an expression's hold is finite and not negative.
  if (command.expression) machine_.Show(*command.expression, command.hold_s, clock().Now());
  if (!command.say.empty()) Say(command.say, "request");
}

void FaceNode::Say(std::string text, std::string kind) {
  ++state_.said_sequence;
  state_.said = std::move(text);
  state_.said_kind = std::move(kind);
}

face::Situation FaceNode::Sample() {
  face::Situation s{.now_ns = clock().Now()};
  nav::Twist2 velocity;
  if (const auto odometry = bus().Get(topics::kOdometry).latest()) {
    velocity = odometry->velocity;
    s.moving = std::abs(odometry->velocity.linear_mps) > kMovingMps ||
               std::abs(odometry->velocity.angular_rps) > kMovingRps;
    const bool pressed_between_ticks = std::exchange(bumped_since_tick_, false);
    s.bumped = odometry->bumper_pressed || pressed_between_ticks;
  }
  if (s.moving) {
    still_since_ns_ = -1;
  } else if (still_since_ns_ < 0) {
    still_since_ns_ = s.now_ns;
  }
  if (const auto command = bus().Get(topics::kCmdVel).latest()) {
    s.driven = command->mode == nav::ControlMode::kTeleop;
    s.fault = command->mode == nav::ControlMode::kStopped;
  }
  if (const auto localization = bus().Get(topics::kLocalization).latest()) {
    s.lost = localization->estimate.health == nav::LocalizationHealth::kLost;
  }
  if (const auto mission = bus().Get(topics::kMission).latest()) {
    s.mission = Phase(mission->status);
    s.mission_id = mission->id;
    if (!mission->goals.empty()) s.place = mission->goals.back().place;
    const bool held_still =
        still_since_ns_ >= 0 && s.now_ns - still_since_ns_ >= drivers::FromSeconds(kWaitingAfterS);
    s.waiting = s.mission == face::MissionPhase::kPaused ||
                (s.mission == face::MissionPhase::kActive &&
                 (held_still || mission->policy == nav::PolicyMode::kWaitingForDepth));
  }
  // People: only a report from the last second counts.
  std::vector<face::Detection> people;
  if (const auto detections = bus().Get(topics::kDetections).latest();
      detections && s.now_ns - detections->stamp_ns <= drivers::FromSeconds(kDetectionsFreshS)) {
    people = detections->items;
  }
  const face::SocialCues cues = social_.Update(people, velocity.linear_mps, velocity.angular_rps, s.now_ns);
  s.person_near = cues.near;
  s.person_blocking = cues.blocking;
  s.person_looking = cues.looking;
  state_.gaze_rad = cues.gaze_rad;
  state_.gaze_at_person = cues.gaze_at_person;
  return s;
}

void FaceNode::Tick() {
  const face::FaceOutput out = machine_.Update(Sample());
  state_.expression = out.expression;
  if (out.say) Say(out.say->text, KindName(out.say->kind));
  bus().Get(topics::kFaceExpression).Publish(state_);
}

}  // namespace corridor::server
