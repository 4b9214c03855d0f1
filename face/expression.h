// The robot's face: which expression the front screen shows for the robot's situation. A pure state machine:
// situations in, expression out, with hold times so that the face does not flicker. Renderers (the kiosk page at
// /face, a framebuffer) and the people detector that will feed `person_near` come in the face issue.
#pragma once

#include <string_view>

#include "drivers/clock.h"

namespace corridor::face {

enum class Expression { kNeutral, kHappy, kFocused, kSurprised, kWorried, kSleepy };
std::string_view ToString(Expression expression);

// What the robot is going through, sampled by the caller.
struct Situation {
  drivers::TimeNs now_ns = 0;
  bool moving = false;          // the base is moving
  bool driven = false;          // a person is driving it (teleop)
  bool bumped = false;          // the bumper is pressed
  bool fault = false;           // the robot stopped because something is wrong (a device not answering, ...)
  bool person_near = false;     // a person is close in front (from the detector, later)
  bool lost = false;            // localization does not know where the robot is
};

struct ExpressionOptions {
  double surprise_hold_s = 2.0;   // a bump keeps the surprised face this long
  double sleepy_after_s = 60.0;   // idle this long: sleepy
};

class ExpressionMachine {
 public:
  explicit ExpressionMachine(const ExpressionOptions& options = {}) : options_(options) {}
  // The expression for this situation; call with non-decreasing times.
  Expression Update(const Situation& situation);
  Expression current() const { return current_; }

 private:
  ExpressionOptions options_;
  Expression current_ = Expression::kNeutral;
  drivers::TimeNs surprised_until_ns_ = -1;
  drivers::TimeNs last_active_ns_ = -1;  // -1 until the first Update: the machine wakes up awake
};

}  // namespace corridor::face
