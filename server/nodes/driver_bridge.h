// Connects device drivers to the bus: whatever a driver delivers on its own thread is published on its topic.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "drivers/battery.h"
#include "drivers/depth_camera.h"
#include "drivers/diff_drive_base.h"
#include "drivers/laser2d.h"
#include "drivers/pan_servo.h"
#include "drivers/serial/link_state.h"
#include "nav/safety/command_gate.h"
#include "server/runtime/bus.h"

namespace corridor::server {

// The CPU time a device's data took to be handed to the graph (the publication on its topic: the taps, and the
// wake-ups of the executors that take it), on whichever thread delivered it: the simulator's, a driver's, or the
// control loop pumping a native driver. One handoff in kSampling is timed (a thread's CPU clock is a system
// call); the total is estimated from them.
struct Handoff {
  static constexpr std::uint64_t kSampling = 8;
  std::atomic<std::uint64_t> count{0};     // handoffs
  std::atomic<std::uint64_t> timed{0};     // of them timed
  std::atomic<std::uint64_t> timed_ns{0};  // their CPU time
  double cpu_s() const;                    // the estimate for all of them
};

// One of the robot's devices as the daemon reports its health: its driver, where it is reached, its link when the
// driver watches one (native drivers; null for the simulator and DDS), and what handing its data on costs.
struct DeviceSlot {
  nav::Device device = nav::Device::kBase;
  std::string driver;  // sim, dds, create2, rplidar
  std::string port;    // the serial device or the ROS 2 topic; empty for the simulator
  drivers::DeviceLink* link = nullptr;
  std::shared_ptr<Handoff> handoff = std::make_shared<Handoff>();  // shared by the slot's copies
};

// `camera`, `laser` and `battery` may be null (no camera or laser fitted, nothing reports the battery). The drivers
// must outlive the bus subscriptions' use of them. Frames are stamped with their arrival on `clock` (the host's), from
// which the control loop's latency is measured. Each slot's link, when it has one, reports its changes on
// devices/links; each delivery is counted to its device's slot's Handoff (the battery's to the base's). The camera's
// frames go to camera/rgbd, or to camera/rgbd_raw when `camera_filtered` (the multi-view filter passes them on).
//
// With a pan servo (`pan`, may be null) the camera turns on the robot: its readings go to camera/pan, the gaze's
// targets on camera/pan_target go to it, and each frame is stamped with the camera's pose at its stamp (RgbdFrame's
// base_T_camera, from the readings about it: nav::PanHistory). A frame taken while the servo's angle is not known
// (its readings stopped) is not handed on, so that the camera's data goes stale and the robot stops.
void ConnectDrivers(Bus& bus, const drivers::Clock& clock, drivers::DepthCamera* camera, drivers::DiffDriveBase& base,
                    drivers::Laser2D* laser, drivers::Battery* battery, const std::vector<DeviceSlot>& slots,
                    bool camera_filtered = false, drivers::PanServo* pan = nullptr);

// "laser (rplidar on /dev/ttyUSB0)": a slot as messages name it.
std::string Describe(const DeviceSlot& slot);

}  // namespace corridor::server
