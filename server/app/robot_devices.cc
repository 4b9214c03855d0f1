#include "server/app/robot_devices.h"

#include <spdlog/spdlog.h>

#include "server/dds/bridge.h"

namespace corridor::server {

RobotDevices::RobotDevices(const Config& config, const drivers::Clock& clock) {
  const DevicesOptions& d = config.devices;
  if (Simulated(config)) {
    sim_ = MakeSimulator(config);
    const Devices simulated = sim_->devices(config);
    camera_ = simulated.camera;
    base_ = &simulated.base;
    laser_ = simulated.laser;
    battery_ = simulated.battery;
    pan_ = simulated.pan;
    slots_ = simulated.slots;
    return;
  }
  const bool any_dds = d.base.driver == DeviceDriver::kDds || d.laser.driver == DeviceDriver::kDds ||
                       d.camera.driver == DeviceDriver::kDds;
  if (any_dds) participant_ = MakeParticipant(config.dds);
  switch (d.base.driver) {
    case DeviceDriver::kDds:
      dds_base_ = std::make_unique<drivers::dds::DdsBase>(*participant_, d.base.dds, clock);
      base_ = dds_base_.get();
      if (dds_base_->has_battery()) battery_ = dds_base_.get();
      slots_.push_back({nav::Device::kBase, "dds", d.base.dds.odom_topic, nullptr});
      break;
    case DeviceDriver::kCreate2:
      create2_ = std::make_unique<drivers::create2::Create2Base>(d.base.create2, clock);
      base_ = create2_.get();
      battery_ = create2_.get();
      slots_.push_back({nav::Device::kBase, "create2", d.base.create2.port.string(), create2_.get()});
      break;
    case DeviceDriver::kKobuki:
      kobuki_ = std::make_unique<drivers::kobuki::KobukiBase>(d.base.kobuki, clock);
      base_ = kobuki_.get();
      battery_ = kobuki_.get();
      slots_.push_back({nav::Device::kBase, "kobuki", d.base.kobuki.port.string(), kobuki_.get()});
      break;
    case DeviceDriver::kTurtlebot3:
      turtlebot3_ = std::make_unique<drivers::turtlebot3::TurtleBot3Base>(d.base.turtlebot3, clock);
      base_ = turtlebot3_.get();
      battery_ = turtlebot3_.get();
      slots_.push_back({nav::Device::kBase, "turtlebot3", d.base.turtlebot3.port.string(), turtlebot3_.get()});
      break;
    case DeviceDriver::kSerialText:  // no battery in its protocol
      serial_text_ = std::make_unique<drivers::serial_text::SerialTextBase>(d.base.serial_text, clock);
      base_ = serial_text_.get();
      slots_.push_back({nav::Device::kBase, "serial-text", d.base.serial_text.port.string(), serial_text_.get()});
      break;
    default: throw ConfigError(std::string("devices.base.driver: ") + ToString(d.base.driver) + " is not a base");
  }
  switch (d.laser.driver) {
    case DeviceDriver::kDds:
      dds_laser_ = std::make_unique<drivers::dds::DdsLaser>(*participant_, d.laser.dds, clock);
      laser_ = dds_laser_.get();
      slots_.push_back({nav::Device::kLaser, "dds", d.laser.dds.topic, nullptr});
      break;
    case DeviceDriver::kRplidar:
      rplidar_ = std::make_unique<drivers::rplidar::RplidarLaser>(d.laser.rplidar, clock);
      laser_ = rplidar_.get();
      slots_.push_back({nav::Device::kLaser, "rplidar", d.laser.rplidar.port.string(), rplidar_.get()});
      break;
    case DeviceDriver::kHokuyo:
      hokuyo_ = std::make_unique<drivers::hokuyo::HokuyoLaser>(d.laser.hokuyo, clock);
      laser_ = hokuyo_.get();
      slots_.push_back({nav::Device::kLaser, "hokuyo", d.laser.hokuyo.port, hokuyo_.get()});
      break;
    case DeviceDriver::kLds:
      lds_ = std::make_unique<drivers::lds::LdsLaser>(d.laser.lds, clock);
      laser_ = lds_.get();
      slots_.push_back({nav::Device::kLaser, "lds", d.laser.lds.port.string(), lds_.get()});
      break;
    case DeviceDriver::kNone: break;
    default: throw ConfigError(std::string("devices.laser.driver: ") + ToString(d.laser.driver) + " is not a laser");
  }
  switch (d.camera.driver) {
    case DeviceDriver::kDds: {
      dds_camera_ = std::make_unique<drivers::dds::DdsDepthCamera>(*participant_, d.camera.dds, clock);
      camera_ = dds_camera_.get();
      slots_.push_back({nav::Device::kCamera, "dds", d.camera.dds.depth_topic, nullptr});
      spdlog::info("dds: waiting for the camera's info on {} (domain {})", d.camera.dds.info_topic,
                   participant_->options().domain_id);
      dds_camera_->WaitForInfo(std::chrono::milliseconds(static_cast<long>(d.camera.info_wait_s * 1000.0)));
      const nav::PinholeCamera& k = dds_camera_->info().camera;
      spdlog::info("dds: camera {} x {} (fx {:.1f}), depth on {}", k.width, k.height, k.fx, d.camera.dds.depth_topic);
      break;
    }
    case DeviceDriver::kRealsense: {
      const drivers::realsense::RealSenseOptions& o = d.camera.realsense;
      realsense_ = std::make_unique<drivers::realsense::RealSenseCamera>(o, clock);
      camera_ = realsense_.get();
      slots_.push_back(
          {nav::Device::kCamera, "realsense", o.depth_node.empty() ? o.name : o.depth_node, realsense_.get()});
      break;
    }
    case DeviceDriver::kStereo: {
      const drivers::stereo::StereoCameraOptions& o = d.camera.stereo;
      stereo_ = std::make_unique<drivers::stereo::StereoCamera>(o, clock);
      camera_ = stereo_.get();
      slots_.push_back({nav::Device::kCamera, "stereo", drivers::stereo::Where(o), stereo_.get()});
      break;
    }
    case DeviceDriver::kOpenni2: {
      const drivers::openni2::OpenNi2Options& o = d.camera.openni2;
      openni2_ = std::make_unique<drivers::openni2::OpenNi2Camera>(o, clock);
      camera_ = openni2_.get();
      slots_.push_back({nav::Device::kCamera, "openni2", o.uri.empty() ? "any device" : o.uri, openni2_.get()});
      break;
    }
    case DeviceDriver::kNone: spdlog::info("device: no camera (the laser's lanes are the robot's sight)"); break;
    default: throw ConfigError(std::string("devices.camera.driver: ") + ToString(d.camera.driver) + " is not a camera");
  }
  if (d.camera.pan_driver == DeviceDriver::kDynamixel) {
    // The camera's pan servo: its link is the camera's too (a camera whose pose is unknown is no camera).
    dynamixel_pan_ = std::make_unique<drivers::dynamixel::DynamixelPanServo>(d.camera.pan, clock);
    pan_ = dynamixel_pan_.get();
    slots_.push_back({nav::Device::kCamera, "dynamixel pan servo", d.camera.pan.port.string(), dynamixel_pan_.get()});
  }
  for (const DeviceSlot& slot : slots_) spdlog::info("device: {}", Describe(slot));
}

RobotDevices::~RobotDevices() { Stop(); }

Devices RobotDevices::devices() const {
  Devices out{
      camera_,           *base_, laser_, sim_ ? sim_->robot.get() : nullptr, battery_, sim_ ? sim_->floors : nullptr,
      participant_.get()};
  out.slots = slots_;
  out.pan = pan_;
  return out;
}

void RobotDevices::Stop() {
  if (dds_camera_) dds_camera_->Stop();
  if (dds_laser_) dds_laser_->Stop();
  if (dds_base_) dds_base_->Stop();
  rplidar_.reset();
  hokuyo_.reset();
  lds_.reset();
  realsense_.reset();
  stereo_.reset();
  openni2_.reset();
  dynamixel_pan_.reset();
  create2_.reset();
  kobuki_.reset();
  turtlebot3_.reset();
  serial_text_.reset();
}

}  // namespace corridor::server
