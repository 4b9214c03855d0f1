#include "nav/policy/takiguchi.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace corridor::nav {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTie = 1e-9;  // costs this close are equal (mirror-image headings' angles differ in the last bit)

bool AllRound(const TakiguchiOptions& o) { return o.field_rad >= 2.0 * kPi - 1e-9; }
// The first ray's bearing (robot frame) and the angle between neighbours.
double FirstRay(const TakiguchiOptions& o) { return -o.field_rad / 2.0; }
double RayStep(const TakiguchiOptions& o) { return o.field_rad / (AllRound(o) ? o.rays : o.rays - 1); }

// Every ray's nearest hit: how far, and the moving object's velocity there (robot frame; zero for a standing thing).
struct Hits {
  std::vector<double> distance_m;
  std::vector<Eigen::Vector2d> velocity;
};

// Casts the rays at a disc centred at `centre` (robot frame) that moves at `velocity` (robot frame).
void Cast(const Eigen::Vector2d& centre, double radius_m, const Eigen::Vector2d& velocity,
          const TakiguchiOptions& options, Hits& hits) {
  const double d = centre.norm();
  if (d - radius_m >= options.range_m) return;
  const int last = options.rays - 1;
  const double step = RayStep(options);
  const double bearing = std::atan2(centre.y(), centre.x());
  // Inside the disc: every ray toward its side of the robot meets it at once.
  const double half = d <= radius_m ? kPi / 2 : std::asin(radius_m / d);
  // The disc's span of bearings may cross the cut at +-pi: try it on both sides.
  for (const double shift : {-2.0 * kPi, 0.0, 2.0 * kPi}) {
    const double low = bearing + shift - half;
    const double high = bearing + shift + half;
    const int first = std::max(0, static_cast<int>(std::ceil((low - FirstRay(options)) / step)));
    const int end = std::min(last, static_cast<int>(std::floor((high - FirstRay(options)) / step)));
    for (int i = first; i <= end; ++i) {
      const double angle = FirstRay(options) + step * i;
      const Eigen::Vector2d u(std::cos(angle), std::sin(angle));
      const double along = u.dot(centre);
      const double across2 = d * d - along * along;
      const double t = d <= radius_m ? 0.0 : along - std::sqrt(std::max(0.0, radius_m * radius_m - across2));
      const auto k = static_cast<std::size_t>(i);
      if (t < hits.distance_m[k]) {
        hits.distance_m[k] = std::max(0.0, t);
        hits.velocity[k] = velocity;
      }
    }
  }
}

}  // namespace

int TakiguchiInputs(const TakiguchiOptions& options) { return 3 * options.rays + 1; }
int TakiguchiClasses(const TakiguchiOptions& options) { return options.headings + 1; }

void CheckTakiguchiOptions(const TakiguchiOptions& options) {
  const auto require = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("takiguchi: ") + what);
  };
  require(options.rays >= 3, "rays: at least 3");
  require(options.field_rad > 0.0 && options.field_rad <= 2.0 * kPi + 1e-9, "field: in (0, 360] degrees");
  require(options.headings >= 2, "headings: at least 2");
  require(options.range_m > 0.0, "range_m: positive");
  require(options.max_object_speed_mps > 0.0, "max_object_speed_mps: positive");
  require(options.min_object_radius_m >= 0.0 && options.point_radius_m > 0.0, "object and point radii: positive");
  require(options.max_linear_mps > 0.0 && options.max_angular_rps > 0.0, "speeds: positive");
  require(options.k_heading > 0.0 && options.turn_in_place_rad > 0.0, "heading controller: positive gains");
}

Eigen::VectorXf TakiguchiInput(const Pose2& robot, const Surroundings& around, double goal_bearing_rad,
                               const TakiguchiOptions& options) {
  const auto n = static_cast<std::size_t>(options.rays);
  Hits hits{std::vector<double>(n, kInf), std::vector<Eigen::Vector2d>(n, Eigen::Vector2d::Zero())};
  const Pose2 to_robot = robot.Inverse();
  const Eigen::Rotation2Dd unrotate(-robot.yaw_rad);
  for (const Eigen::Vector2d& p : around.static_points) {
    Cast(to_robot.Transform(p), options.point_radius_m, Eigen::Vector2d::Zero(), options, hits);
  }
  for (const TrackedObject& o : around.objects) {
    const Eigen::Vector2d velocity = o.moving ? Eigen::Vector2d(unrotate * o.velocity) : Eigen::Vector2d::Zero();
    Cast(to_robot.Transform(o.position), std::max(o.radius_m, options.min_object_radius_m), velocity, options, hits);
  }
  Eigen::VectorXf input(TakiguchiInputs(options));
  const double step = RayStep(options);
  for (int i = 0; i < options.rays; ++i) {
    const auto k = static_cast<std::size_t>(i);
    input(i) = static_cast<float>(std::min(1.0, hits.distance_m[k] / options.range_m));
    const double speed = hits.velocity[k].norm();
    input(options.rays + i) = static_cast<float>(std::min(1.0, speed / options.max_object_speed_mps));
    double direction = 0.0;
    if (speed > 0.0) {
      const double coming_at_robot = FirstRay(options) + step * i + kPi;
      direction = WrapAngle(std::atan2(hits.velocity[k].y(), hits.velocity[k].x()) - coming_at_robot) / kPi;
    }
    input(2 * options.rays + i) = static_cast<float>(direction);
  }
  input(3 * options.rays) = static_cast<float>(WrapAngle(goal_bearing_rad) / kPi);
  return input;
}

std::optional<double> TakiguchiHeading(int klass, const TakiguchiOptions& options) {
  if (klass < 0 || klass > options.headings) {
    throw std::out_of_range("takiguchi: class " + std::to_string(klass) + " of " +
                            std::to_string(TakiguchiClasses(options)));
  }
  if (klass == options.headings) return std::nullopt;
  return -kPi / 2 + kPi * klass / (options.headings - 1);
}

Twist2 HeadingControl(double error_rad, const TakiguchiOptions& options) {
  const double w = std::clamp(options.k_heading * error_rad, -options.max_angular_rps, options.max_angular_rps);
  const double v = std::abs(error_rad) > options.turn_in_place_rad ? 0.0 : options.max_linear_mps * std::cos(error_rad);
  return {v, w};
}

Twist2 TakiguchiCommand(int klass, const TakiguchiOptions& options) {
  const std::optional<double> heading = TakiguchiHeading(klass, options);
  return heading ? HeadingControl(*heading, options) : Twist2{};
}

void CheckTakiguchiNetwork(const Mlp& net, const TakiguchiOptions& options) {
  if (net.inputs() != TakiguchiInputs(options) || net.outputs() != TakiguchiClasses(options)) {
    throw std::invalid_argument("takiguchi: the network has " + std::to_string(net.inputs()) + " inputs and " +
                                std::to_string(net.outputs()) + " outputs, the policy " +
                                std::to_string(TakiguchiInputs(options)) + " and " +
                                std::to_string(TakiguchiClasses(options)) + " (rays " + std::to_string(options.rays) +
                                " over " + std::to_string(std::lround(options.field_rad * 180.0 / kPi)) +
                                " degrees, headings " + std::to_string(options.headings) + ")");
  }
}

std::vector<Eigen::Vector2d> DriveClass(const Pose2& robot, int klass, const TakiguchiOptions& options,
                                        const SafeDirectionOptions& safe) {
  const std::optional<double> heading = TakiguchiHeading(klass, options);
  const int steps = std::max(1, static_cast<int>(std::lround(safe.horizon_s / safe.step_s)));
  std::vector<Eigen::Vector2d> drive;
  drive.reserve(static_cast<std::size_t>(steps));
  Pose2 at = robot;
  for (int i = 0; i < steps; ++i) {
    if (heading)
      at = DriveArc(at, HeadingControl(WrapAngle(robot.yaw_rad + *heading - at.yaw_rad), options), safe.step_s);
    drive.push_back(at.translation());
  }
  return drive;
}

double TimeToMeet(const Eigen::Vector2d& start, const std::vector<Eigen::Vector2d>& drive, const DiscMover& mover,
                  const SafeDirectionOptions& options) {
  const double reach = options.robot_radius_m + mover.radius_m + options.margin_m;
  double before = (mover.position - start).norm();
  for (std::size_t i = 0; i < drive.size(); ++i) {
    const double t = options.step_s * static_cast<double>(i + 1);
    const double gap = (mover.position + mover.velocity * t - drive[i]).norm();
    if (gap < reach && gap < before) return t;
    before = gap;
  }
  return kInf;
}

int SafeDirectionLabel(const Pose2& robot, const std::vector<DiscMover>& movers, double goal_bearing_rad,
                       const TakiguchiOptions& options, const SafeDirectionOptions& safe) {
  const double goal = std::clamp(WrapAngle(goal_bearing_rad), -kPi / 2, kPi / 2);
  int best = options.headings;
  double best_meet = -1.0;
  double best_cost = kInf;
  for (int k = 0; k < TakiguchiClasses(options); ++k) {
    const std::optional<double> heading = TakiguchiHeading(k, options);
    const std::vector<Eigen::Vector2d> drive = DriveClass(robot, k, options, safe);
    double meet = kInf;
    for (const DiscMover& m : movers) meet = std::min(meet, TimeToMeet(robot.translation(), drive, m, safe));
    // Safe choices all count the same; among them (or, with none, among the latest to meet) the cheapest wins, the
    // first of equals (the robot's right).
    const double meet_score = std::min(meet, safe.horizon_s + 1.0);
    const double cost = heading ? std::abs(*heading - goal) : safe.stop_cost_rad;
    if (meet_score > best_meet || (meet_score == best_meet && cost < best_cost - kTie)) {
      best = k;
      best_meet = meet_score;
      best_cost = cost;
    }
  }
  return best;
}

std::vector<DiscMover> MoversAround(const Eigen::Vector2d& robot, const Surroundings& around, double reach_m,
                                    const TakiguchiOptions& options) {
  std::vector<DiscMover> movers;
  for (const TrackedObject& o : around.objects) {
    const double radius = std::max(o.radius_m, options.min_object_radius_m);
    if ((o.position - robot).norm() - radius > reach_m) continue;
    movers.push_back({o.position, o.moving ? o.velocity : Eigen::Vector2d::Zero(), radius});
  }
  for (const Eigen::Vector2d& p : around.static_points) {
    if ((p - robot).norm() - options.point_radius_m > reach_m) continue;
    movers.push_back({p, Eigen::Vector2d::Zero(), options.point_radius_m});
  }
  return movers;
}

}  // namespace corridor::nav
