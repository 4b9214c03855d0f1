#include "face/expression.h"

#include <array>
#include <cmath>
#include <stdexcept>

#include "nav/demand.h"

namespace corridor::face {
namespace {

constexpr std::array<std::string_view, kExpressionCount> kExpressionNames = {
    "neutral", "happy", "focused", "surprised", "worried", "sleepy", "confused", "sad"};

// The rules' urgencies (expression.h), from the bottom of the list.
enum Urgency : int {
  kIdle = 0,
  kSleepyUrgency = 1,
  kBusy = 2,
  kGlad = 3,
  kWorry = 4,
  kRequested = 5,
  kConfusion = 6,
  kSurprise = 7,
  kFault = 8,
};

std::string ArrivedText(const ExpressionOptions& o, const std::string& place) {
  if (place.empty()) return o.arrived_text;
  std::string text = o.arrived_at_text;
  const std::size_t at = text.find("{place}");
  if (at != std::string::npos) text.replace(at, 7, place);
  return text;
}

}  // namespace

std::string_view ToString(Expression expression) {
  const auto i = static_cast<std::size_t>(expression);
  DEMAND(i < kExpressionNames.size());
  return kExpressionNames[i];
}

std::optional<Expression> ExpressionFromString(std::string_view name) {
  for (std::size_t i = 0; i < kExpressionNames.size(); ++i) {
    if (kExpressionNames[i] == name) return static_cast<Expression>(i);
  }
  return std::nullopt;
}

ExpressionMachine::ExpressionMachine(const ExpressionOptions& options) : options_(options) {
  for (const double t :
       {options.min_hold_s, options.surprise_hold_s, options.arrived_hold_s, options.confused_hold_s,
        options.greeting_hold_s, options.greeting_every_s, options.excuse_me_after_s, options.sleepy_after_s}) {
    if (!(t >= 0.0) || !std::isfinite(t)) throw std::invalid_argument("face: hold times must be finite and >= 0");
  }
}

void ExpressionMachine::Show(Expression expression, double hold_s, drivers::TimeNs now_ns) {
  if (!(hold_s >= 0.0) || !std::isfinite(hold_s)) throw std::invalid_argument("face: hold_s must be finite and >= 0");
  requested_ = expression;
  requested_until_ns_ = now_ns + drivers::FromSeconds(hold_s);
}

ExpressionMachine::Wish ExpressionMachine::Wanted(const Situation& s) const {
  const bool on_mission = s.mission == MissionPhase::kActive || s.mission == MissionPhase::kPaused;
  if (s.fault) return {Expression::kSad, kFault};
  if (s.now_ns < surprised_until_ns_) return {Expression::kSurprised, kSurprise};
  if (s.lost || s.now_ns < confused_until_ns_) return {Expression::kConfused, kConfusion};
  if (requested_ && s.now_ns < requested_until_ns_) return {*requested_, kRequested};
  if (s.person_blocking && on_mission) return {Expression::kWorried, kWorry};
  if (s.waiting && on_mission) return {Expression::kWorried, kWorry};
  if (s.now_ns < happy_until_ns_) return {Expression::kHappy, kGlad};
  if (on_mission || s.moving || s.driven) return {Expression::kFocused, kBusy};
  if (s.charging || s.now_ns - last_active_ns_ > drivers::FromSeconds(options_.sleepy_after_s)) {
    return {Expression::kSleepy, kSleepyUrgency};
  }
  return {Expression::kNeutral, kIdle};
}

FaceOutput ExpressionMachine::Update(const Situation& s) {
  FaceOutput out;
  const bool on_mission = s.mission == MissionPhase::kActive || s.mission == MissionPhase::kPaused;
  const bool first = last_active_ns_ < 0;
  if (first) last_active_ns_ = s.now_ns;
  if (s.bumped) surprised_until_ns_ = s.now_ns + drivers::FromSeconds(options_.surprise_hold_s);
  if (s.moving || s.driven || s.bumped || s.fault || s.lost || on_mission || s.person_near || s.person_looking) {
    last_active_ns_ = s.now_ns;
  }

  // The mission's turns: a mission that has just ended (a new id, or the same one in a new phase). What the first
  // update finds (a mission that ended before the daemon started) is not news.
  const bool changed = !first && (s.mission_id != mission_id_ || s.mission != mission_);
  if (changed && s.mission == MissionPhase::kSucceeded) {
    happy_until_ns_ = s.now_ns + drivers::FromSeconds(options_.arrived_hold_s);
    out.say = Phrase{PhraseKind::kArrived, ArrivedText(options_, s.place)};
  } else if (changed && s.mission == MissionPhase::kFailed) {
    confused_until_ns_ = s.now_ns + drivers::FromSeconds(options_.confused_hold_s);
  }
  mission_id_ = s.mission_id;
  mission_ = s.mission;

  // Blocked by a person on a mission: "excuse me" once, after a while.
  if (s.person_blocking && on_mission) {
    if (blocked_since_ns_ < 0) blocked_since_ns_ = s.now_ns;
    if (!excused_ && !out.say && s.now_ns - blocked_since_ns_ >= drivers::FromSeconds(options_.excuse_me_after_s)) {
      out.say = Phrase{PhraseKind::kExcuseMe, options_.excuse_me_text};
      excused_ = true;
    }
  } else {
    blocked_since_ns_ = -1;
    excused_ = false;
  }

  // Someone looking at an idle robot: a smile and a greeting, now and then.
  const bool idle = !on_mission && !s.moving && !s.driven && !s.fault && !s.lost;
  const bool greeting_due =
      last_greeting_ns_ < 0 || s.now_ns - last_greeting_ns_ >= drivers::FromSeconds(options_.greeting_every_s);
  if (s.person_looking && idle && greeting_due && !out.say) {
    out.say = Phrase{PhraseKind::kGreeting, options_.greeting_text};
    last_greeting_ns_ = s.now_ns;
    happy_until_ns_ = std::max(happy_until_ns_, s.now_ns + drivers::FromSeconds(options_.greeting_hold_s));
  }

  const Wish wish = Wanted(s);
  const bool held = shown_since_ns_ >= 0 && s.now_ns - shown_since_ns_ < drivers::FromSeconds(options_.min_hold_s);
  // Alarms (worried and above) show at once over anything less urgent; everything else waits its turn.
  const bool alarm = wish.urgency >= kWorry && wish.urgency > current_urgency_;
  if (wish.expression != current_ && (alarm || !held)) {
    current_ = wish.expression;
    shown_since_ns_ = s.now_ns;
  }
  if (wish.expression == current_) current_urgency_ = wish.urgency;
  if (shown_since_ns_ < 0) shown_since_ns_ = s.now_ns;
  out.expression = current_;
  return out;
}

}  // namespace corridor::face
