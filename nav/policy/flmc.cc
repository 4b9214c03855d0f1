#include "nav/policy/flmc.h"

#include <fl/Headers.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace corridor::nav {
namespace {

// Outputs are shares of the robot's top speeds. Their ranges reach past [0, 1] and [-1, 1] so that a term at an end
// (stop, full speed) is a whole triangle whose centroid is its peak: a stop defuzzifies to 0 exactly, not to the
// centroid of half a triangle. The result is clamped after.
constexpr const char* kLinear = R"(
OutputVariable: linear
  enabled: true
  range: -0.250 1.250
  lock-range: false
  aggregation: Maximum
  defuzzifier: Centroid 200
  default: 0.000
  lock-previous: false
  term: ST Triangle -0.250 0.000 0.250
  term: VS Triangle 0.000 0.150 0.300
  term: SL Triangle 0.150 0.300 0.500
  term: ME Triangle 0.300 0.500 0.750
  term: FA Triangle 0.500 0.750 1.000
  term: VF Triangle 0.750 1.000 1.250
)";
constexpr const char* kAngular = R"(
OutputVariable: angular
  enabled: true
  range: -1.250 1.250
  lock-range: false
  aggregation: Maximum
  defuzzifier: Centroid 200
  default: 0.000
  lock-previous: false
  term: NB Triangle -1.250 -1.000 -0.600
  term: NM Triangle -1.000 -0.600 -0.300
  term: NS Triangle -0.600 -0.300 0.000
  term: ZE Triangle -0.300 0.000 0.300
  term: PS Triangle 0.000 0.300 0.600
  term: PM Triangle 0.300 0.600 1.000
  term: PB Triangle 0.600 1.000 1.250
)";
const std::string kOutputs = std::string(kLinear) + kAngular;

// The waypoint's bearing in seven sets, finer near zero where the robot drives.
constexpr const char* kBearing = R"(
InputVariable: bearing
  enabled: true
  range: -3.142 3.142
  lock-range: true
  term: NB Trapezoid -3.142 -3.142 -1.600 -0.900
  term: NM Triangle -1.600 -0.900 -0.350
  term: NS Triangle -0.900 -0.350 0.000
  term: ZE Triangle -0.350 0.000 0.350
  term: PS Triangle 0.000 0.350 0.900
  term: PM Triangle 0.350 0.900 1.600
  term: PB Trapezoid 0.900 1.600 3.142 3.142
)";

constexpr const char* kBlock = R"(
RuleBlock: mamdani
  enabled: true
  conjunction: Minimum
  disjunction: Maximum
  implication: Minimum
  activation: General
)";

const std::string kMotion = std::string("Engine: motion\n") + kBearing + R"(
InputVariable: distance
  enabled: true
  range: 0.000 5.000
  lock-range: true
  term: ZE Trapezoid 0.000 0.000 0.010 0.040
  term: VN Triangle 0.010 0.080 0.200
  term: NE Triangle 0.080 0.200 0.450
  term: ME Triangle 0.200 0.450 0.900
  term: FA Triangle 0.450 0.900 1.600
  term: VF Triangle 0.900 1.600 2.500
  term: EF Trapezoid 1.600 2.500 5.000 5.000
)" + kOutputs + kBlock + R"(
  rule: if bearing is NB and distance is not ZE then angular is NB
  rule: if bearing is NM and distance is not ZE then angular is NM
  rule: if bearing is NS and distance is not ZE then angular is NS
  rule: if bearing is ZE or distance is ZE then angular is ZE
  rule: if bearing is PS and distance is not ZE then angular is PS
  rule: if bearing is PM and distance is not ZE then angular is PM
  rule: if bearing is PB and distance is not ZE then angular is PB
  rule: if bearing is NB or bearing is PB or distance is ZE then linear is ST
  rule: if bearing is NM or bearing is PM then linear is VS
  rule: if bearing is ZE and distance is VN then linear is VS
  rule: if bearing is ZE and distance is NE then linear is SL
  rule: if bearing is ZE and distance is ME then linear is ME
  rule: if bearing is ZE and distance is FA then linear is FA
  rule: if bearing is ZE and distance is VF then linear is VF
  rule: if bearing is ZE and distance is EF then linear is VF
  rule: if (bearing is NS or bearing is PS) and distance is VN then linear is ST
  rule: if (bearing is NS or bearing is PS) and distance is NE then linear is VS
  rule: if (bearing is NS or bearing is PS) and distance is ME then linear is SL
  rule: if (bearing is NS or bearing is PS) and distance is FA then linear is ME
  rule: if (bearing is NS or bearing is PS) and (distance is VF or distance is EF) then linear is FA
)";

std::string Cone(const char* name) {
  return std::string("InputVariable: ") + name + R"(
  enabled: true
  range: 0.000 3.000
  lock-range: true
  term: NE Trapezoid 0.000 0.000 0.300 0.550
  term: ME Triangle 0.300 0.550 0.900
  term: FA Trapezoid 0.550 0.900 3.000 3.000
)";
}

// Away from what is near, toward the freer side; slower the nearer the front.
const std::string kAvoidance =
    std::string("Engine: avoidance\n") + Cone("left") + Cone("front") + Cone("right") + kOutputs + kBlock + R"(
  rule: if front is FA then linear is ME
  rule: if front is ME then linear is SL
  rule: if front is NE then linear is ST
  rule: if front is FA and left is NE and right is not NE then angular is NS
  rule: if front is FA and right is NE and left is not NE then angular is PS
  rule: if front is FA and ((left is NE and right is NE) or (left is not NE and right is not NE)) then angular is ZE
  rule: if front is ME and left is FA and right is not FA then angular is PM
  rule: if front is ME and right is FA and left is not FA then angular is NM
  rule: if front is ME and left is FA and right is FA then angular is PS
  rule: if front is ME and left is not FA and right is not FA then angular is PM
  rule: if front is NE and right is NE and left is not NE then angular is PB
  rule: if front is NE and left is NE and right is not NE then angular is NB
  rule: if front is NE and ((left is not NE and right is not NE) or (left is NE and right is NE)) then angular is PB
)";

// On the spot: the turn rate from the bearing alone, no forward speed.
const std::string kRotation = std::string("Engine: rotation\n") + kBearing + kAngular + kBlock + R"(
  rule: if bearing is NB then angular is NB
  rule: if bearing is NM then angular is NM
  rule: if bearing is NS then angular is NS
  rule: if bearing is ZE then angular is ZE
  rule: if bearing is PS then angular is PS
  rule: if bearing is PM then angular is PM
  rule: if bearing is PB then angular is PB
)";

// An engine from FLL with the variables a controller needs; std::invalid_argument naming the controller otherwise.
std::unique_ptr<fl::Engine> Load(const std::string& controller, const std::string& fll,
                                 std::initializer_list<const char*> inputs,
                                 std::initializer_list<const char*> outputs) {
  std::unique_ptr<fl::Engine> engine;
  try {
    engine.reset(fl::FllImporter().fromString(fll));
  } catch (const std::exception& e) {
    throw std::invalid_argument("flmc " + controller + ": " + e.what());
  }
  for (const char* name : inputs) {
    if (!engine->hasInputVariable(name)) {
      throw std::invalid_argument("flmc " + controller + ": no input variable '" + name + "'");
    }
  }
  for (const char* name : outputs) {
    if (!engine->hasOutputVariable(name)) {
      throw std::invalid_argument("flmc " + controller + ": no output variable '" + name + "'");
    }
  }
  std::string status;
  if (!engine->isReady(&status)) throw std::invalid_argument("flmc " + controller + ": not ready: " + status);
  return engine;
}

double Output(fl::Engine& engine, const char* name, double lo, double hi) {
  const double value = engine.getOutputVariable(name)->getValue();
  return std::isfinite(value) ? std::clamp(value, lo, hi) : 0.0;  // no rule fired: the default, a stop
}

double Finite(double metres) { return std::isfinite(metres) ? metres : 1e3; }

}  // namespace

std::string DefaultFlmcRules(const std::string& controller) {
  if (controller == "motion") return kMotion;
  if (controller == "avoidance") return kAvoidance;
  if (controller == "rotation") return kRotation;
  throw std::invalid_argument("flmc: no controller '" + controller + "' (motion, avoidance, rotation)");
}

const char* ToString(FlmcMode mode) {
  switch (mode) {
    case FlmcMode::kMotion: return "motion";
    case FlmcMode::kAvoidance: return "avoidance";
    case FlmcMode::kRotation: return "rotation";
  }
  return "?";
}

struct Flmc::Engines {
  std::unique_ptr<fl::Engine> motion, avoidance, rotation;
};

Flmc::Flmc(const FlmcOptions& options) : options_(options), engines_(std::make_unique<Engines>()) {
  if (!(options.max_linear_mps > 0.0 && options.max_angular_rps > 0.0)) {
    throw std::invalid_argument("flmc: the top speeds must be positive");
  }
  const auto text = [](const std::string& given, const char* controller) {
    return given.empty() ? DefaultFlmcRules(controller) : given;
  };
  engines_->motion = Load("motion", text(options.motion_fll, "motion"), {"bearing", "distance"}, {"linear", "angular"});
  engines_->avoidance =
      Load("avoidance", text(options.avoidance_fll, "avoidance"), {"left", "front", "right"}, {"linear", "angular"});
  engines_->rotation = Load("rotation", text(options.rotation_fll, "rotation"), {"bearing"}, {"angular"});
}

Flmc::~Flmc() = default;

FlmcOutput Flmc::Step(const FlmcInput& in) {
  FlmcOutput out;
  double linear = 0.0;
  double angular = 0.0;
  const double nearest = std::min({in.left_m, in.front_m, in.right_m});
  if (in.distance_m <= options_.stop_within_m) return out;  // there
  if (in.distance_m <= options_.rotate_within_m && std::abs(in.bearing_rad) > options_.rotate_above_rad) {
    out.mode = FlmcMode::kRotation;
    fl::Engine& e = *engines_->rotation;
    e.setInputValue("bearing", in.bearing_rad);
    e.process();
    angular = Output(e, "angular", -1.0, 1.0);
  } else if (nearest < options_.avoid_within_m) {
    out.mode = FlmcMode::kAvoidance;
    fl::Engine& e = *engines_->avoidance;
    e.setInputValue("left", Finite(in.left_m));
    e.setInputValue("front", Finite(in.front_m));
    e.setInputValue("right", Finite(in.right_m));
    e.process();
    linear = Output(e, "linear", 0.0, 1.0);
    angular = Output(e, "angular", -1.0, 1.0);
  } else {
    out.mode = FlmcMode::kMotion;
    fl::Engine& e = *engines_->motion;
    e.setInputValue("bearing", in.bearing_rad);
    e.setInputValue("distance", Finite(in.distance_m));
    e.process();
    linear = Output(e, "linear", 0.0, 1.0);
    angular = Output(e, "angular", -1.0, 1.0);
  }
  out.twist = {linear * options_.max_linear_mps, angular * options_.max_angular_rps};
  return out;
}

}  // namespace corridor::nav
