#include "face/expression.h"

namespace corridor::face {

std::string_view ToString(Expression expression) {
  switch (expression) {
    case Expression::kNeutral: return "neutral";
    case Expression::kHappy: return "happy";
    case Expression::kFocused: return "focused";
    case Expression::kSurprised: return "surprised";
    case Expression::kWorried: return "worried";
    case Expression::kSleepy: return "sleepy";
  }
  return "neutral";
}

Expression ExpressionMachine::Update(const Situation& s) {
  if (last_active_ns_ < 0) last_active_ns_ = s.now_ns;
  if (s.bumped) surprised_until_ns_ = s.now_ns + drivers::FromSeconds(options_.surprise_hold_s);
  if (s.moving || s.driven || s.bumped || s.person_near || s.fault || s.lost) last_active_ns_ = s.now_ns;
  // In order of urgency: a fault or being lost outranks a bump, which outranks everything that is going well.
  if (s.fault || s.lost) {
    current_ = Expression::kWorried;
  } else if (s.now_ns < surprised_until_ns_) {
    current_ = Expression::kSurprised;
  } else if (s.person_near) {
    current_ = Expression::kHappy;
  } else if (s.moving) {
    current_ = Expression::kFocused;
  } else if (s.now_ns - last_active_ns_ > drivers::FromSeconds(options_.sleepy_after_s)) {
    current_ = Expression::kSleepy;
  } else {
    current_ = Expression::kNeutral;
  }
  return current_;
}

}  // namespace corridor::face
