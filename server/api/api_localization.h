// Where the robot is and the maps it makes: GET /api/v1/localization, PUT /api/v1/localization/pose, POST
// /api/v1/localization/relocalize; mapping a new building: POST /api/v1/mapping/start, /explore and /stop, GET
// /api/v1/mapping and /api/v1/mapping/image.
#pragma once

#include "server/api/router.h"
#include "server/app/robot_core.h"
#include "server/config/config.h"
#include "server/runtime/bus.h"

namespace corridor::server {

class LocalizationApi {
 public:
  LocalizationApi(Bus& bus, const RobotCore& core, const LocalizationOptions& options);
  void AddRoutes(Router& routes) const;

 private:
  void AddMappingRoutes(Router& routes) const;

  Bus& bus_;
  const RobotCore& core_;
  const LocalizationOptions& options_;
};

// ApiError 409 not_localizing unless localization maps and takes poses (RobotCore::NotLocalizing).
void RequireLocalizing(const RobotCore& core);

}  // namespace corridor::server
