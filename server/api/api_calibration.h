// Routes that measure the robot's own geometry and answer with the configuration patch that would keep it (sent to
// PATCH /api/v1/config by whoever decides; read at the next start): the camera's height and tilt from the floor
// (POST /api/v1/devices/camera/calibration), the laser's yaw against the camera (POST
// /api/v1/devices/laser/calibration), and the wheels' diameter and track from a straight run and a turn on the spot
// (POST /api/v1/devices/wheels/calibration/start, then drive, then .../finish). The measuring is nav's
// (nav/ground/floor_fit.h, nav/localization/sensor_calibration.h); these only gather what it reads.
#pragma once

#include <memory>

#include "drivers/depth_camera.h"
#include "drivers/laser2d.h"
#include "server/api/router.h"
#include "server/config/config.h"
#include "server/runtime/bus.h"

namespace corridor::server {

class CalibrationApi {
 public:
  // `laser`, `camera`: where they are mounted and the camera's intrinsics; null for a device the robot lacks.
  CalibrationApi(Bus& bus, const Config& config, const drivers::Laser2D* laser, const drivers::DepthCamera* camera);
  void AddRoutes(Router& routes) const;

 private:
  Bus& bus_;
  const Config& config_;
  const drivers::Laser2D* laser_;
  const drivers::DepthCamera* camera_;
  std::shared_ptr<struct WheelCalibration> wheel_calibration_;  // a wheel calibration run under way
};

}  // namespace corridor::server
