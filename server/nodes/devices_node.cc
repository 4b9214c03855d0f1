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
    watches_->devices.push_back({std::move(slot), nav::DeviceWatch(stale_after)});
  }
}

void DevicesNode::Activate() {
  const auto tap = [this](auto topic, nav::Device device) {
    bus().Get(topic).Tap([watches = watches_, device, &clock = clock()](const auto&) {
      std::lock_guard lock(watches->mutex);
      const double now_s = drivers::ToSeconds(clock.Now());  // under the lock: a device's times never go back
      for (Watched& d : watches->devices) {
        if (d.slot.device == device) d.watch.Arrived(now_s);
      }
    });
  };
  tap(topics::kOdometry, nav::Device::kBase);
  tap(topics::kScan, nav::Device::kLaser);
  tap(topics::kRgbd, nav::Device::kCamera);
  PeriodicNode::Activate();
}

void DevicesNode::Tick() {
  // The drivers' links first, each under its driver's lock, then the watches under theirs.
  std::vector<drivers::LinkStatus> statuses(watches_->devices.size());
  std::vector<nav::LinkView> links;
  for (std::size_t i = 0; i < statuses.size(); ++i) {
    links.push_back(ViewOf(watches_->devices[i].slot.link, statuses[i]));
  }
  DevicesHealth health;
  std::string worst;
  {
    std::lock_guard lock(watches_->mutex);
    health.stamp_ns = clock().Now();  // under the lock: no arrival is counted after it
    const double now_s = drivers::ToSeconds(health.stamp_ns);
    for (std::size_t i = 0; i < statuses.size(); ++i) {
      const Watched& d = watches_->devices[i];
      DeviceReport r;
      r.device = nav::ToString(d.slot.device);
      r.driver = d.slot.driver;
      r.port = d.slot.port;
      r.state = d.watch.State(now_s, links[i]);
      r.rate_hz = d.watch.RateHz(now_s);
      r.age_s = d.watch.AgeS(now_s);
      r.handoff_cpu_s = d.slot.handoff->cpu_s();
      if (d.slot.link != nullptr) {
        r.link = drivers::ToString(statuses[i].state);
        r.reconnects = statuses[i].reconnects;
        r.last_error = statuses[i].last_error;
      }
      if (r.state != nav::DeviceState::kOk && worst.empty()) {
        worst = Describe(d.slot) + " " + nav::ToString(r.state);
      }
      health.devices.push_back(std::move(r));
    }
  }
  bus().Get(topics::kDevices).Publish(std::move(health));
  if (worst.empty()) {
    SetHealth(Health::kOk, std::to_string(watches_->devices.size()) + " devices");
  } else {
    SetHealth(Health::kDegraded, worst);
  }
}

}  // namespace corridor::server
