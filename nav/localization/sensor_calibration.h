// Calibrations that measure the robot's own geometry from what its sensors see, by scan matching (scan_matcher.h):
//
// - the laser's mounting yaw against the depth camera: the camera's scan at the laser's height (nav/ground/
//   depth_scan.h) is the reference, and the laser's points are turned about the laser until they fall on it;
// - the wheels' diameter and track (UMBmark's idea, Borenstein and Feng, "Measurement and correction of systematic
//   odometry errors in mobile robots", IEEE T-RA 1996: the systematic errors are a scale of distance and a scale of
//   turn), from a straight run and a turn on the spot: the laser's scans before and after are matched, and the motion
//   they show is set against the odometry's. Driving straight scales the wheels' diameter by measured over odometry;
//   turning (with the diameter right) scales the track by odometry over measured.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "nav/geometry/pose2.h"
#include "nav/geometry/sensor_view.h"

namespace corridor::nav {

enum class CalibrationError {
  kNone,
  kTooFewPoints,  // the sensors see too little (nothing within range, or the camera's view empty)
  kNoMatch,       // the scans do not line up anywhere in the window
  kNotARun,       // the odometry shows neither a straight run nor a turn on the spot of the sizes asked for
  kDegenerate,    // the scans line up as well at other distances along the run (a corridor with no end in sight)
};
const char* ToString(CalibrationError error);

struct LaserYawOptions {
  double window_rad = 0.35;  // +- around the configured yaw
  double step_rad = 0.002;   // the search's resolution
  double max_range_m = 4.0;  // laser points farther than this are not matched (the camera's scan ends there)
  int min_points = 20;       // laser points inside the camera's view needed
  double min_score = 0.4;    // mean match value at the best yaw needed
};

struct LaserYawFit {
  CalibrationError error = CalibrationError::kNone;
  std::string detail;    // for people: what was wrong
  double yaw_rad = 0.0;  // the laser's yaw in the base frame at which its points best fall on the camera's
  double score = 0.0;    // mean match value there, [0, 1]
  int points = 0;        // laser points matched
};

// `camera_points`: the depth camera's scan at the laser's height, base frame; `camera_view`: the floor it covers
// (base frame); `laser_points`: the laser's hits in its own frame; `base_T_laser`: its configured mounting.
LaserYawFit FitLaserYaw(std::span<const Eigen::Vector2d> camera_points, const SensorView& camera_view,
                        std::span<const Eigen::Vector2f> laser_points, const Pose2& base_T_laser,
                        const LaserYawOptions& options = {});

struct WheelRunOptions {
  double min_distance_m = 0.5;          // a straight run at least this long
  double max_straight_turn_rad = 0.15;  // and turning no more than this on the way
  double min_turn_rad = 1.5;            // a turn on the spot of at least this (a quarter turn)
  double max_turn_rad = 3.1;            // and at most this: the odometry's pose wraps at half a turn
  double max_turn_drift_m = 0.15;       // moving no farther than this on the way
  double min_score = 0.5;               // mean match value of the second scan on the first needed
  int min_points = 30;                  // of the second scan
};

enum class WheelRunKind { kStraight, kTurn };

struct WheelRunFit {
  CalibrationError error = CalibrationError::kNone;
  std::string detail;
  WheelRunKind kind = WheelRunKind::kStraight;
  double odometry = 0.0;  // the run as the odometry has it: metres straight, radians turned
  double measured = 0.0;  // as the scans show it
  double score = 0.0;
  // Straight: the wheel diameter's factor (measured / odometry). Turn: the track's (odometry / measured).
  double factor = 1.0;
};

// `start_points`, `end_points`: the laser's hits in the base frame at the start and the end of the run (with the
// robot standing); `odom_start`, `odom_end`: the odometry's poses then.
WheelRunFit FitWheelRun(std::span<const Eigen::Vector2f> start_points, std::span<const Eigen::Vector2f> end_points,
                        const Pose2& odom_start, const Pose2& odom_end, const WheelRunOptions& options = {});

// The track's factor (true over configured) from a turn, when the odometry still counts with a wheel diameter that a
// straight run found `diameter_factor` times too small (1 when the diameter is right): the wheels' travel, and so the
// turn the odometry makes of it, is that much off too.
inline double TrackFactor(const WheelRunFit& turn, double diameter_factor) { return diameter_factor * turn.factor; }

}  // namespace corridor::nav
