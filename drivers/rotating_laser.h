// What the drivers of rotating lasers on a serial port (RPLIDAR, LDS) share: the mounting, the scan handler, the
// checks on the link's timings, and a session's reading loop once the device is sending, which turns the protocol's
// measurements into scans (SweepAssembler) and watches the link: no whole frame for stale_s is stale (the robot stops
// until frames flow again), for silence_s the session ends and the port is opened anew, so that a device plugged back
// in under the same path (udev's stable name) scans again by itself.
#pragma once

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <stop_token>
#include <string>
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
  // Streams `port` (Stream: on the driver's thread, or a pumping one) until `stop`, the port fails (throws), or no
  // frame has come for silence_s (the session ends); `first` is what came with the answer to the request that started
  // the scan. `note` runs under the status lock after each pass, for the driver's own counters.
  void ReadSweeps(SerialPort& port, std::stop_token stop, std::span<const std::uint8_t> first, const Decoder& decode,
                  const std::function<void(Status&)>& note) {
    SweepAssembler sweeps(sweep_);
    std::vector<SweepPoint> points;
    // Decodes `bytes`, which arrived from `from_ns` on at the line's pace (byte_ns each): a point is stamped when its
    // share of the bytes was in, a sweep when its last point was. Returns how many whole frames came.
    const auto take = [&](std::span<const std::uint8_t> bytes, TimeNs from_ns, TimeNs byte_ns) {
      points.clear();
      const std::uint64_t frames = decode(bytes, points);
      const auto n = static_cast<TimeNs>(bytes.size());
      const auto m = static_cast<TimeNs>(points.size());
      for (TimeNs i = 0; i < m; ++i) {
        std::optional<LaserScan> scan =
            sweeps.Add(points[static_cast<std::size_t>(i)], from_ns + n * (i + 1) / m * byte_ns);
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
    TimeNs read_ns = clock_.Now();  // the pass before: what this one brings arrived after it
    TimeNs last_frame_ns = read_ns;
    take(first, read_ns, 0);
    this->SetState(LinkState::kRunning);
    const TimeNs byte_ns = FromSeconds(port.byte_s());
    const TimeNs stale_ns = FromSeconds(link_.stale_s);
    const TimeNs silence_ns = FromSeconds(link_.silence_s);
    this->Stream(
        port, stop,
        [&] {
          // The driver's thread waits no longer than until the link would be stale.
          const TimeNs to_stale_ns = stale_ns - (clock_.Now() - last_frame_ns);
          return ToSeconds(to_stale_ns > 0 ? to_stale_ns : stale_ns);
        },
        [&](std::span<const std::uint8_t> bytes, bool waited) {
          const TimeNs now = clock_.Now();
          const auto line_ns = static_cast<TimeNs>(bytes.size()) * byte_ns;
          // Bytes that ended a wait came at most their line time ago; a pump's came after the pass before, each no
          // earlier than its place in the line after it. The last whole frame is counted from then, so that the link
          // is noticed stale stale_s after the device's last byte however long bytes gathered between pumps.
          const TimeNs from_ns = waited ? std::max(read_ns, now - line_ns) : read_ns;
          if (take(bytes, from_ns, byte_ns) > 0) {
            last_frame_ns = std::min(now, from_ns + line_ns);
            this->SetState(LinkState::kRunning);
          }
          read_ns = now;
          const TimeNs quiet_ns = now - last_frame_ns;
          if (quiet_ns >= silence_ns) {
            this->SetState(LinkState::kSilent,
                           fmt::format("no measurement for {:.1f} s: opening the port again", link_.silence_s));
            return false;
          }
          if (quiet_ns >= stale_ns) {
            this->SetState(LinkState::kStale, fmt::format("no measurement for {:.0f} ms", link_.stale_s * 1e3));
          }
          return true;
        });
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
  Link link_;
  nav::Pose2 base_T_laser_;
  double height_m_;
  SweepOptions sweep_;
  const Clock& clock_;
  ScanHandler handler_;  // under the status mutex
};

}  // namespace corridor::drivers
