// Connects device drivers to the bus: whatever a driver delivers on its own thread is published on its topic.
#pragma once

#include "drivers/battery.h"
#include "drivers/depth_camera.h"
#include "drivers/diff_drive_base.h"
#include "drivers/laser2d.h"
#include "server/runtime/bus.h"

namespace corridor::server {

// `laser` and `battery` may be null (no laser fitted, nothing reports the battery). The drivers must outlive the bus subscriptions' use of them. Frames are
// stamped with their arrival on `clock` (the host's), from which the control loop's latency is measured.
void ConnectDrivers(Bus& bus, const drivers::Clock& clock, drivers::DepthCamera& camera, drivers::DiffDriveBase& base,
                    drivers::Laser2D* laser, drivers::Battery* battery);

}  // namespace corridor::server
