#include "server/nodes/driver_bridge.h"

#include "server/runtime/topics.h"

namespace corridor::server {

void ConnectDrivers(Bus& bus, const drivers::Clock& clock, drivers::DepthCamera& camera, drivers::DiffDriveBase& base,
                    drivers::Laser2D* laser, drivers::Battery* battery) {
  auto& rgbd = bus.Get(topics::kRgbd);
  camera.SetFrameHandler([&rgbd, &clock](std::shared_ptr<drivers::RgbdFrame> frame) {
    frame->arrival_ns = clock.Now();
    rgbd.Publish(std::move(frame));
  });
  auto& odometry = bus.Get(topics::kOdometry);
  base.SetOdometryHandler([&odometry](const drivers::WheelOdometry& o) { odometry.Publish(o); });
  if (laser != nullptr) {
    auto& scan = bus.Get(topics::kScan);
    laser->SetScanHandler([&scan](std::shared_ptr<const drivers::LaserScan> s) { scan.Publish(std::move(s)); });
  }
  if (battery != nullptr) {
    auto& state = bus.Get(topics::kBattery);
    battery->SetBatteryHandler([&state](const drivers::BatteryState& b) { state.Publish(b); });
  }
}

}  // namespace corridor::server
