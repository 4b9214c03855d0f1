#include "server/api/api_calibration.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numbers>
#include <optional>
#include <random>

#include "nav/ground/depth_scan.h"
#include "nav/ground/floor_fit.h"
#include "nav/localization/range_scan.h"
#include "nav/localization/sensor_calibration.h"
#include "server/runtime/topics.h"

namespace corridor::server {

// The laser's hits in the base frame (or its own), with where the odometry had the robot standing. Outside the
// anonymous namespace: WheelCalibration, declared in the header, keeps one.
struct Standing {
  std::vector<Eigen::Vector2f> hits;
  nav::Pose2 odom;
};

namespace {

using auth::Access;
using nlohmann::json;

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

double Round(double value, double unit) { return std::round(value / unit) * unit; }

// The laser's hits in the base frame (or its own, `in_laser_frame`), with the robot standing still; throws ApiError
// when there is no laser, no scan or odometry yet, or the robot is moving.
Standing StandingScan(Bus& bus, const drivers::Laser2D* laser, bool in_laser_frame) {
  if (laser == nullptr) {
    throw ApiError(http::status::not_found, "No laser", "this robot has no laser (devices.laser.driver: none)");
  }
  const auto odometry = bus.Get(topics::kOdometry).latest();
  const auto scan = bus.Get(topics::kScan).latest();
  if (!odometry || !scan) {
    throw ApiError(http::status::service_unavailable, "Not yet",
                   "the base's odometry or the laser's scan has not come yet");
  }
  if (std::abs(odometry->velocity.linear_mps) > 0.01 || std::abs(odometry->velocity.angular_rps) > 0.02) {
    throw ApiError(http::status::conflict, "Moving", "the robot is moving: stop it, then measure", "moving");
  }
  const nav::Pose2 mount = in_laser_frame ? nav::Pose2{} : laser->base_T_laser();
  const nav::RangeLimits limits{
      .min_range_m = scan->range_min_m, .max_range_m = scan->range_max_m, .miss_length_m = 0.0};
  return {nav::ScanFromRanges(mount, scan->angle_min_rad, scan->angle_increment_rad, scan->ranges, limits).hits,
          odometry->odom_T_base};
}

ApiError Refused(nav::CalibrationError error, const std::string& detail) {
  return ApiError(http::status::unprocessable_entity, "Not measured", detail, nav::ToString(error));
}

// The wheels the base's driver counts with; null for a base whose odometry is not ours (a ROS 2 driver's).
const drivers::WheelGeometry* ConfiguredWheels(const Config& config) {
  const BaseSlotOptions& base = config.devices.base;
  switch (base.driver) {
    case DeviceDriver::kCreate2: return &base.create2.wheels;
    case DeviceDriver::kKobuki: return &base.kobuki.wheels;
    case DeviceDriver::kTurtlebot3: return &base.turtlebot3.wheels;
    case DeviceDriver::kSerialText: return &base.serial_text.wheels;
    default: return nullptr;
  }
}

}  // namespace

// A wheel calibration under way: where the run began, and the wheels' diameter factor a straight run measured (not yet
// in the odometry, which counts with the configuration read at start).
struct WheelCalibration {
  std::mutex mutex;
  std::optional<Standing> start;
  double diameter_factor = 1.0;
};

CalibrationApi::CalibrationApi(Bus& bus, const Config& config, const drivers::Laser2D* laser,
                               const drivers::DepthCamera* camera)
    : bus_(bus),
      config_(config),
      laser_(laser),
      camera_(camera),
      wheel_calibration_(std::make_shared<WheelCalibration>()) {}

void CalibrationApi::AddRoutes(Router& routes) const {
  // The camera's height, tilt and roll measured from the floor in its latest depth frame, and the configuration's keys
  // that would hold them.
  routes.Add(
      http::verb::post, "/api/v1/devices/camera/calibration", Access::kAdmin,
      Sync([this](const Request& r, const Params&) {
        if (camera_ == nullptr) {
          throw ApiError(http::status::not_found, "No camera",
                         "this robot has no camera (devices.camera.driver: none)");
        }
        const auto frame = bus_.Get(topics::kRgbd).latest();
        if (!frame)
          throw ApiError(http::status::service_unavailable, "No camera frame", "the camera has not sent a frame yet");
        const nav::PinholeCamera camera = camera_->info().camera;
        std::mt19937 rng(1);
        const std::optional<nav::FloorFit> fit = nav::FitFloor(frame->depth_mm, camera, nav::FloorFitOptions{}, rng);
        if (!fit) {
          throw ApiError(http::status::unprocessable_entity, "No floor",
                         "no plane in the lower half of the depth image looks like the floor: point the robot at open "
                         "floor (nothing in the nearest two metres ahead) and try again",
                         "no_floor");
        }
        const Eigen::Isometry3d measured = nav::MountingFromFloor(*fit, camera.base_T_camera);
        const double height_m = measured.translation().z();
        const double tilt_deg = fit->tilt_rad * kDegPerRad;
        // The configured mounting: the optical axis's pitch below the horizontal, and the optical centre's height.
        const Eigen::Vector3d axis = camera.base_T_camera.linear() * Eigen::Vector3d::UnitZ();
        const double configured_tilt_deg = std::asin(std::clamp(-axis.z(), -1.0, 1.0)) * kDegPerRad;
        const json mount{{"mount_height_m", Round(height_m, 0.001)}, {"tilt_deg", Round(tilt_deg, 0.1)}};
        const bool sim = config_.devices.camera.driver == DeviceDriver::kSim;
        return JsonResponse(
            r,
            {{"height_m", height_m},
             {"tilt_deg", tilt_deg},
             {"roll_deg", fit->roll_rad * kDegPerRad},
             {"inlier_fraction", fit->inlier_fraction},
             {"configured", {{"height_m", camera.base_T_camera.translation().z()}, {"tilt_deg", configured_tilt_deg}}},
             {"patch", sim ? json{{"sim", {{"camera", mount}}}} : json{{"devices", {{"camera", mount}}}}}});
      }));
  // The laser's yaw from its latest scan laid on the camera's latest frame, cut at the laser's height.
  routes.Add(http::verb::post, "/api/v1/devices/laser/calibration", Access::kAdmin,
             Sync([this](const Request& r, const Params&) {
               const Standing laser = StandingScan(bus_, laser_, true);
               if (camera_ == nullptr) {
                 throw ApiError(http::status::not_found, "No camera",
                                "the laser's yaw is measured against the camera, and this robot has none");
               }
               const auto frame = bus_.Get(topics::kRgbd).latest();
               if (!frame)
                 throw ApiError(http::status::service_unavailable, "No camera frame",
                                "the camera has not sent a frame yet");
               const double height = laser_->height_m();
               nav::DepthScanOptions cut;
               cut.min_height_m = std::max(0.02, height - 0.05);
               cut.max_height_m = height + 0.05;
               cut.segment_gap_m = 0.0;
               cut.average_within_m = 0.05;  // the wall where it is, not the nearest of its noisy pixels
               nav::DepthScan depth_scan(camera_->info().camera, cut);
               const std::vector<Eigen::Vector2d>& seen = depth_scan.Process(frame->depth_mm);
               const nav::Pose2 mount = laser_->base_T_laser();
               const nav::LaserYawFit fit = nav::FitLaserYaw(seen, depth_scan.View(nav::Pose2{}), laser.hits, mount);
               if (fit.error != nav::CalibrationError::kNone) throw Refused(fit.error, fit.detail);
               const double yaw_deg = Round(nav::WrapAngle(fit.yaw_rad) * kDegPerRad, 0.1);
               const json keys{{"mount_yaw_deg", yaw_deg}};
               const bool sim = config_.devices.laser.driver == DeviceDriver::kSim;
               return JsonResponse(
                   r, {{"yaw_deg", fit.yaw_rad * kDegPerRad},
                       {"configured", {{"yaw_deg", mount.yaw_rad * kDegPerRad}}},
                       {"score", fit.score},
                       {"points", fit.points},
                       {"patch", sim ? json{{"sim", {{"laser", keys}}}} : json{{"devices", {{"laser", keys}}}}}});
             }));
  routes.Add(http::verb::post, "/api/v1/devices/wheels/calibration/start", Access::kAdmin,
             Sync([this](const Request& r, const Params&) {
               Standing start = StandingScan(bus_, laser_, false);
               std::lock_guard lock(wheel_calibration_->mutex);
               wheel_calibration_->start = std::move(start);
               return JsonResponse(r,
                                   {{"started", true},
                                    {"diameter_factor", wheel_calibration_->diameter_factor},
                                    {"next",
                                     "drive straight at least 0.5 m towards or away from a wall, or turn on the spot "
                                     "between 90 and 175 degrees; stop; then finish"}});
             }));
  routes.Add(http::verb::post, "/api/v1/devices/wheels/calibration/finish", Access::kAdmin,
             Sync([this](const Request& r, const Params&) {
               const Standing end = StandingScan(bus_, laser_, false);
               std::lock_guard lock(wheel_calibration_->mutex);
               WheelCalibration& run = *wheel_calibration_;
               if (!run.start) {
                 throw ApiError(http::status::conflict, "Not started",
                                "start the run first (POST /api/v1/devices/wheels/calibration/start)", "not_started");
               }
               const nav::WheelRunFit fit = nav::FitWheelRun(run.start->hits, end.hits, run.start->odom, end.odom);
               if (fit.error != nav::CalibrationError::kNone) throw Refused(fit.error, fit.detail);
               run.start.reset();
               const bool straight = fit.kind == nav::WheelRunKind::kStraight;
               if (straight) run.diameter_factor = fit.factor;
               // A turn measures the track with the odometry's diameter; a straight run's factor not yet in it corrects
               // it.
               const double diameter_factor = run.diameter_factor;
               const double track_factor = straight ? 1.0 : nav::TrackFactor(fit, diameter_factor);
               json patch = nullptr;
               if (const drivers::WheelGeometry* wheels = ConfiguredWheels(config_)) {
                 json keys{{"wheel_diameter_m", Round(wheels->wheel_diameter_m * diameter_factor, 1e-5)}};
                 if (!straight) keys["track_m"] = Round(wheels->track_m * track_factor, 1e-5);
                 patch = {{"devices", {{"base", keys}}}};
               } else if (config_.devices.base.driver == DeviceDriver::kSim) {
                 const drivers::sim::SimBaseOptions& base = config_.sim.robot.base;
                 json keys{{"wheel_diameter_error", Round(base.wheel_diameter_error * diameter_factor, 1e-5)}};
                 if (!straight) keys["track_error"] = Round(base.track_error * track_factor, 1e-5);
                 patch = {{"sim", {{"base", keys}}}};
               }
               const double unit = straight ? 1.0 : kDegPerRad;
               return JsonResponse(r, {{"run", straight ? "straight" : "turn"},
                                       {"unit", straight ? "m" : "deg"},
                                       {"odometry", fit.odometry * unit},
                                       {"measured", fit.measured * unit},
                                       {"score", fit.score},
                                       {"diameter_factor", diameter_factor},
                                       {"track_factor", track_factor},
                                       {"patch", patch}});
             }));
}

}  // namespace corridor::server
