#include "nav/localization/sensor_calibration.h"

#include <algorithm>
#include <cmath>

#include <iomanip>
#include <numbers>
#include <sstream>

#include "nav/localization/hit_field.h"
#include "nav/localization/range_scan.h"
#include "nav/localization/scan_matcher.h"

namespace corridor::nav {
namespace {

double Degrees(double rad) { return rad * 180.0 / std::numbers::pi; }

// Fine enough that a wall is placed to a centimetre or two; scan matching interpolates between cells.
constexpr HitFieldOptions kField{.resolution_m = 0.02, .sigma_m = 0.03, .grow_margin_m = 1.0};

HitField FieldOf(std::span<const Eigen::Vector2f> hits) {
  RangeScan scan;
  scan.hits.assign(hits.begin(), hits.end());
  HitField field(kField);
  field.Insert(scan, Pose2{});
  return field;
}

}  // namespace

const char* ToString(CalibrationError error) {
  switch (error) {
    case CalibrationError::kNone: return "none";
    case CalibrationError::kTooFewPoints: return "too_few_points";
    case CalibrationError::kNoMatch: return "no_match";
    case CalibrationError::kNotARun: return "not_a_run";
    case CalibrationError::kDegenerate: return "degenerate";
  }
  return "unknown";
}

LaserYawFit FitLaserYaw(std::span<const Eigen::Vector2d> camera_points, const SensorView& camera_view,
                        std::span<const Eigen::Vector2f> laser_points, const Pose2& base_T_laser,
                        const LaserYawOptions& options) {
  LaserYawFit fit;
  fit.yaw_rad = base_T_laser.yaw_rad;
  // The laser's points the camera can see too, turned by as much as the window either way (a point near the view's
  // edge may come into it at another yaw: kept when it is inside with room to turn).
  std::vector<Eigen::Vector2f> points;
  for (const Eigen::Vector2f& p : laser_points) {
    const Eigen::Vector2d in_base = base_T_laser.Transform(p.cast<double>());
    if (p.norm() > options.max_range_m || !camera_view.Covers(in_base, 0.0)) continue;
    points.push_back(p);
  }
  fit.points = static_cast<int>(points.size());
  std::vector<Eigen::Vector2f> reference;
  reference.reserve(camera_points.size());
  for (const Eigen::Vector2d& p : camera_points) reference.push_back(p.cast<float>());
  if (fit.points < options.min_points || reference.size() < static_cast<std::size_t>(options.min_points)) {
    fit.error = CalibrationError::kTooFewPoints;
    std::ostringstream detail;
    detail << fit.points << " laser points and " << reference.size() << " camera points in the camera's view ("
           << options.min_points << " of each needed): face the robot to a wall or furniture within "
           << options.max_range_m << " m that both see";
    fit.detail = detail.str();
    return fit;
  }
  const HitField field = FieldOf(reference);
  // Turned about the laser only: its position is as mounted.
  const SearchWindow window{.linear_m = 0.0,
                            .angular_rad = options.window_rad,
                            .angular_step_rad = options.step_rad,
                            .translation_cost = 0.0,
                            .rotation_cost = 0.0};
  const ScanMatch best = CorrelativeMatch(field, points, base_T_laser, window);
  fit.yaw_rad = best.pose.yaw_rad;
  fit.score = best.score;
  if (best.score < options.min_score) {
    fit.error = CalibrationError::kNoMatch;
    std::ostringstream detail;
    detail << std::fixed << std::setprecision(2) << "the laser's points line up with the camera's at best "
           << best.score << " (" << options.min_score << " needed) within " << std::setprecision(0)
           << Degrees(options.window_rad) << " degrees of the configured yaw: do both see the same things at the "
           << "laser's height?";
    fit.detail = detail.str();
  }
  return fit;
}

WheelRunFit FitWheelRun(std::span<const Eigen::Vector2f> start_points, std::span<const Eigen::Vector2f> end_points,
                        const Pose2& odom_start, const Pose2& odom_end, const WheelRunOptions& options) {
  WheelRunFit fit;
  const Pose2 odometry = odom_start.Inverse() * odom_end;  // the run, in the start's base frame
  const double distance = odometry.translation().norm();
  const double turn = std::abs(odometry.yaw_rad);
  if (distance >= options.min_distance_m && turn <= options.max_straight_turn_rad) {
    fit.kind = WheelRunKind::kStraight;
    fit.odometry = distance;
  } else if (turn >= options.min_turn_rad && turn <= options.max_turn_rad && distance <= options.max_turn_drift_m) {
    fit.kind = WheelRunKind::kTurn;
    fit.odometry = odometry.yaw_rad;
  } else {
    fit.error = CalibrationError::kNotARun;
    std::ostringstream detail;
    detail << std::fixed << std::setprecision(2) << "the odometry shows " << distance << " m and "
           << std::setprecision(0) << Degrees(odometry.yaw_rad) << " degrees: drive straight at least "
           << std::setprecision(1) << options.min_distance_m << " m (turning less than " << std::setprecision(0)
           << Degrees(options.max_straight_turn_rad) << " degrees), or turn on the spot between "
           << Degrees(options.min_turn_rad) << " and " << Degrees(options.max_turn_rad) << " degrees";
    fit.detail = detail.str();
    return fit;
  }
  if (start_points.size() < static_cast<std::size_t>(options.min_points) ||
      end_points.size() < static_cast<std::size_t>(options.min_points)) {
    fit.error = CalibrationError::kTooFewPoints;
    std::ostringstream detail;
    detail << "the laser saw " << start_points.size() << " and " << end_points.size() << " points ("
           << options.min_points << " needed): run where walls are in its range";
    fit.detail = detail.str();
    return fit;
  }
  const HitField field = FieldOf(start_points);
  // Systematic odometry errors are a few percent: a window of a sixth of the run either way, and then the least-
  // squares refinement, hardly pulled towards the correlative result.
  SearchWindow window;
  window.linear_m = fit.kind == WheelRunKind::kStraight ? distance / 6.0 + 0.05 : 0.1;
  window.angular_rad = fit.kind == WheelRunKind::kTurn ? turn / 6.0 + 0.05 : 0.1;
  window.translation_cost = 0.0;
  window.rotation_cost = 0.0;
  const ScanMatch coarse = CorrelativeMatch(field, end_points, odometry, window);
  const Pose2 refined = RefineMatch(field, end_points, coarse.pose, coarse.pose,
                                    RefineOptions{.translation_weight = 0.01, .rotation_weight = 0.01});
  fit.score = ScoreAt(field, end_points, refined);
  if (fit.score < options.min_score) {
    fit.error = CalibrationError::kNoMatch;
    std::ostringstream detail;
    detail << std::fixed << std::setprecision(2) << "the scans after the run line up with those before at best "
           << fit.score << " (" << options.min_score << " needed): something moved, or the robot was moving when a "
           << "scan was taken";
    fit.detail = detail.str();
    return fit;
  }
  if (fit.kind == WheelRunKind::kStraight) {
    // The scans must pin the distance: moved 10 cm further along the run or back, the match must be clearly worse.
    const Eigen::Vector2d along = refined.translation().normalized() * 0.1;
    const double worse =
        std::max(ScoreAt(field, end_points, Pose2{refined.x_m + along.x(), refined.y_m + along.y(), refined.yaw_rad}),
                 ScoreAt(field, end_points, Pose2{refined.x_m - along.x(), refined.y_m - along.y(), refined.yaw_rad}));
    if (worse > 0.9 * fit.score) {
      fit.error = CalibrationError::kDegenerate;
      fit.detail =
          "the scans line up as well 10 cm further along the run: drive towards or away from a wall across "
          "the way (a corridor whose end the laser cannot see does not pin the distance)";
      return fit;
    }
    fit.measured = refined.translation().norm();
    fit.factor = fit.measured / fit.odometry;
  } else {
    // The turn as the odometry counts it, corrected by the scans' small difference (the pose's yaw wraps).
    fit.measured = fit.odometry + WrapAngle(refined.yaw_rad - odometry.yaw_rad);
    fit.factor = fit.odometry / fit.measured;
  }
  return fit;
}

}  // namespace corridor::nav
