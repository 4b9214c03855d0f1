// ASNS's fuzzy motion controller (FLMC; seed paper 003, Section 4.8, Tables 5-6): three Mamdani controllers, each a
// fuzzylite engine (Debian's libfuzzylite, LGPL-3+, linked dynamically) whose variables, membership functions and
// rules are FLL text, so that a user can change them without a build (docs/asns.md says what corridor chose where the
// paper is silent):
//   - motion: the next waypoint's bearing error and distance, 7 membership functions each, to a forward speed and a
//     turn rate (shares of the maximum);
//   - obstacle avoidance: the free distance in the left, front and right cones to a forward speed and a turn rate;
//   - rotation: near a waypoint facing away from it, the bearing error to a turn rate on the spot.
// Which one drives: none within stop_within_m of the waypoint; rotation when the waypoint is within rotate_within_m
// and its bearing off by more than rotate_above_rad; else avoidance when something is nearer than avoid_within_m in a
// cone; else motion.
#pragma once

#include <memory>
#include <string>

#include "nav/geometry/pose2.h"

namespace corridor::nav {

struct FlmcOptions {
  double max_linear_mps = 0.26;
  double max_angular_rps = 1.0;
  double stop_within_m = 0.03;    // at the waypoint: no command (its bearing means nothing this near)
  double rotate_within_m = 0.4;   // near a waypoint ...
  double rotate_above_rad = 0.6;  // ... and facing this far away from it: turn on the spot
  double avoid_within_m = 0.8;    // something nearer in a cone: the avoidance controller drives
  // The controllers' FLL text (fuzzylite's format); empty: corridor's own (DefaultFlmcRules).
  std::string motion_fll;
  std::string avoidance_fll;
  std::string rotation_fll;
};

// corridor's rule bases, as FLL: "motion", "avoidance", "rotation".
std::string DefaultFlmcRules(const std::string& controller);

struct FlmcInput {
  double bearing_rad = 0.0;  // the waypoint's bearing from the robot's heading, positive to the left, in [-pi, pi]
  double distance_m = 0.0;   // to the waypoint
  // Free distance in the cones ahead (left 15-60 degrees, front +-15 degrees, right), +infinity for nothing seen.
  double left_m = 0.0;
  double front_m = 0.0;
  double right_m = 0.0;
};

enum class FlmcMode { kMotion, kAvoidance, kRotation };
const char* ToString(FlmcMode mode);

struct FlmcOutput {
  Twist2 twist;
  FlmcMode mode = FlmcMode::kMotion;
};

class Flmc {
 public:
  // Builds the three engines. Throws std::invalid_argument naming the controller when its FLL does not parse, lacks
  // its variables (motion: inputs bearing and distance; avoidance: left, front, right; rotation: bearing; outputs
  // linear and angular, rotation's angular alone) or is not ready to run.
  explicit Flmc(const FlmcOptions& options);
  ~Flmc();
  Flmc(const Flmc&) = delete;
  Flmc& operator=(const Flmc&) = delete;

  // One command. Not for concurrent use (the engines keep their variables' values).
  FlmcOutput Step(const FlmcInput& input);

 private:
  struct Engines;
  FlmcOptions options_;
  std::unique_ptr<Engines> engines_;
};

}  // namespace corridor::nav
