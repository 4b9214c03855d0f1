#include "server/nodes/face_node.h"

#include <utility>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

constexpr double kFaceRateHz = 5.0;
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

void SpokenPhrases::Add(std::uint64_t sequence, std::shared_ptr<const std::string> wav) {
  std::lock_guard lock(mutex_);
  phrases_.emplace_back(sequence, std::move(wav));
  while (phrases_.size() > kKept) phrases_.pop_front();
}

std::shared_ptr<const std::string> SpokenPhrases::Find(std::uint64_t sequence) const {
  std::lock_guard lock(mutex_);
  for (const auto& [s, wav] : phrases_) {
    if (s == sequence) return wav;
  }
  return nullptr;
}

FaceNode::FaceNode(Executor& executor, Bus& bus, const FaceOptions& options, const face::SocialOptions& social,
                   std::shared_ptr<const face::Speech> speech, std::shared_ptr<SpokenPhrases> spoken,
                   std::shared_ptr<EventLog> events)
    : PeriodicNode("face", executor, bus, kFaceRateHz),
      machine_(options.expression),
      social_(social),
      watch_(options.events),
      events_(std::move(events)),
      speech_(std::move(speech)),
      spoken_(std::move(spoken)) {}

void FaceNode::Activate() {
  Subscribe(topics::kBumped, "bump", [this](const auto&) { bumped_since_tick_ = true; });
  Subscribe(topics::kFaceCommand, "command", [this](const auto& command) { OnCommand(*command); });
  // New detections move the eyes at once, not at the next tick: a person appearing is looked at within a frame.
  Subscribe(topics::kDetections, "people", [this](const auto&) { Tick(); });
  PeriodicNode::Activate();
}

void FaceNode::OnCommand(const FaceCommand& command) {
  // Said first: synthesis can take a while on a busy board, and the expression's hold counts from when it can show.
  if (!command.say.empty()) Say(command.say, "request");
  // The API validated it: an expression's hold is finite and not negative.
  if (command.expression) machine_.Show(*command.expression, command.hold_s, clock().Now());
}

void FaceNode::Say(std::string text, std::string kind) {
  ++state_.said_sequence;
  state_.said = std::move(text);
  state_.said_kind = std::move(kind);
  // Synthesized before the state that announces it goes out, so the page finds the audio when it asks. A failure
  // leaves the phrase silent (the page's mouth still moves) and the node degraded, saying why.
  if (speech_ && spoken_) {
    try {
      spoken_->Add(state_.said_sequence, std::make_shared<const std::string>(speech_->SynthesizeWav(state_.said)));
    } catch (const std::exception& e) {
      SetHealth(Health::kDegraded, std::string("speech: ") + e.what());
    }
  }
}

face::Situation FaceNode::Sample() {
  face::Situation s{.now_ns = clock().Now()};
  nav::Twist2 velocity;
  if (const auto odometry = odometry_topic_.latest()) {
    velocity = odometry->velocity;
    s.moving =
        std::abs(odometry->velocity.linear_mps) > kMovingMps || std::abs(odometry->velocity.angular_rps) > kMovingRps;
    const bool pressed_between_ticks = std::exchange(bumped_since_tick_, false);
    s.bumped = odometry->bumper_pressed || pressed_between_ticks;
  }
  if (s.moving) {
    still_since_ns_ = -1;
  } else if (still_since_ns_ < 0) {
    still_since_ns_ = s.now_ns;
  }
  if (const auto command = cmd_vel_topic_.latest()) {
    s.driven = command->mode == nav::ControlMode::kTeleop;
    s.fault = command->mode == nav::ControlMode::kStopped;
    // What stopped it: the failing part or device, else the gate's reason (no odometry, a cliff).
    if (s.fault) s.fault_detail = command->detail.empty() ? StopReason(*command) : command->detail;
  }
  if (const auto battery = battery_topic_.latest()) {
    s.charging = battery->charging;
    s.battery_percent = battery->charge * 100.0;
  }
  if (const auto localization = localization_topic_.latest()) {
    s.lost = localization->estimate.health == nav::LocalizationHealth::kLost;
  }
  if (const auto mission = mission_topic_.latest()) {
    s.mission = Phase(mission->status);
    s.mission_id = mission->id;
    if (!mission->goals.empty()) s.place = mission->goals.back().place;
    s.mission_error = mission->error;
    const bool held_still = still_since_ns_ >= 0 && s.now_ns - still_since_ns_ >= drivers::FromSeconds(kWaitingAfterS);
    // At a door or a lift: what for (the runner's words for people).
    if (!mission->waiting_for_door.empty() || !mission->lift.empty()) s.waiting_for = mission->waiting;
    s.waiting = s.mission == face::MissionPhase::kPaused ||
                (s.mission == face::MissionPhase::kActive &&
                 (held_still || mission->policy == nav::PolicyMode::kWaitingForDepth));
  }
  // People: only a report from the last second counts.
  people_.clear();
  if (const auto detections = detections_topic_.latest();
      detections && s.now_ns - detections->stamp_ns <= drivers::FromSeconds(kDetectionsFreshS)) {
    people_ = detections->items;
  }
  const face::SocialCues cues = social_.Update(people_, velocity.linear_mps, velocity.angular_rps, s.now_ns);
  s.person_near = cues.near;
  s.person_blocking = cues.blocking;
  s.person_looking = cues.looking;
  state_.gaze_rad = cues.gaze_rad;
  state_.gaze_at_person = cues.gaze_at_person;
  return s;
}

void FaceNode::Tick() {
  const face::Situation situation = Sample();
  const face::FaceOutput out = machine_.Update(situation);
  for (const face::RobotEvent& event : watch_.Update(situation, people_)) {
    if (events_) events_->Append(event);
  }
  state_.expression = out.expression;
  if (out.say) Say(out.say->text, KindName(out.say->kind));
  face_expression_topic_.Publish(state_);
}

}  // namespace corridor::server
