#include "server/nodes/driver_bridge.h"

#include "nav/geometry/pan_history.h"
#include "server/runtime/topics.h"

#include <time.h>

#include <mutex>
#include <optional>

namespace corridor::server {
namespace {

std::uint64_t ThreadCpuNs() {
  timespec t{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<std::uint64_t>(t.tv_sec) * 1'000'000'000u + static_cast<std::uint64_t>(t.tv_nsec);
}

// Runs `deliver`, timing one call in Handoff::kSampling to `handoff` (none: untimed).
template <typename Deliver>
void HandOff(Handoff* handoff, Deliver&& deliver) {
  if (handoff == nullptr || handoff->count.fetch_add(1, std::memory_order_relaxed) % Handoff::kSampling != 0) {
    deliver();
    return;
  }
  const std::uint64_t before = ThreadCpuNs();
  deliver();
  handoff->timed_ns.fetch_add(ThreadCpuNs() - before, std::memory_order_relaxed);
  handoff->timed.fetch_add(1, std::memory_order_relaxed);
}

Handoff* HandoffOf(const std::vector<DeviceSlot>& slots, nav::Device device) {
  for (const DeviceSlot& slot : slots) {
    if (slot.device == device) return slot.handoff.get();
  }
  return nullptr;
}

}  // namespace

double Handoff::cpu_s() const {
  const std::uint64_t n = timed.load(std::memory_order_relaxed);
  if (n == 0) return 0.0;
  return 1e-9 * static_cast<double>(timed_ns.load(std::memory_order_relaxed)) *
         static_cast<double>(count.load(std::memory_order_relaxed)) / static_cast<double>(n);
}

std::string Describe(const DeviceSlot& slot) {
  std::string text = std::string(nav::ToString(slot.device)) + " (" + slot.driver;
  if (!slot.port.empty()) text += " on " + slot.port;
  return text + ")";
}

void ConnectDrivers(Bus& bus, const drivers::Clock& clock, drivers::DepthCamera* camera, drivers::DiffDriveBase& base,
                    drivers::Laser2D* laser, drivers::Battery* battery, const std::vector<DeviceSlot>& slots,
                    bool camera_filtered, drivers::PanServo* pan) {
  // The pan servo's readings, shared by its thread (adding) and the camera's (looking up).
  struct PanTrack {
    std::mutex mutex;
    nav::PanHistory history;
  };
  std::shared_ptr<PanTrack> track;
  if (pan != nullptr && camera != nullptr) {
    track = std::make_shared<PanTrack>();
    auto& readings = bus.Get(topics::kCameraPan);
    pan->SetReadingHandler([track, &readings](const drivers::PanReading& r) {
      {
        std::lock_guard lock(track->mutex);
        track->history.Add(drivers::ToSeconds(r.stamp_ns), r.pan_rad, r.velocity_rps);
      }
      readings.Publish(r);
    });
    bus.Get(topics::kCameraPanTarget).Tap([pan](const double& target) { pan->SetTarget(target); });
  }
  if (camera != nullptr) {
    auto& rgbd = bus.Get(camera_filtered ? topics::kRgbdRaw : topics::kRgbd);
    camera->SetFrameHandler([&rgbd, &clock, handoff = HandoffOf(slots, nav::Device::kCamera), track,
                             axis = pan != nullptr ? pan->axis_xy() : Eigen::Vector2d::Zero().eval(),
                             mount = camera->info().camera.base_T_camera](std::shared_ptr<drivers::RgbdFrame> frame) {
      frame->arrival_ns = clock.Now();
      if (track) {
        std::optional<double> pan_rad;
        {
          std::lock_guard lock(track->mutex);
          pan_rad = track->history.At(drivers::ToSeconds(frame->stamp_ns));
        }
        if (!pan_rad) return;  // where the camera looked is not known
        frame->base_T_camera = nav::PanTurn(axis, *pan_rad) * mount;
      }
      HandOff(handoff, [&] { rgbd.Publish(std::move(frame)); });
    });
  }
  Handoff* base_handoff = HandoffOf(slots, nav::Device::kBase);
  auto& odometry = bus.Get(topics::kOdometry);
  base.SetOdometryHandler([&odometry, base_handoff](const drivers::WheelOdometry& o) {
    HandOff(base_handoff, [&] { odometry.Publish(o); });
  });
  if (laser != nullptr) {
    auto& scan = bus.Get(topics::kScan);
    laser->SetScanHandler(
        [&scan, handoff = HandoffOf(slots, nav::Device::kLaser)](std::shared_ptr<const drivers::LaserScan> s) {
          HandOff(handoff, [&] { scan.Publish(std::move(s)); });
        });
  }
  if (battery != nullptr) {
    auto& state = bus.Get(topics::kBattery);
    battery->SetBatteryHandler(
        [&state, base_handoff](const drivers::BatteryState& b) { HandOff(base_handoff, [&] { state.Publish(b); }); });
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
