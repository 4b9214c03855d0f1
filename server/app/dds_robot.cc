#include "server/app/dds_robot.h"

#include <spdlog/spdlog.h>

#include "server/dds/bridge.h"

namespace corridor::server {

Devices DdsRobot::devices() const {
  return Devices{*camera, *base, laser.get(), nullptr, nullptr, nullptr, participant.get()};
}

void DdsRobot::Stop() {
  if (camera) camera->Stop();
  if (laser) laser->Stop();
  if (base) base->Stop();
}

DdsRobot MakeDdsRobot(const Config& config, const drivers::Clock& clock) {
  if (!config.dds.enabled) {
    throw ConfigError(
        "sim.enabled: false needs the robot's devices over DDS (dds.enabled and dds.devices): no other "
        "real drivers are built yet");
  }
  DdsRobot robot;
  robot.participant = MakeParticipant(config.dds);
  const DdsDevicesOptions& d = config.dds.devices;
  robot.camera = std::make_unique<drivers::dds::DdsDepthCamera>(*robot.participant, d.camera, clock);
  if (!d.laser.topic.empty()) {
    robot.laser = std::make_unique<drivers::dds::DdsLaser>(*robot.participant, d.laser, clock);
  }
  robot.base = std::make_unique<drivers::dds::DdsBase>(*robot.participant, d.base, clock);
  spdlog::info("dds: waiting for the camera's info on {} (domain {})", d.camera.info_topic,
               robot.participant->options().domain_id);
  robot.camera->WaitForInfo(std::chrono::milliseconds(static_cast<long>(d.info_wait_s * 1000.0)));
  const nav::PinholeCamera& k = robot.camera->info().camera;
  spdlog::info("dds: camera {} x {} (fx {:.1f}), depth on {}{}; odometry on {}, commands to {}", k.width, k.height,
               k.fx, d.camera.depth_topic, d.laser.topic.empty() ? "" : ", scans on " + d.laser.topic,
               d.base.odom_topic, d.base.cmd_vel_topic);
  return robot;
}

}  // namespace corridor::server
