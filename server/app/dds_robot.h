// A robot whose devices are served by ROS 2 drivers over DDS (dds.devices, with the simulator off): the participant
// the devices and the DDS bridge share, and the devices themselves, as the graph's Devices.
#pragma once

#include <memory>

#include "drivers/clock.h"
#include "drivers/dds/devices.h"
#include "drivers/dds/participant.h"
#include "server/app/graph.h"
#include "server/runtime/config.h"

namespace corridor::server {

struct DdsRobot {
  std::unique_ptr<drivers::dds::Participant> participant;
  std::unique_ptr<drivers::dds::DdsDepthCamera> camera;
  std::unique_ptr<drivers::dds::DdsLaser> laser;  // null: dds.devices.laser.topic is empty
  std::unique_ptr<drivers::dds::DdsBase> base;

  Devices devices() const;
  // Ends the devices' subscriptions (waiting for a delivery in progress): nothing reaches the graph after it.
  void Stop();
};

// Joins DDS as the configuration says and waits for the camera's CameraInfo (dds.devices.info_wait_s). Throws
// ConfigError when dds.enabled is off, std::runtime_error when DDS cannot start or no camera info comes.
DdsRobot MakeDdsRobot(const Config& config, const drivers::Clock& clock);

}  // namespace corridor::server
