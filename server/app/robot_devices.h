// The robot's devices as devices.* configures them (docs/hardware.md): the simulator's robot, ROS 2 drivers over
// DDS, native drivers on serial ports, or a mix of the last two, each slot with its driver. What the graph drives.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "drivers/clock.h"
#include "drivers/create2/create2_base.h"
#include "drivers/dds/devices.h"
#include "drivers/dds/participant.h"
#include "drivers/dynamixel/pan_servo.h"
#include "drivers/hokuyo/hokuyo_laser.h"
#include "drivers/kobuki/kobuki_base.h"
#include "drivers/lds/lds_laser.h"
#include "drivers/openni2/openni2_camera.h"
#include "drivers/realsense/realsense_camera.h"
#include "drivers/rplidar/rplidar_laser.h"
#include "drivers/serial_text/serial_text_base.h"
#include "drivers/stereo/stereo_camera.h"
#include "drivers/turtlebot3/turtlebot3_base.h"
#include "server/app/graph.h"
#include "server/app/simulator.h"
#include "server/config/config.h"

namespace corridor::server {

class RobotDevices {
 public:
  // Starts every slot's driver on `clock` (which must outlive them). With a camera over DDS, waits for its CameraInfo
  // (devices.camera.info_wait_s). Native drivers start at once and keep trying their ports in the background (a
  // device plugged in later is taken up). Throws std::runtime_error when the simulator's world cannot be loaded, DDS
  // cannot start, or no camera info comes.
  RobotDevices(const Config& config, const drivers::Clock& clock);
  RobotDevices(const RobotDevices&) = delete;
  RobotDevices& operator=(const RobotDevices&) = delete;
  ~RobotDevices();

  Devices devices() const;
  // The simulator, when the devices are the simulator's robot.
  const Simulator* simulator() const { return sim_ ? &*sim_ : nullptr; }
  // Stops every driver (DDS subscriptions ended, native drivers' threads joined, their devices stopped): no driver
  // callback reaches the graph after it. Idempotent.
  void Stop();

 private:
  std::optional<Simulator> sim_;
  std::unique_ptr<drivers::dds::Participant> participant_;
  std::unique_ptr<drivers::dds::DdsDepthCamera> dds_camera_;
  std::unique_ptr<drivers::dds::DdsLaser> dds_laser_;
  std::unique_ptr<drivers::dds::DdsBase> dds_base_;
  std::unique_ptr<drivers::create2::Create2Base> create2_;
  std::unique_ptr<drivers::kobuki::KobukiBase> kobuki_;
  std::unique_ptr<drivers::turtlebot3::TurtleBot3Base> turtlebot3_;
  std::unique_ptr<drivers::serial_text::SerialTextBase> serial_text_;
  std::unique_ptr<drivers::rplidar::RplidarLaser> rplidar_;
  std::unique_ptr<drivers::hokuyo::HokuyoLaser> hokuyo_;
  std::unique_ptr<drivers::lds::LdsLaser> lds_;
  std::unique_ptr<drivers::realsense::RealSenseCamera> realsense_;
  std::unique_ptr<drivers::stereo::StereoCamera> stereo_;
  std::unique_ptr<drivers::openni2::OpenNi2Camera> openni2_;
  std::unique_ptr<drivers::dynamixel::DynamixelPanServo> dynamixel_pan_;
  drivers::DepthCamera* camera_ = nullptr;
  drivers::DiffDriveBase* base_ = nullptr;
  drivers::Laser2D* laser_ = nullptr;
  drivers::Battery* battery_ = nullptr;
  drivers::PanServo* pan_ = nullptr;
  std::vector<DeviceSlot> slots_;
};

}  // namespace corridor::server
