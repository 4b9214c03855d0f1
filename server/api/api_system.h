// The robot as a whole: GET /api/v1/health and /state, teleoperation, the camera's images, the devices and what is
// plugged in, the laser's scan, the bus's topics, the OpenAPI document and the configuration file.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "drivers/clock.h"
#include "drivers/laser2d.h"
#include "server/api/router.h"
#include "server/app/robot_core.h"
#include "server/config/config.h"
#include "server/runtime/bus.h"

namespace corridor::server {

class SystemApi {
 public:
  // `laser`: where the laser is mounted (GET /api/v1/laser/scan); null when the robot has none.
  SystemApi(Bus& bus, const RobotCore& core, const Config& config, const drivers::Clock& clock,
            const drivers::Laser2D* laser);
  void AddRoutes(Router& routes) const;

  // Drives the robot for the dead man's time: {linear_mps, angular_rps} from `source` ("rest", "websocket"); the
  // command applied, or ApiError 400 for a body that is not one.
  nlohmann::json Teleop(const nlohmann::json& body, const std::string& source) const;

 private:
  Response CameraImage(const Request& request, bool depth) const;

  Bus& bus_;
  const RobotCore& core_;
  const Config& config_;
  const drivers::Clock& clock_;
  const drivers::Laser2D* laser_;
  drivers::TimeNs start_ns_;
  nlohmann::json started_config_;  // the configuration file's document when the daemon started (null: unreadable)
};

// The OpenAPI 3.1 document (server/api/openapi.json, built into the binary).
const std::string& OpenApiDocument();

}  // namespace corridor::server
