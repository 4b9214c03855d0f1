// The robot's face: which expression the front screen shows, and what the robot says, for what it is going through.
// A pure state machine: situations in (sampled by the caller a few times a second), expression and phrases out, with
// hold times so that the face never flickers. The kiosk page at /face draws the expression; server/nodes/face_node
// samples the bus into Situations; the voice (face/voice.h) speaks the phrases.
//
// The rules, most urgent first (from worried up, a more urgent expression shows at once; any other change waits until
// the shown expression has been up for min_hold_s):
//   sad        a fault or a protective stop
//   surprised  a bump, for surprise_hold_s
//   confused   lost (localization), or a mission that failed (no path), for confused_hold_s after the failure
//   (shown)    an expression an app asked for (Show), for its hold
//   worried    a person blocking the way, or a mission holding the robot still (paused, waiting for the way)
//   happy      arrived, for arrived_hold_s; a person looking at the robot while it is idle (and a greeting)
//   focused    on a mission or moving
//   sleepy     charging, or idle for sleepy_after_s
//   neutral
// Phrases: a greeting when a person looks at an idle robot (at most every greeting_every_s); "excuse me" once a
// person has blocked a mission's way for excuse_me_after_s (once per blocking); the arrival, at a named place or not.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "drivers/clock.h"

namespace corridor::face {

enum class Expression { kNeutral, kHappy, kFocused, kSurprised, kWorried, kSleepy, kConfused, kSad };
inline constexpr int kExpressionCount = 8;
std::string_view ToString(Expression expression);
// The expression named `name` (as ToString writes it); nullopt for any other name.
std::optional<Expression> ExpressionFromString(std::string_view name);

// Where the robot's mission is, as the face needs it.
enum class MissionPhase { kNone, kActive, kPaused, kSucceeded, kFailed, kCanceled };

// What the robot is going through, sampled by the caller.
struct Situation {
  drivers::TimeNs now_ns = 0;
  bool moving = false;  // the base is moving
  bool driven = false;  // a person is driving it (teleop)
  bool bumped = false;  // the bumper is pressed
  bool fault = false;   // the robot stopped because something is wrong (a device not answering, a node
                        // failing, a protective stop)
  bool lost = false;    // localization does not know where the robot is
  MissionPhase mission = MissionPhase::kNone;
  std::string mission_id{};                 // of the mission in `mission` (a new id is a new mission)
  std::string place{};                      // the named place the mission's last goal is, if any
  std::string mission_error{};              // why a failed mission failed
  std::string fault_detail{};               // what failed, with `fault`
  bool waiting = false;                     // an active or paused mission holds the robot still
  bool person_blocking = false;             // a person stands in the robot's way (in front, close)
  bool person_near = false;                 // a person is close in front
  bool person_looking = false;              // a person's face is turned to the robot, close
  bool charging = false;                    // the battery is charging (the robot stands on its dock)
  std::optional<double> battery_percent{};  // its charge, 0 to 100, when the base reports one
  std::string waiting_for{};  // what a mission holds for at a door or a lift ("door d1 to open"), "" when nothing
};

enum class PhraseKind { kGreeting, kExcuseMe, kArrived };
struct Phrase {
  PhraseKind kind = PhraseKind::kGreeting;
  std::string text;
};

struct FaceOutput {
  Expression expression = Expression::kNeutral;
  std::optional<Phrase> say;  // something to say now, at most one per update
};

struct ExpressionOptions {
  double min_hold_s = 1.0;         // an expression stays up at least this long unless a more urgent one comes
  double surprise_hold_s = 2.0;    // a bump keeps the surprised face this long
  double arrived_hold_s = 3.0;     // happy on arrival
  double confused_hold_s = 5.0;    // after a mission failed
  double greeting_hold_s = 3.0;    // happy after a greeting
  double greeting_every_s = 30.0;  // at most one greeting this often
  double excuse_me_after_s = 3.0;  // a person blocking the way this long: "excuse me"
  double sleepy_after_s = 60.0;    // idle this long: sleepy
  std::string greeting_text = "Hello!";
  std::string excuse_me_text = "Excuse me, may I pass?";
  std::string arrived_text = "I have arrived.";
  std::string arrived_at_text = "I have arrived at the {place}.";  // {place}: the place's name
};

class ExpressionMachine {
 public:
  // Throws std::invalid_argument for a negative time in the options.
  explicit ExpressionMachine(const ExpressionOptions& options = {});

  // The expression for this situation, and a phrase to say if one is due; call with non-decreasing times.
  FaceOutput Update(const Situation& situation);
  // Shows `expression` from now_ns for hold_s (an app's or building system's request), where nothing more urgent is
  // shown (see the rules above). Throws std::invalid_argument for a hold that is negative or not finite.
  void Show(Expression expression, double hold_s, drivers::TimeNs now_ns);
  Expression current() const { return current_; }

 private:
  struct Wish {
    Expression expression = Expression::kNeutral;
    int urgency = 0;  // the rule's place in the list above, counted from the bottom
  };
  // The expression the rules ask for now.
  Wish Wanted(const Situation& s) const;

  ExpressionOptions options_;
  Expression current_ = Expression::kNeutral;
  int current_urgency_ = 0;
  drivers::TimeNs shown_since_ns_ = -1;
  drivers::TimeNs surprised_until_ns_ = -1;
  drivers::TimeNs confused_until_ns_ = -1;
  drivers::TimeNs happy_until_ns_ = -1;
  drivers::TimeNs last_active_ns_ = -1;  // -1 until the first Update: the machine wakes up awake
  drivers::TimeNs last_greeting_ns_ = -1;
  drivers::TimeNs blocked_since_ns_ = -1;  // a person has blocked the way since; -1: not blocked
  bool excused_ = false;                   // "excuse me" said for this blocking
  std::optional<Expression> requested_;
  drivers::TimeNs requested_until_ns_ = -1;
  std::string mission_id_;
  MissionPhase mission_ = MissionPhase::kNone;
};

}  // namespace corridor::face
