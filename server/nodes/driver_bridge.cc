#include "server/nodes/driver_bridge.h"

#include "server/runtime/topics.h"

namespace corridor::server {

std::string Describe(const DeviceSlot& slot) {
  std::string text = std::string(nav::ToString(slot.device)) + " (" + slot.driver;
  if (!slot.port.empty()) text += " on " + slot.port;
  return text + ")";
}

void ConnectDrivers(Bus& bus, const drivers::Clock& clock, drivers::DepthCamera* camera, drivers::DiffDriveBase& base,
                    drivers::Laser2D* laser, drivers::Battery* battery, const std::vector<DeviceSlot>& slots) {
  if (camera != nullptr) {
    auto& rgbd = bus.Get(topics::kRgbd);
    camera->SetFrameHandler([&rgbd, &clock](std::shared_ptr<drivers::RgbdFrame> frame) {
      frame->arrival_ns = clock.Now();
      rgbd.Publish(std::move(frame));
    });
  }
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
  auto& links = bus.Get(topics::kDeviceLinks);
  for (const DeviceSlot& slot : slots) {
    if (slot.link == nullptr) continue;
    auto report = [&links, &clock, device = slot.device, name = Describe(slot)](const drivers::LinkStatus& s) {
      const bool up = s.state == drivers::LinkState::kRunning;
      std::string detail = name + ": " + drivers::ToString(s.state);
      if (!up && !s.last_error.empty()) detail += ": " + s.last_error;
      links.Publish(DeviceLinkChange{clock.Now(), device, up, std::move(detail)});
    };
    slot.link->SetLinkHandler(report);
    report(slot.link->link());  // a change before the handler was set is not lost
  }
}

}  // namespace corridor::server
