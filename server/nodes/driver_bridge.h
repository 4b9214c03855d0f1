// Connects device drivers to the bus: whatever a driver delivers on its own thread is published on its topic.
#pragma once

#include <string>
#include <vector>

#include "drivers/battery.h"
#include "drivers/depth_camera.h"
#include "drivers/diff_drive_base.h"
#include "drivers/laser2d.h"
#include "drivers/serial/link_state.h"
#include "nav/safety/command_gate.h"
#include "server/runtime/bus.h"

namespace corridor::server {

// One of the robot's devices as the daemon reports its health: its driver, where it is reached, and its link when the
// driver watches one (native drivers; null for the simulator and DDS).
struct DeviceSlot {
  nav::Device device = nav::Device::kBase;
  std::string driver;  // sim, dds, create2, rplidar
  std::string port;    // the serial device or the ROS 2 topic; empty for the simulator
  drivers::DeviceLink* link = nullptr;
};

// `camera`, `laser` and `battery` may be null (no camera or laser fitted, nothing reports the battery). The drivers
// must outlive the bus subscriptions' use of them. Frames are stamped with their arrival on `clock` (the host's), from
// which the control loop's latency is measured. Each slot's link, when it has one, reports its changes on
// devices/links.
void ConnectDrivers(Bus& bus, const drivers::Clock& clock, drivers::DepthCamera* camera, drivers::DiffDriveBase& base,
                    drivers::Laser2D* laser, drivers::Battery* battery, const std::vector<DeviceSlot>& slots);

// "laser (rplidar on /dev/ttyUSB0)": a slot as messages name it.
std::string Describe(const DeviceSlot& slot);

}  // namespace corridor::server
