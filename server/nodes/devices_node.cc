#include "server/nodes/devices_node.h"

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

constexpr double kReportHz = 4.0;

double StaleAfter(nav::Device device, const nav::CommandGateOptions& safety) {
  switch (device) {
    case nav::Device::kBase: return safety.odometry_timeout_s;
    case nav::Device::kLaser: return safety.laser_timeout_s;
    case nav::Device::kCamera: return safety.depth_timeout_s;
  }
  return 1.0;
}

nav::LinkView ViewOf(const drivers::DeviceLink* link, drivers::LinkStatus& status) {
  if (link == nullptr) return nav::LinkView::kNotWatched;
  status = link->link();
  switch (status.state) {
    case drivers::LinkState::kRunning: return nav::LinkView::kUp;
    case drivers::LinkState::kConnecting:
    case drivers::LinkState::kStale: return nav::LinkView::kStale;
    case drivers::LinkState::kSilent:
    case drivers::LinkState::kDisconnected: return nav::LinkView::kGone;
  }
  return nav::LinkView::kGone;
}

}  // namespace

DevicesNode::DevicesNode(Executor& io, Bus& bus, std::vector<DeviceSlot> slots, const nav::CommandGateOptions& safety)
    : PeriodicNode("devices", io, bus, kReportHz) {
  for (DeviceSlot& slot : slots) {
    const double stale_after = StaleAfter(slot.device, safety);
    devices_.push_back({std::move(slot), nav::DeviceWatch(stale_after)});
  }
}

void DevicesNode::Arrived(nav::Device device) {
  const double now_s = drivers::ToSeconds(clock().Now());
  for (Watched& d : devices_) {
    if (d.slot.device == device) d.watch.Arrived(now_s);
  }
}

void DevicesNode::Activate() {
  Subscribe(topics::kOdometry, "odometry", [this](const auto&) { Arrived(nav::Device::kBase); });
  Subscribe(topics::kScan, "scan", [this](const auto&) { Arrived(nav::Device::kLaser); });
  Subscribe(topics::kRgbd, "frame", [this](const auto&) { Arrived(nav::Device::kCamera); });
  PeriodicNode::Activate();
}

void DevicesNode::Tick() {
  const drivers::TimeNs now = clock().Now();
  const double now_s = drivers::ToSeconds(now);
  DevicesHealth health{now, {}};
  std::string worst;
  for (const Watched& d : devices_) {
    drivers::LinkStatus status;
    const nav::LinkView link = ViewOf(d.slot.link, status);
    DeviceReport r;
    r.device = nav::ToString(d.slot.device);
    r.driver = d.slot.driver;
    r.port = d.slot.port;
    r.state = d.watch.State(now_s, link);
    r.rate_hz = d.watch.RateHz(now_s);
    r.age_s = d.watch.AgeS(now_s);
    if (d.slot.link != nullptr) {
      r.link = drivers::ToString(status.state);
      r.reconnects = status.reconnects;
      r.last_error = status.last_error;
    }
    if (r.state != nav::DeviceState::kOk && worst.empty()) {
      worst = Describe(d.slot) + " " + nav::ToString(r.state);
    }
    health.devices.push_back(std::move(r));
  }
  bus().Get(topics::kDevices).Publish(std::move(health));
  if (worst.empty()) {
    SetHealth(Health::kOk, std::to_string(devices_.size()) + " devices");
  } else {
    SetHealth(Health::kDegraded, worst);
  }
}

}  // namespace corridor::server
