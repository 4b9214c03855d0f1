// What the drivers of rotating lasers on a serial port (RPLIDAR, LDS) share: the mounting, the scan handler, the
// checks on the link's timings, and a session's reading loop once the device is sending, which turns the protocol's
// measurements into scans (SweepAssembler) and watches the link: no whole frame for stale_s is stale (the robot stops
// until frames flow again), for silence_s the session ends and the port is opened anew, so that a device plugged back
// in under the same path (udev's stable name) scans again by itself.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <stop_token>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <spdlog/fmt/fmt.h>

#include "drivers/laser2d.h"
#include "drivers/laser_sweep.h"
#include "drivers/serial/linked_device.h"
#include "drivers/serial/serial_port.h"

namespace corridor::drivers {

// `Status`: the driver's LinkStatus, with `scans` counting the revolutions handed on.
template <typename Status>
class RotatingLaser : public Laser2D, public LinkedDevice<Status> {
 public:
  nav::Pose2 base_T_laser() const override { return base_T_laser_; }
  double height_m() const override { return height_m_; }
  void SetScanHandler(ScanHandler handler) override {
    std::lock_guard lock(this->mutex_);
    handler_ = std::move(handler);
  }

 protected:
  struct Link {
    std::filesystem::path port;
    double stale_s = 0.0;
    double silence_s = 0.0;
    double reconnect_s = 0.0;
  };
  // Throws std::invalid_argument, naming `device`, for options that cannot work. `clock` stamps the scans (when a
  // revolution's last byte arrived) and must outlive the driver.
  RotatingLaser(std::string device, Link link, nav::Pose2 base_T_laser, double height_m, SweepOptions sweep,
                const Clock& clock)
      : LinkedDevice<Status>(device, link.port.string()),
        link_(std::move(link)),
        base_T_laser_(base_T_laser),
        height_m_(height_m),
        sweep_(sweep),
        clock_(clock) {
    if (link_.port.empty()) throw std::invalid_argument(device + ": no port given");
    if (!(link_.stale_s > 0.0) || !(link_.silence_s > link_.stale_s) || !(link_.reconnect_s > 0.0)) {
      throw std::invalid_argument(device +
                                  ": stale_s and reconnect_s must be positive, and silence_s longer than stale_s");
    }
    SweepAssembler check(sweep_);  // throws for bad sweep options here, not on the driver's thread
  }

  // Decodes the bytes a read brought, appending the measurements they complete; returns how many whole frames came
  // (bytes that are all noise are no sign of life).
  using Decoder = std::function<std::uint64_t(std::span<const std::uint8_t> bytes, std::vector<SweepPoint>& points)>;
  // Reads `port` until `stop`, the port fails (throws), or no frame has come for silence_s (the session ends);
  // `first` is what came with the answer to the request that started the scan. `note` runs under the status lock
  // after each read, for the driver's own counters.
  void ReadSweeps(SerialPort& port, std::stop_token stop, std::span<const std::uint8_t> first, const Decoder& decode,
                  const std::function<void(Status&)>& note) {
    SweepAssembler sweeps(sweep_);
    std::vector<SweepPoint> points;
    const auto take = [&](std::span<const std::uint8_t> bytes, TimeNs now) {
      points.clear();
      const std::uint64_t frames = decode(bytes, points);
      for (const SweepPoint& point : points) {
        std::optional<LaserScan> scan = sweeps.Add(point, now);
        if (!scan) continue;
        ScanHandler handler;
        {
          std::lock_guard lock(this->mutex_);
          ++this->status_.scans;
          handler = handler_;
        }
        if (handler) handler(std::make_shared<const LaserScan>(std::move(*scan)));
      }
      std::lock_guard lock(this->mutex_);
      note(this->status_);
      return frames;
    };
    TimeNs last_frame_ns = clock_.Now();
    take(first, last_frame_ns);
    this->SetState(LinkState::kRunning);
    std::array<std::uint8_t, 1024> buffer{};
    bool flowing = false;  // the last read brought bytes: the next finds more there without waiting on the port
    while (!stop.stop_requested()) {
      std::size_t n = flowing ? port.ReadArrived(buffer) : 0;
      if (n == 0) {
        // Waits no longer than until the link would be stale, so that gathering does not put off noticing it.
        const double to_stale_s = link_.stale_s - ToSeconds(clock_.Now() - last_frame_ns);
        n = port.Read(buffer, to_stale_s > 0.0 ? to_stale_s : link_.stale_s);
      }
      flowing = n > 0;
      const TimeNs now = clock_.Now();
      if (take(std::span<const std::uint8_t>(buffer.data(), n), now) > 0) {
        last_frame_ns = now;
        this->SetState(LinkState::kRunning);
      }
      const double quiet_s = ToSeconds(now - last_frame_ns);
      if (quiet_s >= link_.silence_s) {
        this->SetState(LinkState::kSilent,
                       fmt::format("no measurement for {:.1f} s: opening the port again", link_.silence_s));
        return;
      }
      if (quiet_s >= link_.stale_s) {
        this->SetState(LinkState::kStale, fmt::format("no measurement for {:.0f} ms", link_.stale_s * 1e3));
      }
      // A few bytes came (a USB adapter passes them on every millisecond or so): let more gather before the next
      // read, rather than wake a thousand times a second. A revolution is handed on at most kGather late, and the
      // link noticed stale at most kGather late (the last frame's time is when it was read).
      if (n > 0 && n < buffer.size() / 4) std::this_thread::sleep_for(kGather);
    }
  }

  // Runs `session` on an opened port until `stop`, opening it anew every reconnect_s after a session ends or fails.
  void RunPortSessions(std::stop_token stop, int baud_rate, const std::function<void(SerialPort&)>& session) {
    this->RunSessions(stop, link_.reconnect_s, [&] {
      this->SetState(LinkState::kConnecting);
      SerialPort port(link_.port, baud_rate);
      session(port);
    });
  }

  const Clock& clock() const { return clock_; }

 private:
  static constexpr std::chrono::milliseconds kGather{5};

  Link link_;
  nav::Pose2 base_T_laser_;
  double height_m_;
  SweepOptions sweep_;
  const Clock& clock_;
  ScanHandler handler_;  // under the status mutex
};

}  // namespace corridor::drivers
